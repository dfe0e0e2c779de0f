// `stsim highway SCENARIO`: the co-simulation front end (a progress line on a terminal, a summary
// at the end); st::cosim below it does not print.
#include "highway_run.hpp"

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <ranges>
#include <sstream>

#include <sthighway/report.hpp>
#include <stcosim/backend.hpp>
#include <stcosim/conversions.hpp>
#include <stcosim/plugin.hpp>
#include <stcosim/scenario.hpp>
#include <stcosim/collisions.hpp>
#include <stcosim/ssm_validation.hpp>

namespace st::cosim {
namespace {

namespace fs = std::filesystem;
namespace hw = st::highway;
using Clock = std::chrono::steady_clock;

volatile sig_atomic_t gInterrupted = 0;
extern "C" void onInterrupt(int) { gInterrupted = 1; }

// Installs a SIGINT/SIGTERM handler for the run and restores the previous ones afterwards.
class InterruptGuard {
 public:
  InterruptGuard() {
    gInterrupted = 0;
    struct sigaction sa {};
    sa.sa_handler = onInterrupt;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &oldInt_);
    sigaction(SIGTERM, &sa, &oldTerm_);
    // a peer closing the TraCI socket must give an error, not kill us
    struct sigaction ign {};
    ign.sa_handler = SIG_IGN;
    sigaction(SIGPIPE, &ign, &oldPipe_);
  }
  ~InterruptGuard() {
    sigaction(SIGINT, &oldInt_, nullptr);
    sigaction(SIGTERM, &oldTerm_, nullptr);
    sigaction(SIGPIPE, &oldPipe_, nullptr);
  }

 private:
  struct sigaction oldInt_ {}, oldTerm_ {}, oldPipe_ {};
};

TraciEndpoint parseTraci(const std::string& text) {
  // HOST:PORT[:ORDER]
  TraciEndpoint e;
  std::vector<std::string> parts;
  for (const auto part : std::views::split(text, ':')) parts.emplace_back(part.begin(), part.end());
  auto number = [&](const std::string& s, const char* what) {
    try {
      std::size_t used = 0;
      const long v = std::stol(s, &used);
      if (used == s.size() && v > 0 && v < 65536) return static_cast<int>(v);
    } catch (...) {
    }
    throw st::cli::UsageError(std::string("--traci: ") + what + " must be a positive integer, got '" + s + "' in '" +
                              text + "' (HOST:PORT[:ORDER])");
  };
  if (parts.size() < 2 || parts.size() > 3 || parts[0].empty())
    throw st::cli::UsageError("--traci needs HOST:PORT[:ORDER], got '" + text + "'");
  e.host = parts[0];
  e.port = number(parts[1], "PORT");
  e.order = parts.size() == 3 ? number(parts[2], "ORDER") : 1;
  return e;
}

// Command-line options override the scenario.
void applyOptions(const st::cli::Args& a, Scenario& s) {
  hw::MonitorConfig& m = s.plugin.monitor;
  if (a.has("detector") && !hw::parseDetectorKind(a.get("detector"), m.detector.kind))
    throw st::cli::UsageError("--detector must be concentric, five or box, got '" + a.get("detector") + "'");
  if (a.has("broadphase") && !hw::parseBroadphase(a.get("broadphase"), m.broadphase))
    throw st::cli::UsageError("--broadphase must be cells or all-pairs, got '" + a.get("broadphase") + "'");
  if (a.has("layout") && !hw::parseFiveCircleLayout(a.get("layout"), m.detector.five))
    throw st::cli::UsageError("--layout must be a or b, got '" + a.get("layout") + "'");
  if (a.has("motion") && !hw::parseMotionModel(a.get("motion"), m.detector.motion))
    throw st::cli::UsageError("--motion must be velocity or acceleration, got '" + a.get("motion") + "'");
  if (a.has("penetration")) {
    const double p = a.getDouble("penetration");
    if (p < 0.0 || p > 1.0) throw st::cli::UsageError("--penetration must be in [0, 1]");
    s.plugin.smart.penetration = p;
  }
  if (a.has("action") && !parseAction(a.get("action"), s.plugin.actions.action))
    throw st::cli::UsageError("--action must be color, brake or none, got '" + a.get("action") + "'");
  if (a.has("end")) {
    const double e = a.getDouble("end");
    if (e <= 0.0) throw st::cli::UsageError("--end must be positive");
    s.end = e;
  }
  if (a.has("scale")) {
    const double d = a.getDouble("scale");
    if (!(d >= 0.0 && d <= 1000.0)) throw st::cli::UsageError("--scale must be in [0, 1000]");
    s.demandScale = d;
  }
  if (a.has("validate-ssm")) s.validateSsm = true;
  if (a.has("seed")) {
    const long seed = a.getInt("seed");
    if (seed < 0 || seed > 2147483647) throw st::cli::UsageError("--seed must be in [0, 2^31 - 1]");
    s.seed = static_cast<std::uint64_t>(seed);
    s.plugin.smart.seed = s.seed;
  }
}

std::string csvCell(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string fmt(double v, int prec = 2) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(prec) << v;
  return os.str();
}

}  // namespace

int runHighwayCommand(const st::cli::Args& a) {
  const auto wallStart = Clock::now();
  const fs::path scenarioPath = a.positionalValue(0).value_or("");
  Scenario s = loadScenario(scenarioPath);
  applyOptions(a, s);
  const SumoConfigFiles files = checkSumoConfig(s.sumocfg);

  const bool attach = a.has("traci");
  const bool gui = a.has("gui");
  const bool validate = s.validateSsm;
  if (attach && gui) throw st::cli::UsageError("--gui starts sumo-gui; with --traci the running SUMO decides");
  if (attach && validate)
    throw st::cli::UsageError("--validate-ssm needs stsim to start SUMO (the SSM device is a SUMO option)");
  const fs::path out = a.has("out") || !s.out ? fs::path(a.get("out")) : *s.out;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw std::runtime_error("cannot create output directory " + out.string() + ": " + ec.message());

  // outputs first, so whatever happens later leaves valid files
  hw::WarningsCsvWriter csv(out / "warnings.csv");
  std::ofstream collisionsCsv(out / "collisions.csv");
  if (!collisionsCsv) throw std::runtime_error("cannot write " + (out / "collisions.csv").string());
  collisionsCsv << "time,collider,victim,type,lane,pos,collider_speed,victim_speed\n";
  collisionsCsv.flush();

  std::vector<std::string> args = sumoArguments(s);
  const fs::path ssmFile = fs::absolute(out / "ssm.xml");
  // the SSM threshold: above any safe time we expect, so every conflict below a safe time is logged
  const double ssmThreshold = 5.0;
  if (validate) {
    fs::remove(ssmFile, ec);
    const auto extra = ssmArguments(ssmFile, ssmThreshold);
    args.insert(args.end(), extra.begin(), extra.end());
  }

  // Over TraCI SUMO's collisions come from its --collision-output file, read after the run (SUMO
  // 1.15's libtraci cannot fetch them per step); attached to a SUMO started elsewhere, stsim cannot
  // ask for that file, so the run has no collision figures.
  const bool collisionsFromFile = gui;
  const fs::path collisionFile = fs::absolute(out / "sumo_collisions.xml");
  if (collisionsFromFile) {
    fs::remove(collisionFile, ec);
    const auto extra = collisionOutputArguments(collisionFile);
    args.insert(args.end(), extra.begin(), extra.end());
  }

  InterruptGuard interruptGuard;
  std::unique_ptr<Backend> backend;
  if (attach) {
    backend = attachTraci(parseTraci(a.get("traci")));
  } else if (gui) {
    SumoLaunch l{args, true, (out / "sumo.log").string(), ""};
    backend = launchTraci(l);
  } else {
    backend = startLibsumo(SumoLaunch{args, false, "", ""});
  }

  HighwayPlugin plugin(*backend, s.plugin);
  int cellPolygons = 0;
  if (gui || backend->hasGui()) cellPolygons = plugin.drawCells();
  std::unique_ptr<SsmValidator> validator;
  if (validate)
    validator = std::make_unique<SsmValidator>(toRoadGeometry(backend->lanes()), s.plugin.monitor, backend->deltaT());

  const bool progress = ::isatty(STDERR_FILENO) == 1;
  double sumoSeconds = 0.0, stsimSeconds = 0.0, validationSeconds = 0.0;
  auto lastProgress = Clock::now();
  std::string error;
  std::string stopReason = "end";
  std::uint64_t collisionRows = 0;
  const double endTime = s.end ? *s.end : (files.end ? *files.end : -1.0);

  // kept for the collisions' warning lead times, worked out at the end
  std::vector<SumoCollision> collisionReports;
  std::vector<hw::Warning> vehicleWarnings;
  auto writeWarnings = [&](const std::vector<hw::Warning>& finished) {
    csv.write(finished);
    for (const hw::Warning& w : finished)
      if (w.kind == hw::WarningKind::Vehicle) vehicleWarnings.push_back(w);
  };
  auto writeCollision = [&](const SumoCollision& c) {
    collisionReports.push_back(c);
    collisionsCsv << fmt(c.time, 3) << "," << csvCell(c.collider) << "," << csvCell(c.victim) << ","
                  << csvCell(c.type) << "," << csvCell(c.lane) << "," << fmt(c.pos, 3) << ","
                  << fmt(c.colliderSpeed, 3) << "," << fmt(c.victimSpeed, 3) << "\n";
    collisionRows++;
  };
  auto writeCollisions = [&] {
    for (const auto& c : plugin.takeCollisions()) writeCollision(c);
  };

  try {
    while (backend->running()) {
      if (gInterrupted) {
        stopReason = "interrupted";
        break;
      }
      if (endTime >= 0.0 && backend->time() >= endTime - 0.5 * backend->deltaT()) break;
      const auto t0 = Clock::now();
      backend->step();
      const auto t1 = Clock::now();
      plugin.update();
      const auto t2 = Clock::now();
      sumoSeconds += std::chrono::duration<double>(t1 - t0).count();
      stsimSeconds += std::chrono::duration<double>(t2 - t1).count();
      if (validator) {
        validator->record(backend->time(), plugin.states());
        validationSeconds += std::chrono::duration<double>(Clock::now() - t2).count();
      }
      writeWarnings(plugin.takeFinished());
      writeCollisions();
      if (progress && t2 - lastProgress > std::chrono::milliseconds(250)) {
        lastProgress = t2;
        std::uint64_t warned = 0;
        for (auto n : plugin.monitor().counters().warningsByKind) warned += n;
        std::fprintf(stderr, "\r  t = %8.1f s%s  vehicles %5zu  warnings %7llu  SUMO %6.1f s  stsim %6.1f s ",
                     backend->time(), endTime >= 0 ? (" / " + fmt(endTime, 0)).c_str() : "",
                     backend->vehicles().size(), static_cast<unsigned long long>(warned), sumoSeconds, stsimSeconds);
        std::fflush(stderr);
      }
    }
  } catch (const std::exception& e) {
    error = e.what();
    stopReason = "error";
  }
  if (progress) std::fprintf(stderr, "\r%100s\r", "");

  // close the episodes, write everything, then close SUMO (which writes the SSM file)
  plugin.finish();
  writeWarnings(plugin.takeFinished());
  csv.flush();
  writeCollisions();
  collisionsCsv.flush();
  if (validator) validator->finish(backend->time());
  const double simEnd = backend->time();
  const std::string backendName = backend->describe();
  backend->close();

  PluginCounters pc = plugin.counters();
  bool fileRead = false;
  if (collisionsFromFile) {
    try {
      for (const SumoCollision& c : readCollisionOutput(collisionFile, backend->deltaT())) writeCollision(c);
      collisionsCsv.flush();
      fileRead = true;
    } catch (const std::exception& e) {
      if (error.empty()) error = e.what();
    }
  }
  // each collision's first report, counted once whichever way the reports came
  CollisionCounter counter;
  const std::vector<SumoCollision> firstReports = countCollisions(counter, collisionReports, backend->deltaT());
  if (fileRead) {  // the plugin saw none of them
    pc.collisions = counter.distinct();
    pc.collisionSteps = counter.reports();
  }

  // how long before each collision its collider was warning about the victim
  std::vector<CollisionWarning> leads;
  if (!attach) {
    leads = collisionWarnings(firstReports, backend->deltaT(), vehicleWarnings);
    std::ofstream lc(out / "collision_warnings.csv");
    lc << "time,collider,victim,collider_warned,lead_time_s\n";
    for (const CollisionWarning& w : leads)
      lc << fmt(w.collision.time, 3) << "," << csvCell(w.collision.collider) << "," << csvCell(w.collision.victim) << ","
         << (w.leadTime ? 1 : 0) << "," << (w.leadTime ? fmt(*w.leadTime, 3) : std::string()) << "\n";
  }

  std::optional<ValidationReport> validation;
  if (validator && error.empty()) {
    validation = validator->evaluate(readSsmOutput(ssmFile));
    std::ofstream vj(out / "validation.json");
    vj << toJson(*validation);
  }

  hw::RunInfo info;
  info.source = scenarioPath.string();
  info.detector = hw::toString(s.plugin.monitor.detector.kind);
  info.broadphase = hw::toString(s.plugin.monitor.broadphase);
  info.simulatedSeconds = simEnd;
  info.wallSeconds = std::chrono::duration<double>(Clock::now() - wallStart).count();
  info.numbers = {{"sumo_seconds", sumoSeconds},
                  {"stsim_seconds", stsimSeconds},
                  {"validation_seconds", validationSeconds},
                  {"steps", static_cast<double>(pc.steps)},
                  {"step_length_s", backend->deltaT()},
                  {"seed", static_cast<double>(s.seed)},
                  {"penetration", s.plugin.smart.penetration},
                  {"equipped_vehicles", static_cast<double>(pc.equipped)},
                  {"departed", static_cast<double>(pc.departed)},
                  {"arrived", static_cast<double>(pc.arrived)},
                  {"teleports", static_cast<double>(pc.teleports)},
                  {"color_changes", static_cast<double>(pc.colorChanges)},
                  {"brake_commands", static_cast<double>(pc.brakeCommands)},
                  {"incidents", static_cast<double>(pc.incidents)},
                  {"cell_polygons", static_cast<double>(cellPolygons)}};
  if (!attach) {
    info.numbers.push_back({"sumo_collisions", static_cast<double>(pc.collisions)});
    info.numbers.push_back({"sumo_collision_steps", static_cast<double>(pc.collisionSteps)});
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
  }
  info.strings = {{"sumocfg", s.sumocfg.string()},
                  {"backend", backendName},
                  {"action", toString(s.plugin.actions.action)},
                  {"stop_reason", stopReason}};
  if (attach)
    info.strings.emplace_back("sumo_collisions", "unknown: attached to a SUMO started elsewhere, which stsim cannot ask "
                                                 "for --collision-output (libtraci 1.15 has no getCollisions)");
  if (!error.empty()) info.strings.emplace_back("error", error);
  hw::writeSummaryJson(out / "summary.json", plugin.monitor().counters(), info);

  if (!error.empty()) throw std::runtime_error(error + " (results so far in " + out.string() + ")");

  const hw::MonitorCounters& c = plugin.monitor().counters();
  std::uint64_t total = 0;
  for (auto n : c.warningsByKind) total += n;
  std::cout << "highway (" << backendName << ", " << info.detector << " detector): " << fmt(simEnd, 1) << " s simulated, "
            << c.vehiclesSeen << " vehicles (" << pc.equipped << " equipped), " << fmt(c.vehicleMeters / 1000.0, 1)
            << " vehicle-km\n  warnings " << total << ": vehicle " << c.warningsByKind[0] << ", curb "
            << c.warningsByKind[1] << ", lane_marker " << c.warningsByKind[2] << ", hazard " << c.warningsByKind[3]
            << " (" << fmt(c.vehicleMeters > 0 ? static_cast<double>(total) / (c.vehicleMeters / 1000.0) : 0.0, 2)
            << " per vehicle-km); SUMO collisions " << (attach ? std::string("unknown") : std::to_string(pc.collisions))
            << "; handoffs " << c.handoffs
            << "\n  time: SUMO " << fmt(sumoSeconds) << " s, stsim " << fmt(stsimSeconds) << " s, wall "
            << fmt(info.wallSeconds) << " s\n";
  if (validation) {
    std::cout << "  SSM validation: " << validation->matchedSamples << " following samples, "
              << fmt(100.0 * validation->withinFraction(), 2) << " % within " << validation->tolerance
              << " s of SSM's TTC;";
    for (const auto& d : validation->detectors)
      std::cout << " " << d.detector << " recall " << fmt(d.recall(), 3) << " precision " << fmt(d.precision(), 3) << ";";
    std::cout << "\n";
  }
  std::cout << "  wrote " << (out / "warnings.csv").string() << ", " << (out / "collisions.csv").string()
            << (attach ? std::string() : ", " + (out / "collision_warnings.csv").string()) << ", "
            << (out / "summary.json").string()
            << (validation ? ", " + (out / "validation.json").string() : std::string()) << "\n";
  if (stopReason == "interrupted") {
    std::cerr << "stsim highway: interrupted at t = " << fmt(simEnd, 1) << " s; results so far written\n";
    return 130;
  }
  return 0;
}

}  // namespace st::cosim
