#include <stcosim/run.hpp>

#include <algorithm>
#include <limits>
#include <thread>

#include <sthighway/conflict_map.hpp>
#include <stcosim/detection.hpp>
#include <stcosim/conversions.hpp>

#include "run_parts.hpp"

namespace st::cosim {

namespace fs = std::filesystem;
namespace hw = st::highway;

namespace {
int checkOptions(const Scenario& s, const RunSetup& setup) {
  const bool attach = setup.attach.has_value();
  if (attach && setup.gui) throw RunSetupError("--gui starts sumo-gui; with --traci the running SUMO decides");
  if (attach && s.validateSsm)
    throw RunSetupError("--validate-ssm needs stsim to start SUMO (the SSM device is a SUMO option)");
  return resolveThreads(s, setup);
}

// Of SUMO's distinct collisions (their first reports), those whose bodies never touched: no
// touching report of the pair from its first report to the pair's next collision.
std::uint64_t minGapOnly(const std::vector<SumoCollision>& firstReports, const std::vector<SumoCollision>& touching) {
  auto pairOf = [](const SumoCollision& c) { return std::minmax(c.collider, c.victim); };
  std::uint64_t n = 0;
  for (std::size_t i = 0; i < firstReports.size(); ++i) {
    const auto pair = pairOf(firstReports[i]);
    double until = std::numeric_limits<double>::infinity();
    for (std::size_t j = i + 1; j < firstReports.size(); ++j)
      if (pairOf(firstReports[j]) == pair) {
        until = firstReports[j].time;
        break;
      }
    const bool touched = std::any_of(touching.begin(), touching.end(), [&](const SumoCollision& c) {
      return pairOf(c) == pair && c.time >= firstReports[i].time && c.time < until;
    });
    if (!touched) ++n;
  }
  return n;
}

// SUMO's collisions from its --collision-output file, when the plugin saw none of them
// (each told a contact or a minGap violation from the bodies the plugin kept of that step)
void readCollisionFile(const SumoStart& start, const HighwayPlugin& plugin, RunOutputs& outputs, LoopOutcome& loop,
                       bool& fileRead) {
  try {
    const double dt = start.backend->deltaT();
    for (SumoCollision c : readCollisionOutput(start.collisionFile, dt)) {
      c.gap = plugin.collidingGap(c, dt);
      outputs.writeCollision(c);
    }
    outputs.flush();
    fileRead = true;
  } catch (const std::exception& e) {
    if (loop.error.empty()) loop.error = e.what();
  }
}

// SUMO's collisions counted into pc, each once whichever way the reports came (read from the
// file when the plugin saw none of them), and told apart: the contacts (bodies touching) and
// SUMO's minGap violations (bodies apart). Returns each contact's first report.
std::vector<SumoCollision> countRunCollisions(const SumoStart& start, const HighwayPlugin& plugin, RunOutputs& outputs,
                                              LoopOutcome& loop, PluginCounters& pc) {
  const double dt = start.backend->deltaT();
  bool fileRead = false;
  if (start.collisionsFromFile) readCollisionFile(start, plugin, outputs, loop, fileRead);
  CollisionCounter counter;
  const std::vector<SumoCollision> firstReports = countCollisions(counter, outputs.collisionReports(), dt);
  if (fileRead) {  // the plugin saw none of them
    pc.collisions = counter.distinct();
    pc.collisionSteps = counter.reports();
  }
  std::vector<SumoCollision> touching, apart;
  for (const SumoCollision& c : outputs.collisionReports()) (c.contact() ? touching : apart).push_back(c);
  CollisionCounter contactCounter;
  std::vector<SumoCollision> firstContacts = countCollisions(contactCounter, touching, dt);
  pc.contacts = contactCounter.distinct();
  pc.mingapViolations = minGapOnly(firstReports, touching);
  return firstContacts;
}

// The conflict map of whatever was written: whether it was drawn (why not, and whether it
// failed, into the result).
bool drawRunMap(const Scenario& s, const SumoConfigFiles& files, const fs::path& out, RunResult& result) {
  const hw::ConflictMapOutcome map = hw::drawConflictMap(
      {out / "conflict_map", files.net, {out / "conflicts.csv"}, (s.source.parent_path().filename() / s.source.filename()).string()});
  result.mapProblem = map.why;
  result.mapFailed = map.state == hw::ConflictMapOutcome::State::Failed;
  return map.state == hw::ConflictMapOutcome::State::Drawn;
}

// The files a run wrote, in the order its closing line names them.
std::vector<fs::path> writtenFiles(const fs::path& out, bool attach, bool validation, bool mapped) {
  std::vector<fs::path> written{out / "warnings.csv", out / "conflicts.csv", out / "events.csv", out / "collisions.csv"};
  if (!attach) written.push_back(out / "collision_warnings.csv");
  written.push_back(out / "summary.json");
  if (validation) written.push_back(out / "validation.json");
  if (mapped) {
    written.push_back(out / "conflict_map.png");
    written.push_back(out / "conflict_map.svg");
  }
  return written;
}
}  // namespace

int resolveThreads(const Scenario& s, const RunSetup& setup) {
  const bool canOverlap = detectionCanOverlap(s.plugin);
  switch (setup.threads) {
    case 0: return canOverlap && std::thread::hardware_concurrency() >= 2 ? 2 : 1;
    case 1: return 1;
    case 2:
      if (!canOverlap)
        throw RunSetupError(std::string("--threads 2 runs detection beside SUMO's next step; --action ") +
                            toString(s.plugin.actions.action) +
                            " must reach SUMO before that step: use --action none or color, or --threads 1");
      return 2;
    default:
      throw RunSetupError("--threads must be 1 (detection after each SUMO step) or 2 (beside it), got " +
                          std::to_string(setup.threads));
  }
}

RunResult runScenario(const Scenario& s, const RunSetup& setup, const RunObserver& observer) {
  const SumoConfigFiles files = checkSumoConfig(s.sumocfg);
  const int threads = checkOptions(s, setup);
  const bool attach = setup.attach.has_value();
  const fs::path& out = setup.out;

  // outputs first, so whatever happens later leaves valid files
  RunOutputs outputs(out, setup.trajectories);
  SumoStart start = startSumo(s, setup);
  Backend& backend = *start.backend;

  HighwayPlugin plugin(backend, s.plugin);
  plugin.recordTrajectories(setup.trajectories);
  int cellPolygons = 0;
  if (setup.gui || backend.hasGui()) cellPolygons = plugin.drawCells();
  std::unique_ptr<SsmValidator> validator;
  if (s.validateSsm)
    validator = std::make_unique<SsmValidator>(toRoadGeometry(backend.lanes()), s.plugin.monitor, backend.deltaT());

  const double endTime = s.end ? *s.end : (files.end ? *files.end : -1.0);
  LoopOutcome loop = stepLoop(backend, plugin, validator.get(), outputs, endTime, threads == 2, observer);

  const std::string backendName = backend.describe();
  const double simEnd = closeRun(backend, plugin, validator.get(), outputs);

  PluginCounters pc = plugin.counters();
  const std::vector<SumoCollision> firstContacts = countRunCollisions(start, plugin, outputs, loop, pc);

  // how long before each contact its collider was warning about the victim
  std::vector<CollisionWarning> leads;
  if (!attach) {
    leads = collisionWarnings(firstContacts, backend.deltaT(), outputs.vehicleWarnings());
    writeCollisionWarnings(out / "collision_warnings.csv", leads);
  }

  RunResult result;
  result.attached = attach;
  result.threads = threads;
  result.stopReason = loop.stopReason;
  if (validator && loop.error.empty()) {
    result.validation = validator->evaluate(readSsmOutput(start.ssmFile), firstContacts);
    io::writeTextFile(out / "validation.json", toJson(*result.validation));
  }

  SummaryFacts facts;
  facts.simEnd = simEnd;
  facts.deltaT = backend.deltaT();
  facts.backend = backendName;
  facts.net = fs::absolute(files.net).string();
  facts.cellPolygons = cellPolygons;
  facts.loop = &loop;
  facts.plugin = &pc;
  facts.leads = attach ? nullptr : &leads;
  const hw::RunInfo info = writeSummary(s, setup, facts, plugin.monitor().counters());
  // the map of whatever was written, an error or not
  const bool mapped = setup.map && drawRunMap(s, files, out, result);

  if (!loop.error.empty()) throw std::runtime_error(loop.error + " (results so far in " + out.string() + ")");

  result.backend = backendName;
  result.detector = info.detector;
  result.simulatedSeconds = simEnd;
  result.sumoSeconds = loop.sumoSeconds;
  result.stsimSeconds = loop.stsimSeconds;
  result.wallSeconds = info.wallSeconds;
  result.monitor = plugin.monitor().counters();
  result.plugin = pc;
  result.written = writtenFiles(out, attach, result.validation.has_value(), mapped);
  return result;
}

}  // namespace st::cosim
