#pragma once
// The pool scenario's settings, each named once with its type, unit, range, default and one line
// of doc (stio/settings_table.hpp's core, as the arm's starm/settings.hpp). Every front end sets
// them through this table: the scenario YAML (the nested keys, "space.cell_size", are the
// reference names), stsim pool's --set KEY=VALUE and the options that stand for one key (--space,
// --df), and validateScenario for a scenario built in code. A value is checked and its error
// worded once, whichever front end read it; the defaults are the structs' (Scenario, TableSpec,
// SpaceSpec). docs/pool_settings.md is settingsReferenceMarkdown().
#include <span>
#include <string>
#include <string_view>

#include <stio/settings_table.hpp>

namespace st::pool {

struct Scenario;

using namespace io::setting_names;
using Setting = io::Setting<Scenario>;


// Every setting, in the order the reference lists them.
std::span<const Setting> poolSettings();
// The setting named key; null if none.
const Setting* findSetting(std::string_view key);
// Checks text (a command-line value or a YAML scalar alike) for s and stores it; throws SettingError.
void applySettingText(Scenario& sc, const Setting& s, std::string_view text);
// Every value in its range (for a scenario built in code); throws SettingError naming the key.
void checkSettings(const Scenario& sc);
// Whether key applies to sc's space kind: a quadtree's (space.decomposition_factor, divisions,
// max_depth) and cells' keys (space.cell_size, margin) to that kind only, every other key always.
bool keyForKind(const Scenario& sc, std::string_view key);
// A space key of another kind than sc's: taken, it would do nothing, so it is refused, naming the
// kind it is for. Throws SettingError.
void checkKeyForKind(const Scenario& sc, std::string_view key);

// The reference: one Markdown table row per setting (key, values, its value in `values` under the
// heading `column`, doc); by default the defaults.
std::string settingsReferenceMarkdown(const Scenario* values = nullptr, const char* column = "default");

}  // namespace st::pool
