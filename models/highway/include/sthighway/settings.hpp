#pragma once
// The monitor's settings (MonitorConfig), each named once with its type, unit, range and one line
// of doc. Every front end sets MonitorConfig through this table: the YAML scenario (the nested
// keys, "safe_time.vehicle_reaction", are the reference names), stsim highway's options (--set
// KEY=VALUE for any of them, and short options for the common ones) and Python's
// Monitor(**settings) (the same key with '.' spelt '_', or nested dicts). applySetting checks a
// value and words its error once, whichever front end read it; the defaults are MonitorConfig's.
#include <span>
#include <string>
#include <string_view>

#include <sthighway/monitor.hpp>
#include <stio/settings_table.hpp>

namespace st::highway {

// The core every settings table shares (stio/settings_table.hpp): a key's type, unit, range,
// words and doc, how a value is read and checked, and the words of its error ("KEY PROBLEM":
// "safe_time.vehicle_reaction must be in [0, 60] s, got 99"; problem() without the key).
using namespace io::setting_names;
using Setting = io::Setting<MonitorConfig>;

// Every setting, in the order the reference lists them.
std::span<const Setting> monitorSettings();
// The setting named key (the nested name, or its flat spelling with '_' for '.'); null if none.
const Setting* findSetting(std::string_view key);
// "safe_time.vehicle_reaction" -> "safe_time_vehicle_reaction"
std::string flatName(std::string_view key);

// Checks v against s (type, finite, range, choice) and stores it; throws SettingError.
void applySetting(MonitorConfig& cfg, const Setting& s, const SettingValue& v);
// The same from text (a command-line value, a YAML scalar): a number, true/false or a choice.
void applySettingText(MonitorConfig& cfg, const Setting& s, std::string_view text);
// Every value in its range, and what no single setting can check: conflict.rear_end_below <= conflict.crossing_above, a
// five-circle layout that covers the car. Throws SettingError naming the key to change.
void checkSettings(const MonitorConfig& cfg);

// The reference: one Markdown table row per setting (key, type and range, its value in `values`
// under the heading `column`, doc).
std::string settingsReferenceMarkdown(const MonitorConfig& values = MonitorConfig{}, const char* column = "default");

}  // namespace st::highway
