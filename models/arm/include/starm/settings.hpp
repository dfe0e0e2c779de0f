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

namespace st::arm {

struct Scenario;

enum class SettingType { Number, Integer, Boolean, Choice };

// A value as read: a number, a bool, or a word (a choice; "never", "auto" or "scene" for the
// numbers that take one).
using SettingValue = std::variant<double, bool, std::string>;

struct Setting {
  const char* key;   // the YAML's nested name, e.g. "safety.cycle_time"
  SettingType type;
  const char* unit;  // "s", "m", "m/s", "kg", "rad/s^2" or "" (none)
  double min;        // Number, Integer: the range, inclusive of max
  double max;
  bool aboveMin;     // the range excludes min: (min, max]
  const char* words; // Choice: "stop|scaling|pfl"; Number, Integer: a word taken instead ("never"), or ""
  const char* maxWhy;   // what the upper bound is ("the 60 s look-ahead limit"), worded in its error; or ""
  const char* follows;  // the key whose value is the default of this one, or ""
  const char* doc;
  void (*set)(Scenario&, const SettingValue&);  // stores a value applySetting checked
  SettingValue (*get)(const Scenario&);         // the value it holds
};

// The error of a bad value: what() is "KEY PROBLEM"; problem() without the key, for the front
// ends that name the key their own way ("file:line: KEY: PROBLEM", "--set KEY: PROBLEM").
class SettingError : public std::invalid_argument {
 public:
  SettingError(std::string key, std::string problem)
      : std::invalid_argument(key + " " + problem), key_(std::move(key)), problem_(std::move(problem)) {}
  const std::string& key() const { return key_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string key_, problem_;
};

// A value given on the command line for a key, as text (stsim arm --set KEY=VALUE).
struct SettingOverride {
  std::string key;
  std::string text;
  std::string option;  // how the front end names it: "--set safety.cycle_time", "--response"
};

// Every setting, in the order the reference lists them.
std::span<const Setting> armSettings();
// The setting named key; null if none.
const Setting* findSetting(std::string_view key);
// What a value of s must be, for a type error: "a number", "a number or never", "one of a, b".
std::string expected(const Setting& s);
// The values s takes, as the reference gives them: "number in (0, 60] s", "one of a, b".
std::string valuesText(const Setting& s);
// A value as the YAML would write it: 0.5, true, never.
std::string settingText(const SettingValue& v);
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
