#pragma once
// The settings a replay (stsim highway --fcd) and a SUMO run share: their specs (type, unit, range,
// doc; stio/settings_table.hpp), so both read them with one range and one wording. The cosim
// scenario's table (stcosim/scenario_settings.hpp) stores them in its Scenario; a replay reads
// them from its options.
#include <stio/settings_table.hpp>

namespace st::highway {

// the longest run: 1e9 s, as a trace's times are bounded (sumo_files.hpp)
inline constexpr io::SettingSpec kSeedSetting{
    "seed", io::SettingType::Integer, "", 0.0, 2147483647.0, false, "", "",
    "seed of the equipped-vehicle draw and of SUMO (a .sumocfg without a scenario: its own)", true};
inline constexpr io::SettingSpec kEndSetting{
    "end", io::SettingType::Number, "s", 0.0, 1e9, true, "sumocfg", "",
    "stop at this simulated time; sumocfg: the sumocfg's end (a replay: the trace's last frame)", true};
inline constexpr io::SettingSpec kPenetrationSetting{
    "penetration", io::SettingType::Number, "", 0.0, 1.0, false, "", "",
    "fraction of vehicles equipped with the smart-car system (a draw by seed and vehicle id)", true};

}  // namespace st::highway
