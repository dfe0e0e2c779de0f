#pragma once
// runScenario's stages, one job each; run.cpp reads as their list:
//   RunOutputs      the streamed files, opened before SUMO starts (run_outputs.cpp)
//   startSumo       SUMO's arguments and the backend; a start failure's summary (run_sumo.cpp)
//   stepLoop        step SUMO, detect, write, until the end, a stop or an error (run_loop.cpp)
//   closeRun        close the episodes, flush, close SUMO (run_loop.cpp)
//   writeSummary    collisions' leads, validation, summary.json (run_summary.cpp)
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <stio/output.hpp>

#include <sthighway/report.hpp>
#include <sthighway/run_files.hpp>
#include <stcosim/collisions.hpp>
#include <stcosim/run.hpp>

namespace st::cosim {

// The highway's tick files (warnings.csv, conflicts.csv, events.csv, exposure.csv, trajectories.csv:
// highway::TickFiles) and collisions.csv, written as the run goes, and what the end needs of them
// (the vehicle warnings and collision reports, for the collisions' warning lead times).
class RunOutputs {
 public:
  // Creates `out` and removes what an earlier run wrote there: every file in it belongs to this run.
  // With trajectories, trajectories.csv too (the plugin records them).
  explicit RunOutputs(const std::filesystem::path& out, bool trajectories = false);
  // The finished warnings and hindsight's events since the last call.
  void writeDetected(HighwayPlugin& plugin);
  void writeCollisions(HighwayPlugin& plugin);
  void writeCollision(const SumoCollision& c);
  void flush();
  const std::vector<SumoCollision>& collisionReports() const { return collisionReports_; }
  const std::vector<highway::Warning>& vehicleWarnings() const { return ticks_.vehicleWarnings(); }

 private:
  highway::TickFiles ticks_;  // first: it creates the directory
  io::CsvRowWriter collisions_;
  std::vector<SumoCollision> collisionReports_;
};

// collision_warnings.csv: one row per collision, whether and how long before its collider warned.
void writeCollisionWarnings(const std::filesystem::path& path, const std::vector<CollisionWarning>& leads);

struct SumoStart {
  std::unique_ptr<Backend> backend;
  std::filesystem::path ssmFile;        // SSM's output, with validate_ssm
  std::filesystem::path collisionFile;  // SUMO's --collision-output, when collisionsFromFile
  bool collisionsFromFile = false;      // over a launched TraCI SUMO (libtraci has no getCollisions)
};
// Starts (or attaches to) SUMO. When it never ran, writes a summary saying so, then rethrows.
SumoStart startSumo(const Scenario& s, const RunSetup& setup);

struct LoopOutcome {
  double sumoSeconds = 0.0, stsimSeconds = 0.0, validationSeconds = 0.0;
  std::string stopReason = "end";  // end | interrupted | error
  std::string error;               // the error that ended the run, if any
};
// Steps SUMO with the plugin (detection in line, or overlapped beside the next step: DetectionStage) until the end time, a stop request or an error (caught into the outcome).
LoopOutcome stepLoop(Backend& backend, HighwayPlugin& plugin, SsmValidator* validator, RunOutputs& outputs,
                     double endTime, bool overlap, const RunObserver& observer);

// Closes the open episodes at the current time, writes everything, then closes SUMO (which writes
// the SSM file). Returns the simulated end time.
double closeRun(Backend& backend, HighwayPlugin& plugin, SsmValidator* validator, RunOutputs& outputs);

// What summary.json needs beyond the scenario, the setup and the counters.
struct SummaryFacts {
  double simEnd = 0.0, deltaT = 0.0;
  std::string backend;
  std::string net;
  int cellPolygons = 0;
  const LoopOutcome* loop = nullptr;
  const PluginCounters* plugin = nullptr;
  const std::vector<CollisionWarning>* leads = nullptr;  // null when attached
};
// summary.json; returns the run info written (for the result).
highway::RunInfo writeSummary(const Scenario& s, const RunSetup& setup, const SummaryFacts& f,
                              const highway::MonitorCounters& counters);
// summary.json for a SUMO that never ran.
void writeStartFailureSummary(const Scenario& s, const RunSetup& setup, const std::string& error);

}  // namespace st::cosim
