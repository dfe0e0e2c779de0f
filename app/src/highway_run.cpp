// `stsim highway SCENARIO`: the co-simulation front end (a progress line on a terminal, a summary
// at the end); st::cosim below it does not print.
#include "highway_run.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <ranges>

#include <sthighway/report.hpp>
#include <stcosim/run.hpp>
#include <stcosim/scenario_settings.hpp>
#include <stio/format.hpp>

#include "highway_options.hpp"
#include "setting_options.hpp"
#include "stop_signals.hpp"

namespace st::cli {
namespace {

namespace cosim = st::cosim;

namespace fs = std::filesystem;
namespace hw = st::highway;

cosim::TraciEndpoint parseTraci(const std::string& text) {
  // HOST:PORT[:ORDER]
  cosim::TraciEndpoint e;
  std::vector<std::string> parts;
  for (const auto part : std::views::split(text, ':')) parts.emplace_back(part.begin(), part.end());
  auto number = [&](const std::string& s, const char* what) {
    try {
      std::size_t used = 0;
      const long v = std::stol(s, &used);
      if (used == s.size() && v > 0 && v < 65536) return static_cast<int>(v);
    } catch (...) {
    }
    throw UsageError(std::string("--traci: ") + what + " must be a whole number from 1 to 65535, got '" + s +
                              "' in '" + text + "' (HOST:PORT[:ORDER])");
  };
  if (parts.size() < 2 || parts.size() > 3 || parts[0].empty())
    throw UsageError("--traci needs HOST:PORT[:ORDER], got '" + text + "'");
  e.host = parts[0];
  e.port = number(parts[1], "PORT");
  e.order = parts.size() == 3 ? number(parts[2], "ORDER") : 1;
  return e;
}

// Command-line options override the scenario, each checked by its key's table.
void applyOptions(const Args& a, cosim::Scenario& s) {
  const std::vector<io::SettingOverride> overrides = highwayOverrides(a);
  applyMonitorOptions(overrides, s.plugin.monitor);
  try {
    for (const io::SettingOverride& o : overrides)
      if (const cosim::ScenarioSetting* setting = cosim::findScenarioSetting(o.key)) cosim::applyScenarioSettingText(s, *setting, o.text);
    cosim::checkScenarioSettings(s);
  } catch (const io::SettingError& e) {
    overrideError(overrides, e, "");
  }
}

std::string fmt(double v, int decimals = 2) { return io::fixed(v, decimals); }

}  // namespace

int printScenarioSettings(const Args& a) {
  // the values in effect: the defaults, a scenario's, then the options
  cosim::Scenario s;
  const auto scenario = a.positionalValue(0);
  if (scenario) s = cosim::loadScenario(*scenario);
  applyOptions(a, s);
  const bool given = scenario.has_value() || !highwayOverrides(a).empty();
  std::cout << cosim::scenarioSettingsMarkdown(s, given ? "in effect" : "default");
  return 0;
}

int runHighwayCommand(const Args& a) {
  cosim::RunSetup setup;  // the wall clock starts before the scenario is read
  const fs::path scenarioPath = a.positionalValue(0).value_or("");
  cosim::Scenario s = cosim::loadScenario(scenarioPath);
  applyOptions(a, s);
  setup.out = a.has("out") || !s.out ? fs::path(a.get("out")) : *s.out;
  setup.gui = a.has("gui");
  setup.map = !a.has("no-map");
  if (a.has("threads")) {
    const long n = a.getInt("threads");
    if (n != 1 && n != 2)
      throw UsageError("--threads must be 1 (detection after each SUMO step) or 2 (beside it), got " +
                                a.get("threads"));
    setup.threads = static_cast<int>(n);
  }
  setup.trajectories = a.has("trajectories");
  if (a.has("traci")) setup.attach = parseTraci(a.get("traci"));

  // a peer closing the TraCI socket must give an error, not kill the run
  const StopSignals stopSignals(StopSignals::Pipe::Ignore);
  cosim::RunObserver observer;
  observer.stopRequested = StopSignals::requested;
  const bool progress = ::isatty(STDERR_FILENO) == 1;
  if (progress)
    observer.progress = [](const cosim::RunProgress& p) {
      std::fprintf(stderr, "\r  t = %8.1f s%s  vehicles %5zu  warnings %7llu  SUMO %6.1f s  stsim %6.1f s ", p.time,
                   p.endTime >= 0 ? (" / " + fmt(p.endTime, 0)).c_str() : "", p.vehicles,
                   static_cast<unsigned long long>(p.warnings), p.sumoSeconds, p.stsimSeconds);
      std::fflush(stderr);
    };
  auto clearProgress = [&] {
    if (progress) std::fprintf(stderr, "\r%100s\r", "");
  };
  cosim::RunResult r;
  try {
    r = cosim::runScenario(s, setup, observer);
  } catch (const cosim::RunSetupError& e) {
    throw UsageError(e.what());
  } catch (...) {
    clearProgress();
    throw;
  }
  clearProgress();

  const hw::MonitorCounters& c = r.monitor;
  const cosim::PluginCounters& pc = r.plugin;
  std::uint64_t total = 0;
  for (auto n : c.warningsByKind) total += n;
  std::cout << "highway (" << r.backend << ", " << r.detector << " detector): " << fmt(r.simulatedSeconds, 1)
            << " s simulated, " << c.vehiclesSeen << " vehicles (" << pc.equipped << " equipped), "
            << (c.personsSeen ? std::to_string(c.personsSeen) + " persons on foot, " : std::string())
            << fmt(c.vehicleMeters / 1000.0, 1) << " vehicle-km\n  warnings " << total << ": vehicle "
            << c.warningsByKind[0] << ", curb " << c.warningsByKind[1] << ", lane_marker " << c.warningsByKind[2]
            << ", hazard " << c.warningsByKind[3] << " ("
            << fmt(c.vehicleMeters > 0 ? static_cast<double>(total) / (c.vehicleMeters / 1000.0) : 0.0, 2)
            << " per vehicle-km); by type: " << hw::conflictTypeBreakdown(c) << "\n  conflicts "
            << hw::conflictCountText(c) << ": one per pair and encounter, TTC <= " << fmt(s.plugin.monitor.conflict.maxTtc, 1)
            << " s (conflicts.csv)\n  collisions (bodies touching) "
            << (r.attached ? std::string("unknown")
                           : std::to_string(pc.contacts) + "; SUMO's collisions " + std::to_string(pc.collisions) + ", of which " +
                                 std::to_string(pc.mingapViolations) + " minGap violations with the bodies apart")
            << "; handoffs " << c.handoffs << "\n  time: SUMO " << fmt(r.sumoSeconds) << " s, stsim "
            << fmt(r.stsimSeconds) << " s, wall " << fmt(r.wallSeconds) << " s\n";
  if (const auto& v = r.validation) {
    std::cout << "  SSM validation: " << cosim::summaryLine(*v) << "\n";
  }
  std::cout << "  wrote ";
  for (std::size_t i = 0; i < r.written.size(); ++i) std::cout << (i ? ", " : "") << r.written[i].string();
  std::cout << "\n";
  if (!r.mapProblem.empty() && !r.mapFailed) std::cerr << "stsim highway: no conflict map: " << r.mapProblem << "\n";
  if (r.stopReason == "interrupted") {
    if (r.mapFailed) std::cerr << "stsim highway: no conflict map: " << r.mapProblem << "\n";
    std::cerr << "stsim highway: interrupted at t = " << fmt(r.simulatedSeconds, 1) << " s; results so far written\n";
    return StopSignals::exitCode();  // 130 on Ctrl-C, 143 on SIGTERM, 129 on SIGHUP
  }
  // a map that could not be written (a full disk) fails the run as any output does
  if (r.mapFailed) throw std::runtime_error((setup.out / "conflict_map.png").string() + ": " + r.mapProblem);
  return 0;
}

}  // namespace st::cli
