#pragma once
// The highway options both front ends read (--fcd replays and SUMO runs), parsed and worded once:
// each option that stands for a key, and --set KEY=VALUE, is checked by the key's table (the
// monitor's, sthighway/settings.hpp; the scenario's, stcosim/scenario_settings.hpp).
#include <optional>
#include <vector>

#include <sthighway/monitor.hpp>
#include <stio/settings_table.hpp>
#include <stsim/cli.hpp>

namespace st::cli {

// The settings the command line gives: the options that stand for one key (--detector, --end,
// --seed, --action, ...), --validate-ssm, and --set for any key of the monitor's table or the
// scenario's (without SUMO support: the keys a replay reads). An unknown key or one given twice
// throws UsageError.
std::vector<io::SettingOverride> highwayOverrides(const Args& a);

// The monitor's keys among them into cfg, over what it holds (the defaults, or a scenario's),
// then checkSettings. Throws UsageError naming the option.
void applyMonitorOptions(const std::vector<io::SettingOverride>& overrides, highway::MonitorConfig& cfg);

// What a replay (--fcd) reads of the run's settings; a key only a SUMO run has is a UsageError.
struct ReplaySettings {
  double penetration = 1.0;
  long seed = 42;               // a replay's draw (a SUMO run takes the scenario's when not given)
  std::optional<double> end;    // none: to the trace's last frame
};
ReplaySettings replaySettings(const std::vector<io::SettingOverride>& overrides);

}  // namespace st::cli
