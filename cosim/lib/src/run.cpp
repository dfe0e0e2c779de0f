#include <stcosim/run.hpp>

#include <algorithm>
#include <fstream>

#include <sthighway/conflict_map.hpp>
#include <sthighway/report.hpp>
#include <stcosim/collisions.hpp>
#include <stcosim/conversions.hpp>
#include <stio/format.hpp>

namespace st::cosim {

namespace fs = std::filesystem;
namespace hw = st::highway;
using Clock = std::chrono::steady_clock;

RunResult runScenario(const Scenario& s, const RunSetup& setup, const RunObserver& observer) {
  const SumoConfigFiles files = checkSumoConfig(s.sumocfg);
  const bool attach = setup.attach.has_value();
  const bool gui = setup.gui;
  const bool validate = s.validateSsm;
  if (attach && gui) throw RunSetupError("--gui starts sumo-gui; with --traci the running SUMO decides");
  if (attach && validate)
    throw RunSetupError("--validate-ssm needs stsim to start SUMO (the SSM device is a SUMO option)");
  const fs::path& out = setup.out;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw std::runtime_error("cannot create output directory " + out.string() + ": " + ec.message());
  // every file in out belongs to this run: what an earlier run wrote and this one may not goes first
  hw::removeRunOutputs(out);

  // outputs first, so whatever happens later leaves valid files
  hw::WarningsCsvWriter csv(out / "warnings.csv");
  hw::EventsCsvWriter eventsCsv(out / "events.csv");
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

  std::unique_ptr<Backend> backend;
  try {
    if (attach) {
      backend = attachTraci(*setup.attach);
    } else if (gui) {
      SumoLaunch l{args, true, (out / "sumo.log").string(), ""};
      backend = launchTraci(l);
    } else {
      backend = startLibsumo(SumoLaunch{args, false, "", ""});
    }
  } catch (const std::exception& e) {
    // SUMO never ran: the summary says so (not an earlier run's)
    hw::RunInfo info;
    info.source = s.source.string();
    info.detector = hw::toString(s.plugin.monitor.detector.kind);
    info.broadphase = hw::toString(s.plugin.monitor.broadphase);
    info.prediction = hw::toString(s.plugin.monitor.prediction);
    info.wallSeconds = std::chrono::duration<double>(Clock::now() - setup.wallStart).count();
    info.strings = {{"sumocfg", s.sumocfg.string()}, {"stop_reason", "error"}, {"error", e.what()}};
    hw::writeSummaryJson(out / "summary.json", hw::MonitorCounters{}, info);
    throw;
  }

  HighwayPlugin plugin(*backend, s.plugin);
  int cellPolygons = 0;
  if (gui || backend->hasGui()) cellPolygons = plugin.drawCells();
  std::unique_ptr<SsmValidator> validator;
  if (validate)
    validator = std::make_unique<SsmValidator>(toRoadGeometry(backend->lanes()), s.plugin.monitor, backend->deltaT());

  RunResult result;
  result.attached = attach;
  double sumoSeconds = 0.0, stsimSeconds = 0.0, validationSeconds = 0.0;
  std::string error;
  std::string& stopReason = result.stopReason;
  const double endTime = s.end ? *s.end : (files.end ? *files.end : -1.0);
  auto lastProgress = Clock::now();

  // kept for the collisions' warning lead times, worked out at the end
  std::vector<SumoCollision> collisionReports;
  std::vector<hw::Warning> vehicleWarnings;
  std::vector<hw::HindsightEvent> events;  // one buffer for every step
  auto writeWarnings = [&](const std::vector<hw::Warning>& finished) {
    csv.write(finished);
    for (const hw::Warning& w : finished)
      if (w.kind == hw::WarningKind::Vehicle) vehicleWarnings.push_back(w);
    plugin.takeEvents(events);
    eventsCsv.write(events);
  };
  auto fmt3 = [](double v) { return io::fixed(v, 3); };
  auto writeCollision = [&](const SumoCollision& c) {
    collisionReports.push_back(c);
    collisionsCsv << fmt3(c.time) << "," << io::csvField(c.collider) << "," << io::csvField(c.victim) << ","
                  << io::csvField(c.type) << "," << io::csvField(c.lane) << "," << fmt3(c.pos) << ","
                  << fmt3(c.colliderSpeed) << "," << fmt3(c.victimSpeed) << "\n";
  };
  auto writeCollisions = [&] {
    for (const auto& c : plugin.takeCollisions()) writeCollision(c);
  };

  try {
    while (backend->running()) {
      if (observer.stopRequested && observer.stopRequested()) {
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
      if (observer.progress && t2 - lastProgress > observer.progressInterval) {
        lastProgress = t2;
        RunProgress p;
        p.time = backend->time();
        p.endTime = endTime;
        p.vehicles = backend->vehicles().size();
        for (auto n : plugin.monitor().counters().warningsByKind) p.warnings += n;
        p.sumoSeconds = sumoSeconds;
        p.stsimSeconds = stsimSeconds;
        observer.progress(p);
      }
    }
  } catch (const std::exception& e) {
    if (observer.stopRequested && observer.stopRequested()) {
      // Ctrl-C reaches an attached SUMO in the same terminal too: its lost connection is the stop
      stopReason = "interrupted";
    } else {
      error = e.what();
      stopReason = "error";
    }
  }

  // close the episodes, write everything, then close SUMO (which writes the SSM file)
  plugin.finish();
  writeWarnings(plugin.takeFinished());
  csv.flush();
  eventsCsv.flush();
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
      lc << fmt3(w.collision.time) << "," << io::csvField(w.collision.collider) << ","
         << io::csvField(w.collision.victim) << "," << (w.leadTime ? 1 : 0) << ","
         << (w.leadTime ? fmt3(*w.leadTime) : std::string()) << "\n";
  }

  if (validator && error.empty()) {
    result.validation = validator->evaluate(readSsmOutput(ssmFile));
    std::ofstream vj(out / "validation.json");
    vj << toJson(*result.validation);
  }

  hw::RunInfo info;
  info.source = s.source.string();
  info.detector = hw::toString(s.plugin.monitor.detector.kind);
  info.broadphase = hw::toString(s.plugin.monitor.broadphase);
  info.prediction = hw::toString(s.plugin.monitor.prediction);
  info.hindsight = s.plugin.monitor.hindsight;
  info.simulatedSeconds = simEnd;
  info.wallSeconds = std::chrono::duration<double>(Clock::now() - setup.wallStart).count();
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
    // recall as hindsight counts it for near misses: warned at least its lead time before
    std::vector<double> ahead;
    for (const CollisionWarning& w : leads)
      if (w.leadTime && *w.leadTime >= s.plugin.monitor.hindsight.lead) ahead.push_back(*w.leadTime);
    info.rawJson.push_back({"collisions", hw::eventRecallJson(leads.size(), ahead.size(), ahead)});
  }
  info.strings = {{"sumocfg", s.sumocfg.string()},
                  {"net", fs::absolute(files.net).string()},
                  {"backend", backendName},
                  {"action", toString(s.plugin.actions.action)},
                  {"stop_reason", stopReason}};
  if (attach)
    info.strings.emplace_back("sumo_collisions", "unknown: attached to a SUMO started elsewhere, which stsim cannot ask "
                                                 "for --collision-output (libtraci 1.15 has no getCollisions)");
  if (!error.empty()) info.strings.emplace_back("error", error);
  hw::writeSummaryJson(out / "summary.json", plugin.monitor().counters(), info);
  // the map of whatever was written, an error or not
  const bool mapped = setup.map && hw::writeConflictMap({out / "conflict_map", files.net, {out / "warnings.csv"},
                                                         (s.source.parent_path().filename() / s.source.filename()).string()},
                                                        result.mapProblem);

  if (!error.empty()) throw std::runtime_error(error + " (results so far in " + out.string() + ")");

  result.backend = backendName;
  result.detector = info.detector;
  result.simulatedSeconds = simEnd;
  result.sumoSeconds = sumoSeconds;
  result.stsimSeconds = stsimSeconds;
  result.wallSeconds = info.wallSeconds;
  result.monitor = plugin.monitor().counters();
  result.plugin = pc;
  result.written = {out / "warnings.csv", out / "events.csv", out / "collisions.csv"};
  if (!attach) result.written.push_back(out / "collision_warnings.csv");
  result.written.push_back(out / "summary.json");
  if (result.validation) result.written.push_back(out / "validation.json");
  if (mapped) {
    result.written.push_back(out / "conflict_map.png");
    result.written.push_back(out / "conflict_map.svg");
  }
  return result;
}

}  // namespace st::cosim
