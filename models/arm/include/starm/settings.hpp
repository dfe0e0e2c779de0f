#pragma once
// The arm scenario's settings, each named once with its type, unit, range, default and one line of
// doc (as sthighway/settings.hpp is the highway monitor's). Every front end sets them through this
// table: the scenario YAML (the nested keys, "safety.cycle_time", are the reference names), stsim
// arm's --set KEY=VALUE (and the options that stand for one key), the stopping study and the stream
// client's braking defaults. applySettingText checks a value and words its error once, whichever
// front end read it; the defaults are the structs' (SafetyConfig, BrakeConfig, BroadphaseConfig,
// SsmConfig), and a key that follows another (braking.delay follows safety.reaction_time) takes
// that key's value unless it is given itself. docs/arm_settings.md is settingsReferenceMarkdown().
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <stio/settings_table.hpp>

namespace st::arm {

struct Scenario;

using io::SettingType;
using io::SettingValue;
using io::SettingError;
using io::SettingOverride;
using io::expected;
using io::valuesText;
using io::settingText;

// A key of the table (stio/settings_table.hpp: key, type, unit, range, words, doc, set, get), and
// the key whose value is the default of this one, or "".
struct Setting : io::Setting<Scenario> {
  const char* follows;
};


// Every setting, in the order the reference lists them.
std::span<const Setting> armSettings();
// The setting named key; null if none.
const Setting* findSetting(std::string_view key);
// The default of a key as text (a scenario with no settings given), for an option's default.
std::string defaultText(std::string_view key);

// Checks v against s (type, range, word) and stores it; throws SettingError.
void applySetting(Scenario& s, const Setting& setting, const SettingValue& v);
// The same from text, a command-line value or a YAML scalar alike: a number, true/false or a word.
void applySettingText(Scenario& s, const Setting& setting, std::string_view text);
// Every key that follows another and is not given takes that key's value.
void followDefaults(Scenario& s, const std::function<bool(std::string_view key)>& given = {});
// What no single key can check: the horizon against the safe time, the look-ahead's bound.
// Throws SettingError naming the key to change.
void checkSettings(const Scenario& s);

// The reference: one Markdown table row per setting (key, values, its value in `values` under the
// heading `column`, doc); by default the defaults.
std::string settingsReferenceMarkdown(const Scenario* values = nullptr, const char* column = "default");

}  // namespace st::arm
