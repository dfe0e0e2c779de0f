#pragma once
// The highway options both front ends read (--fcd replays and SUMO runs), parsed and worded once.
#include <sthighway/monitor.hpp>
#include <stsim/cli.hpp>

namespace st::cli {

// --detector, --broadphase, --layout, --motion, --rear-end-below, --crossing-above and --set into
// cfg, over what it holds (the defaults, or a scenario's settings); an option not given leaves its
// key as it is. Throws UsageError naming the option.
void applyMonitorOptions(const Args& a, highway::MonitorConfig& cfg);

// --penetration, checked to lie in [0, 1]. Throws UsageError.
double penetrationOption(const Args& a);
// --end, positive (s); --seed in [0, 2^31 - 1]. The same words for replays and SUMO runs. Throw UsageError.
double endOption(const Args& a);
long seedOption(const Args& a);

}  // namespace st::cli
