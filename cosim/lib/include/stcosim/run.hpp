#pragma once
// One co-simulation run of a scenario: SUMO (embedded libsumo, sumo-gui launched over TraCI, or a
// running SUMO attached over TraCI) stepped with the smart-car plugin until the end time, a stop
// request or an error. Writes into setup.out: warnings.csv, collisions.csv, collision_warnings.csv
// (not when attached), summary.json, validation.json with the scenario's validate_ssm, and the
// conflict map (conflict_map.png/.svg, sthighway/conflict_map.hpp) unless setup.map is off. The
// outputs are opened first, so whatever happens later leaves valid files. Prints nothing.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <sthighway/monitor.hpp>
#include <stcosim/backend.hpp>
#include <stcosim/plugin.hpp>
#include <stcosim/scenario.hpp>
#include <stcosim/ssm_validation.hpp>

namespace st::cosim {

struct RunSetup {
  std::filesystem::path out = ".";
  std::optional<TraciEndpoint> attach;  // attach to this running SUMO instead of starting one
  bool gui = false;                     // start sumo-gui and draw the cells
  bool map = true;                      // draw the conflict map
  // Where detection runs (stcosim/detection.hpp): 1 in line after each SUMO step; 2 on a worker
  // beside SUMO's next step, for an action that allows it (detectionCanOverlap: none); 0 picks 2
  // when the machine has a second core and the action allows it, else 1. Same results either way.
  int threads = 0;
  bool trajectories = false;            // write trajectories.csv (each episode's TTC and DRAC per tick)
  // summary.json's wall_s counts from here (the front end's start, so reading counts too)
  std::chrono::steady_clock::time_point wallStart = std::chrono::steady_clock::now();
};

// Options that contradict each other or the scenario (--gui with --traci, SSM validation when
// attached): the front end reports them as usage errors.
struct RunSetupError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

struct RunProgress {
  double time = 0.0;
  double endTime = -1.0;  // s; negative when the run has no end time
  std::size_t vehicles = 0;
  std::uint64_t warnings = 0;
  double sumoSeconds = 0.0, stsimSeconds = 0.0;
};

struct RunObserver {
  std::function<bool()> stopRequested;               // polled before every step; true ends the run
  std::function<void(const RunProgress&)> progress;  // after a step, at most once per interval
  std::chrono::milliseconds progressInterval{250};
};

struct RunResult {
  std::string backend;   // the backend's description
  std::string detector;  // the detector's name
  std::string stopReason = "end";  // end | interrupted
  bool attached = false;
  int threads = 1;  // 2: detection ran beside SUMO's step
  double simulatedSeconds = 0.0, sumoSeconds = 0.0, stsimSeconds = 0.0, wallSeconds = 0.0;
  highway::MonitorCounters monitor;
  PluginCounters plugin;
  std::optional<ValidationReport> validation;
  std::vector<std::filesystem::path> written;  // the files written, in the order a closing line names them
  std::string mapProblem;  // why no conflict map was drawn (python3-matplotlib missing, ...), if so
  bool mapFailed = false;  // the map was tried and could not be written (a full disk): the run fails
};

// The thread count a run uses: setup.threads with 0 resolved. Throws RunSetupError for a count
// other than 0, 1, 2, or 2 with an action that must reach SUMO before the next step.
int resolveThreads(const Scenario& s, const RunSetup& setup);

// Runs the scenario. Throws ScenarioError for a bad SUMO configuration, RunSetupError for
// contradicting options, std::runtime_error when the outputs cannot be written or SUMO cannot be
// started; an error during the run (SUMO's, a dropped connection) first writes everything so far,
// then throws std::runtime_error with the message and where the results are.
RunResult runScenario(const Scenario& s, const RunSetup& setup, const RunObserver& observer = {});

}  // namespace st::cosim
