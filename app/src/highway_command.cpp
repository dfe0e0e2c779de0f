// stsim highway: smart-car warnings on a recorded SUMO trace (--fcd + --net), or on a live SUMO
// scenario (SCENARIO.yaml / .sumocfg) through the co-simulation when it is built in.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <utility>

#include <sthighway/conflict_map.hpp>
#include <sthighway/monitor.hpp>
#include <sthighway/settings.hpp>
#include <sthighway/report.hpp>
#include <sthighway/run_driver.hpp>
#include <sthighway/run_settings.hpp>
#include <sthighway/sumo_files.hpp>
#include <stsim/cli.hpp>
#include <stsim/commands.hpp>

#include "highway_options.hpp"
#include "setting_options.hpp"

#ifdef STSIM_HAVE_COSIM
#include <stcosim/scenario.hpp>
#include <stcosim/scenario_settings.hpp>

#include "highway_run.hpp"
#define STSIM_HIGHWAY_COSIM 1
#endif

namespace st::cli {

namespace {

namespace hw = st::highway;

// The default of a monitor setting, as the help shows it.
std::string settingDefault(const char* key) {
  return hw::settingText(hw::findSetting(key)->get(hw::MonitorConfig{}));
}

// the options that stand for one key: the monitor's, then the run's (the scenario's table)
const std::vector<KeyOption> kMonitorOptions = {
    {"detector", "detector"},     {"layout", "layout"},         {"motion", "motion"},
    {"broadphase", "broadphase"}, {"prediction", "prediction"}, {"rear-end-below", "conflict.rear_end_below"},
    {"crossing-above", "conflict.crossing_above"}};
const std::vector<KeyOption> kRunOptions = {
    {"penetration", "penetration"}, {"action", "action"}, {"end", "end"}, {"scale", "demand_scale"}, {"seed", "seed"}};

// A key of the monitor's table or the scenario's; without SUMO support, of the monitor's or the
// three a replay reads.
const io::SettingSpec* findHighwaySetting(std::string_view key) {
  if (const hw::Setting* s = hw::findSetting(key)) return s;
#ifdef STSIM_HIGHWAY_COSIM
  return st::cosim::findScenarioSetting(key);
#else
  for (const io::SettingSpec* s : {&hw::kSeedSetting, &hw::kEndSetting, &hw::kPenetrationSetting})
    if (key == s->key) return s;
  return nullptr;
#endif
}

// An option's help from its key's row: what it sets, its values, the key.
std::string runOptionHelp(const char* key, const char* fallback) {
  const io::SettingSpec* s = findHighwaySetting(key);
  if (!s) return fallback;
  return std::string(s->doc) + "; " + io::valuesText(*s) + " (scenario " + key + ")";
}
std::string runOptionDefault(const char* key) {
#ifdef STSIM_HIGHWAY_COSIM
  return io::settingText(st::cosim::findScenarioSetting(key)->get(st::cosim::Scenario{}));
#else
  return std::string(key) == "penetration" ? "1" : "";
#endif
}

Args makeArgs() {
  Args a("highway",
         "Smart-car collision warnings (report section 4): concentric, five-circle or exact box detector,\n"
         "safe time growing with momentum, cells with handoff. Either replay a SUMO trace\n"
         "(--fcd TRACE.xml --net NET.net.xml) or run a SCENARIO with SUMO (yaml or .sumocfg).");
  a.positional("SCENARIO", "scenario YAML or SUMO .sumocfg (live co-simulation; needs SUMO support)", false)
      .option("fcd", "TRACE.xml", "SUMO floating-car-data trace to replay (sumo --fcd-output)")
      .option("net", "NET.net.xml", "SUMO network giving lane shapes and widths (with --fcd)")
      .option("vtypes", "FILE.xml", "route/additional file whose <vType>s give sizes and masses (with --fcd)")
      .option("tls-states", "FILE.xml", "SUMO's SaveTLSStates output of the traced run: the lights' states (with --fcd)")
      .option("routes", "FILE.xml", "the traced vehicles' routes: SUMO's --vehroute-output of the run, or a route file (with --fcd)")
      .option("detector", "concentric|five|box", "collision detector", settingDefault("detector"))
      .option("layout", "a|b", "five-circle zone layout: Fig. 11(a) small or 11(b) large overlaps", settingDefault("layout"))
      .option("motion", "velocity|acceleration", "prediction: constant velocity, or constant acceleration", settingDefault("motion"))
      .option("broadphase", "cells|all-pairs", "neighbour search", settingDefault("broadphase"))
      .option("prediction", "road|straight", "motion along the lanes (lane-frame road checks), or straight lines", settingDefault("prediction"))
      .option("set", "KEY=VALUE[,...]", "any setting by its scenario key, e.g. safe_time.vehicle_reaction=1.2 or end=60 (--settings and --scenario-settings list them)")
      .flag("settings", "print every monitor setting (key, range, default, what it sets) and exit")
      .option("out", "DIR", "output directory (default: the scenario's out:, out/<config name>/ for a .sumocfg, . for --fcd)", ".")
      .option("penetration", "P", runOptionHelp("penetration", ""), runOptionDefault("penetration"))
      .option("action", "none|color|brake", runOptionHelp("action", "action on a warning (SUMO runs)"), runOptionDefault("action"))
      .option("traci", "HOST:PORT", "attach to a running SUMO through TraCI instead of embedding libsumo")
      .flag("gui", "run sumo-gui and draw the cells (SUMO runs)")
      .option("end", "SECONDS", runOptionHelp("end", ""))
      .option("threads", "1|2", "2: detection beside SUMO's next step (--action none or color); default 2 when it can, else 1")
      .option("scale", "FACTOR", runOptionHelp("demand_scale", "multiply the routes' demand (SUMO --scale; SUMO runs)"))
      .option("seed", "N", runOptionHelp("seed", "") + "; default: the scenario's, 42")
      .flag("validate-ssm", "compare with SUMO's SSM device, writes validation.json (SUMO runs; scenario validate_ssm)")
      .flag("scenario-settings", "print every scenario setting besides the monitor's (key, range, default) and exit")
      .flag("trajectories", "also write trajectories.csv: each episode's TTC and DRAC at every tick (as SSM's trajectories)")
      .option("rear-end-below", "DEG", "conflict type: rear-end below this heading angle (scenario conflict.rear_end_below)", settingDefault("conflict.rear_end_below"))
      .option("crossing-above", "DEG", "conflict type: crossing above this angle, lane change between (conflict.crossing_above)", settingDefault("conflict.crossing_above"))
      .flag("no-map", "do not draw the conflict map (conflict_map.png / .svg)");
  return a;
}

// A replay's summary line and its conflict map's outcome.
void reportTrace(const Args& a, const hw::MonitorCounters& c, const hw::DriveResult& result, double maxTtc) {
  const std::filesystem::path out = a.get("out");
  std::uint64_t total = 0;
  for (auto n : c.warningsByKind) total += n;
  std::cout << "highway: " << c.vehiclesSeen << " vehicles, "
            << (c.personsSeen ? std::to_string(c.personsSeen) + " persons on foot, " : std::string())
            << c.vehicleMeters / 1000.0 << " vehicle-km, " << total
            << " warnings (vehicle " << c.warningsByKind[0] << ", curb " << c.warningsByKind[1] << ", lane_marker "
            << c.warningsByKind[2] << ", hazard " << c.warningsByKind[3] << "; " << hw::conflictTypeBreakdown(c) << "), "
            << hw::conflictCountText(c) << " conflicts (one per pair and encounter, TTC <= " << maxTtc
            << " s: conflicts.csv), " << c.handoffs << " handoffs, " << result.info.wallSeconds << " s wall; wrote "
            << (out / "warnings.csv").string() << ", " << (out / "conflicts.csv").string() << " and " << (out / "summary.json").string() << "\n";
  if (!result.map) return;
  const hw::ConflictMapOutcome& map = *result.map;
  using State = hw::ConflictMapOutcome::State;
  if (map.state == State::Drawn) std::cout << "  conflict map: " << (out / "conflict_map.png").string() << " (and .svg)\n";
  // a map that could not be written (a full disk) fails the run as any output does; a missing tool does not
  if (map.state == State::Failed) throw std::runtime_error((out / "conflict_map.png").string() + ": " + map.why);
  if (map.state == State::Unavailable) std::cerr << "stsim highway: no conflict map: " << map.why << "\n";
}

// What a replay reads besides the trace: the network, the lights' recorded states, the vehicle
// types (and routes, read once the trace is open); filled in place (the states refer to the links).
struct TraceInputs {
  hw::RoadGeometry road;
  std::optional<hw::SignalLinks> signalLinks;
  std::optional<hw::SignalStates> signalStates;
  hw::FcdChecks checks;
  hw::VehicleTypes types;
  hw::VehicleRoutes routes;
};

void readTraceInputs(const Args& a, bool priorityRules, TraceInputs& in) {
  std::vector<std::string> leftOut;
  int lights = 0;
  in.road = hw::readSumoNet(a.get("net"), &leftOut, &lights);
  // a trace carries no light states: said once, as the junction results depend on it, unless
  // SUMO's recorded states come with it
  if (lights > 0 && !a.has("tls-states"))
    std::cerr << "stsim highway: note: " << a.get("net") << " has " << lights
              << " traffic light(s); an FCD trace carries no light states, so cars are predicted through red lights "
                 "(a live run reads them; give SUMO's SaveTLSStates output with --tls-states)\n";
  if (a.has("tls-states")) {
    in.signalLinks.emplace(hw::readSignalLinks(a.get("net"), priorityRules));
    in.signalStates.emplace(a.get("tls-states"), *in.signalLinks);
  } else if (priorityRules) {
    // the priority rules need no recorded state: where a car gives way is in the network
    hw::SignalLinks links = hw::readSignalLinks(a.get("net"), true);
    const bool yields = !links.waitLength.empty() ||
                        std::any_of(links.byEdges.begin(), links.byEdges.end(), [](const auto& l) { return l.second.light < 0; });
    if (yields) {
      in.signalLinks.emplace(std::move(links));
      in.signalStates.emplace(*in.signalLinks);
    }
  }
  // the trace is checked against the network (bounds, lanes) and, with --vtypes, its types
  in.checks = hw::fcdChecksFor(in.road, leftOut, a.get("net"));
  if (a.has("vtypes")) {
    in.types = hw::readSumoVehicleTypes(a.get("vtypes"));
    if (in.types.empty()) throw hw::InputError(a.get("vtypes") + ": defines no <vType> (--vtypes wants a route or additional file)");
    in.checks.typesComplete = true;
    in.checks.typesFile = a.get("vtypes");
  }
}

int runTrace(const Args& a) {
  for (const char* opt : {"traci", "gui", "threads"})
    if (a.has(opt)) throw UsageError(std::string("--") + opt + " applies to SUMO runs (SCENARIO), not to --fcd");
  if (!a.has("net")) throw UsageError("--fcd needs --net NET.net.xml for the lane geometry");
  hw::MonitorConfig cfg;
  const std::vector<io::SettingOverride> overrides = highwayOverrides(a);
  applyMonitorOptions(overrides, cfg);
  // checked as for a SUMO run (-1 was taken: no frame, exit 0; a seed outside the draw's range)
  const ReplaySettings run = replaySettings(overrides);

  hw::DriveSetup setup;
  setup.out = a.get("out");
  setup.trajectories = a.has("trajectories");
  setup.end = run.end;
  setup.penetration = run.penetration;
  setup.seed = static_cast<std::uint64_t>(run.seed);
  setup.source = a.get("fcd");
  setup.net = a.get("net");
  if (!a.has("no-map")) setup.map = "stsim highway";
  TraceInputs in;
  readTraceInputs(a, cfg.priorityRules, in);
  hw::HighwayMonitor monitor(in.road, cfg);
  // the source: the trace's frames, with the lights' recorded states and the routes
  hw::FcdReader reader(a.get("fcd"), in.types, in.checks, &in.road);
  if (in.signalStates) reader.useSignals(&*in.signalLinks, &*in.signalStates, a.has("tls-states"));
  if (a.has("routes")) {
    in.routes = hw::readSumoRoutes(a.get("routes"));
    reader.useRoutes(&in.routes);
  }
  const hw::DriveResult result = hw::driveRun(reader, monitor, setup);
  reportTrace(a, monitor.counters(), result, cfg.conflict.maxTtc);
  return 0;
}

int run(int argc, const char* const* argv) {
  Args a = makeArgs();
  if (!a.parse(argc, argv)) {
    std::cout << a.help();
    return 0;
  }
  const auto scenario = a.positionalValue(0);
  if (a.has("settings")) {
    // the values in effect: the defaults, a scenario's, then the options
    hw::MonitorConfig cfg;
#ifdef STSIM_HIGHWAY_COSIM
    if (scenario) cfg = st::cosim::loadScenario(*scenario).plugin.monitor;
#else
    if (scenario) throw std::runtime_error("cannot read " + *scenario + ": stsim was built without SUMO support (cosim)");
#endif
    const std::vector<io::SettingOverride> overrides = highwayOverrides(a);
    applyMonitorOptions(overrides, cfg);
    // "in effect" when a scenario or an option gave a monitor key (not --end, a scenario key)
    bool given = scenario.has_value();
    for (const io::SettingOverride& o : overrides) given = given || hw::findSetting(o.key) != nullptr;
    std::cout << hw::settingsReferenceMarkdown(cfg, given ? "in effect" : "default");
    return 0;
  }
  if (a.has("scenario-settings")) {
#ifdef STSIM_HIGHWAY_COSIM
    return printScenarioSettings(a);
#else
    throw std::runtime_error("no scenario settings: stsim was built without SUMO support (cosim)");
#endif
  }
  if (a.has("fcd")) {
    if (scenario) throw UsageError("give either --fcd TRACE (replay) or a SCENARIO (SUMO run), not both");
    return runTrace(a);
  }
  if (!scenario) throw UsageError("missing input: --fcd TRACE.xml --net NET.net.xml, or a SCENARIO (see stsim highway --help)");
  for (const char* opt : {"net", "vtypes", "tls-states", "routes"})
    if (a.has(opt)) throw UsageError(std::string("--") + opt + " applies to --fcd replays");
#ifdef STSIM_HIGHWAY_COSIM
  return runHighwayCommand(a);
#else
  throw std::runtime_error("cannot run " + *scenario + ": stsim was built without SUMO support (cosim)");
#endif
}

}  // namespace

std::vector<io::SettingOverride> highwayOverrides(const Args& a) {
  std::vector<KeyOption> options = kMonitorOptions;
  options.insert(options.end(), kRunOptions.begin(), kRunOptions.end());
  std::vector<io::SettingOverride> out = settingOverrides(a, options, findHighwaySetting, "highway", "");
  if (a.has("validate-ssm")) {
    for (const io::SettingOverride& o : out)
      if (o.key == "validate_ssm") throw UsageError(o.option + ": validate_ssm given twice");
    out.push_back({"validate_ssm", "true", "--validate-ssm"});
  }
  return out;
}

void applyMonitorOptions(const std::vector<io::SettingOverride>& overrides, hw::MonitorConfig& cfg) {
  try {
    for (const io::SettingOverride& o : overrides)
      if (const hw::Setting* s = hw::findSetting(o.key)) hw::applySettingText(cfg, *s, o.text);
    hw::checkSettings(cfg);
  } catch (const io::SettingError& e) {
    overrideError(overrides, e, "");
  }
}

ReplaySettings replaySettings(const std::vector<io::SettingOverride>& overrides) {
  ReplaySettings out;
  for (const io::SettingOverride& o : overrides) {
    if (hw::findSetting(o.key)) continue;
    try {
      if (o.key == hw::kPenetrationSetting.key) {
        out.penetration = std::get<double>(io::settingValue(hw::kPenetrationSetting, o.text));
      } else if (o.key == hw::kSeedSetting.key) {
        out.seed = static_cast<long>(std::get<double>(io::settingValue(hw::kSeedSetting, o.text)));
      } else if (o.key == hw::kEndSetting.key) {
        const io::SettingValue v = io::settingValue(hw::kEndSetting, o.text);
        if (const double* x = std::get_if<double>(&v)) out.end = *x;  // sumocfg: to the trace's end
      } else {
        throw UsageError(o.option + " applies to SUMO runs (SCENARIO), not to --fcd");
      }
    } catch (const io::SettingError& e) {
      overrideError(overrides, e, "");
    }
  }
  return out;
}

Command highwayCommand() {
  return {"highway", "smart-car warnings on a SUMO trace or live SUMO run (report section 4)", run};
}

}  // namespace st::cli
