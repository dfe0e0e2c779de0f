#pragma once
// The highway options both front ends read (--fcd replays and SUMO runs), parsed and worded once.
#include <sthighway/monitor.hpp>
#include <stsim/cli.hpp>

namespace st::cli {

// --detector, --broadphase, --layout, --motion, --rear-end-below, --crossing-above into cfg. With givenOnly, options not on the command
// line leave cfg as it is (a scenario's settings); otherwise their defaults apply. Throws UsageError.
void applyMonitorOptions(const Args& a, highway::MonitorConfig& cfg, bool givenOnly);

// --penetration, checked to lie in [0, 1]. Throws UsageError.
double penetrationOption(const Args& a);
// --end, positive (s); --seed in [0, 2^31 - 1]. The same words for replays and SUMO runs. Throw UsageError.
double endOption(const Args& a);
long seedOption(const Args& a);

}  // namespace st::cli
