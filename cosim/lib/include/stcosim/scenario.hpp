#pragma once
// A co-simulation scenario: a SUMO configuration plus stsim's settings, read from a scenario YAML
// (or defaults for a plain .sumocfg). Paths in the YAML are relative to the YAML file. Every key
// below is shown at its default, or with "default:" beside it when the value shown is an example.
// The scenario's own settings (seed, end, demand_scale, validate_ssm, penetration, action, brake.*,
// collision_*) are the table of docs/scenario_settings.md (stcosim/scenario_settings.hpp, printed
// by `stsim highway --scenario-settings`); the monitor's (detector ... hindsight) the table of
// docs/settings.md (`stsim highway --settings`). Each key is checked by its table, in the YAML and
// on the command line alike; only a few of the monitor's are shown here.
//
//   sumocfg: motorway.sumocfg        # required
//   seed: 42                          # SUMO's seed and the smart-car draw
//   end: 420                          # s of simulated time (default sumocfg: the sumocfg's end)
//   demand_scale: 1.0                 # SUMO's --scale: multiplies the routes' demand
//   validate_ssm: false               # also run SUMO's SSM device and write validation.json
//   detector: five                    # concentric | five | box
//   layout: a                         # five-circle zones: a (Fig. 11a) | b (Fig. 11b)
//   motion: velocity                  # velocity | acceleration
//   broadphase: cells                 # cells | all-pairs
//   check_road: true                  # curbs and lane markers
//   penetration: 1.0                  # fraction of vehicles equipped
//   smart_types: [truck]              # vTypes always equipped (default: none)
//   action: color                     # none | color | brake
//   brake: {deceleration: 3.0, max_deceleration: 9.0, standstill_gap: 1.0}   # action brake (m/s^2, m)
//   safe_time:
//     vehicle_reaction: 1.0           # s
//     road_reaction: 0.5              # s
//     brake_force: {passenger: 12000, truck: 75000, bus: 72000, motorcycle: 2250, emergency: 31500, other: 12000}
//   conflict: {rear_end_below: 30, crossing_above: 85, max_ttc: 1.5, max_pet: 5}   # deg, deg, s, s: SSAM's
//   concentric: {inner_margin: 0.0, outer_margin: 0.0}
//   cells: {length: 800, hysteresis_db: 3, tx_power_dbm: 40, path_loss_exponent: 3,
//           reference_distance: 1, radio_range: 1000, decomposition_factor: 128, max_depth: 8}
//   collision_action: warn            # passed to SUMO's --collision.action
//   collision_mingap_factor: 1        # SUMO's --collision.mingap-factor: SUMO registers a collision
//                                     # when a gap falls below factor x the follower's minGap (SUMO's
//                                     # default 1); 0 counts physical contact only
//   incidents:                        # scripted hard braking (plugin.hpp Incident; default: none)
//     - {time: 150, near: [2200, -5.6], speed: 0, deceleration: 8, hold: 30}
//   sumo_args: ["--lateral-resolution", "0.8"]   # extra SUMO options (default: none)
//   out: out/motorway                 # output directory, relative to the working directory
//                                     # (--out overrides it; without either, `stsim highway --help`'s)
// Unknown keys are errors (a typo must not silently fall back to a default).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <stcosim/plugin.hpp>

namespace st::cosim {

// A bad scenario or SUMO configuration; what() is one line naming the file (and line or field).
struct ScenarioError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Scenario {
  std::filesystem::path source;    // the YAML or .sumocfg given
  std::filesystem::path sumocfg;
  PluginConfig plugin;
  std::uint64_t seed = 42;
  // false for a plain .sumocfg that sets no seed and a command line without --seed: SUMO keeps
  // its own (23423, or a random one under <random>), and the smart-car draw takes 23423
  bool passSeed = true;
  std::optional<double> end;
  std::optional<double> demandScale;  // SUMO --scale
  bool validateSsm = false;
  std::string collisionAction = "warn";
  std::optional<double> collisionMinGapFactor;  // SUMO --collision.mingap-factor
  std::vector<std::string> sumoArgs;
  std::optional<std::filesystem::path> out;
};

// Every key a scenario YAML accepts, dotted ("brake.deceleration"): the reader checks files
// against it, and `stsim batch` may sweep any of them.
const std::vector<std::string>& scenarioKeys();

// Reads a scenario YAML, or wraps a .sumocfg with default settings. Throws ScenarioError.
Scenario loadScenario(const std::filesystem::path& path);

// The input files a .sumocfg names (net-file, route-files, additional-files), resolved against its
// directory. Throws ScenarioError if the config is unreadable, names no network, a named file
// does not exist, or a route or additional file holds what SUMO would stop on without naming the
// file: a vehicle (or flow) id given twice, a vType whose mass is not a positive number (each
// named file:line).
struct SumoConfigFiles {
  std::filesystem::path net;
  std::vector<std::filesystem::path> routes;
  std::vector<std::filesystem::path> additionals;
  std::optional<double> stepLength;  // s
  std::optional<double> end;         // s
};
SumoConfigFiles checkSumoConfig(const std::filesystem::path& sumocfg);

// SUMO's options for a scenario: -c, --seed, --end, --collision.action, quiet console, extras.
std::vector<std::string> sumoArguments(const Scenario& s);

}  // namespace st::cosim
