#include "run_parts.hpp"

#include <algorithm>

namespace st::cosim {

namespace fs = std::filesystem;
namespace hw = st::highway;
using Clock = std::chrono::steady_clock;

namespace {
hw::RunInfo baseInfo(const Scenario& s, const RunSetup& setup) {
  hw::RunInfo info;
  info.source = s.source.string();
  info.detector = hw::toString(s.plugin.monitor.detector.kind);
  info.broadphase = hw::toString(s.plugin.monitor.broadphase);
  info.prediction = hw::toString(s.plugin.monitor.prediction);
  info.wallSeconds = std::chrono::duration<double>(Clock::now() - setup.wallStart).count();
  return info;
}

// the collisions (contacts: the bodies touch; leads holds one per contact) and their warning lead times: counts, mean and least, recall as hindsight counts it
void addCollisionFigures(hw::RunInfo& info, const Scenario& s, const PluginCounters& pc,
                         const std::vector<CollisionWarning>& leads) {
  info.numbers.push_back({"sumo_collisions", static_cast<double>(pc.collisions)});
  info.numbers.push_back({"sumo_collision_steps", static_cast<double>(pc.collisionSteps)});
  info.numbers.push_back({"contacts", static_cast<double>(pc.contacts)});
  info.numbers.push_back({"mingap_violations", static_cast<double>(pc.mingapViolations)});
  double warned = 0.0, sum = 0.0, least = 0.0;
  for (const CollisionWarning& w : leads)
    if (w.leadTime) {
      least = warned == 0.0 ? *w.leadTime : std::min(least, *w.leadTime);
      warned += 1.0;
      sum += *w.leadTime;
    }
  info.numbers.push_back({"collisions_warned", warned});
  if (warned > 0.0) {
    info.numbers.push_back({"collision_lead_time_mean_s", sum / warned});
    info.numbers.push_back({"collision_lead_time_min_s", least});
  }
  // recall as hindsight counts it for near misses: warned at least its lead time before
  std::vector<double> ahead;
  for (const CollisionWarning& w : leads)
    if (w.leadTime && *w.leadTime >= s.plugin.monitor.hindsight.lead) ahead.push_back(*w.leadTime);
  info.rawJson.push_back({"collisions", hw::eventRecallJson(leads.size(), ahead.size(), ahead)});
}
}  // namespace

void writeStartFailureSummary(const Scenario& s, const RunSetup& setup, const std::string& error) {
  hw::RunInfo info = baseInfo(s, setup);
  info.strings = {{"sumocfg", s.sumocfg.string()}, {"stop_reason", "error"}, {"error", error}};
  hw::writeSummaryJson(setup.out / "summary.json", hw::MonitorCounters{}, info);
}

hw::RunInfo writeSummary(const Scenario& s, const RunSetup& setup, const SummaryFacts& f,
                         const hw::MonitorCounters& counters) {
  const PluginCounters& pc = *f.plugin;
  const LoopOutcome& loop = *f.loop;
  hw::RunInfo info = baseInfo(s, setup);
  info.hindsight = s.plugin.monitor.hindsight;
  info.conflict = s.plugin.monitor.conflict;
  info.simulatedSeconds = f.simEnd;
  info.numbers = {{"sumo_seconds", loop.sumoSeconds},
                  {"stsim_seconds", loop.stsimSeconds},
                  {"validation_seconds", loop.validationSeconds},
                  {"steps", static_cast<double>(pc.steps)},
                  {"step_length_s", f.deltaT},
                  {"seed", static_cast<double>(s.seed)},
                  {"penetration", s.plugin.smart.penetration},
                  {"equipped_vehicles", static_cast<double>(pc.equipped)},
                  {"departed", static_cast<double>(pc.departed)},
                  {"arrived", static_cast<double>(pc.arrived)},
                  {"teleports", static_cast<double>(pc.teleports)},
                  {"color_changes", static_cast<double>(pc.colorChanges)},
                  {"brake_commands", static_cast<double>(pc.brakeCommands)},
                  {"incidents", static_cast<double>(pc.incidents)},
                  {"cell_polygons", static_cast<double>(f.cellPolygons)}};
  if (f.leads) addCollisionFigures(info, s, pc, *f.leads);
  info.strings = {{"sumocfg", s.sumocfg.string()},
                  {"net", f.net},
                  {"backend", f.backend},
                  {"action", toString(s.plugin.actions.action)},
                  {"stop_reason", loop.stopReason}};
  if (!f.leads)
    info.strings.emplace_back("sumo_collisions", "unknown: attached to a SUMO started elsewhere, which stsim cannot ask "
                                                 "for --collision-output (libtraci 1.15 has no getCollisions)");
  if (!loop.error.empty()) info.strings.emplace_back("error", loop.error);
  hw::writeSummaryJson(setup.out / "summary.json", counters, info);
  return info;
}

}  // namespace st::cosim
