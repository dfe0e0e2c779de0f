#pragma once
// The cosim scenario's own settings (seed, end, action, brake, SUMO's collision options ...), each
// named once with its type, unit, range and doc, as sthighway/settings.hpp names the monitor's.
// Both front ends read them through this table with one range and one wording: the scenario YAML
// (its top-level keys, and brake.*) and stsim highway's options (--end, --seed, --penetration,
// --action, --scale, --validate-ssm, and --set KEY=VALUE for any of them). The keys a table cannot
// hold (sumocfg, description, smart_types, incidents, sumo_args, out: paths and lists) are read by
// the YAML reader alone. docs/scenario_settings.md is scenarioSettingsMarkdown().
#include <span>
#include <string>
#include <string_view>

#include <stio/settings_table.hpp>

namespace st::cosim {

struct Scenario;

using ScenarioSetting = io::Setting<Scenario>;

// Every setting, in the order the reference lists them.
std::span<const ScenarioSetting> scenarioSettings();
// The setting named key; null if none.
const ScenarioSetting* findScenarioSetting(std::string_view key);
// Text as the key's type (a YAML scalar, a command-line value), checked and stored; throws
// io::SettingError.
void applyScenarioSettingText(Scenario& s, const ScenarioSetting& setting, std::string_view text);
// What no single key can check: brake.max_deceleration against brake.deceleration. Throws
// io::SettingError naming the key to change.
void checkScenarioSettings(const Scenario& s);
// The reference: one Markdown table row per setting, its value in `values` under `column`.
std::string scenarioSettingsMarkdown(const Scenario& values, const char* column = "default");
// The same with a default Scenario's values.
std::string scenarioSettingsMarkdown();

}  // namespace st::cosim
