#pragma once
// Scenario files (YAML) and the run loop that drives a monitor from a sensor source.
//
// The scalar keys of safety, braking, octree and ssm are the settings table's (starm/settings.hpp,
// docs/arm_settings.md: ranges, defaults, docs); the shape of a file:
//   safety: {cycle_time: 0.001, reaction_time: 0.01, stopping_time: 0.2, min_separation: 0.02, horizon: 0.3}
//   octree: {kind: tree|cells|single, decomposition_factor: 4, max_depth: 8, margin: 0.05, cell_size: 0.25,
//            bounds: {min: [..], max: [..]}}
//   models: {name: {convention: modified|classic, joints: [{a, alpha, d, offset, limits: [lo, hi], max_rate}],
//                   flange: {xyz, rpy}, capsules: [{body, a: [x,y,z], b: [x,y,z], radius}]}
//                   | {urdf: file.urdf, allow: [[link, link]]}}     (starm/urdf.hpp)
//   arms: [{name, model: panda|iiwa14|<models key>, base: {xyz, rpy},
//           allow: [[i|link, j|link|obstacle:NAME]], check: [[i, j]], waypoints: [{t, q: [...]}]}]
//   trace: file.csv            (instead of waypoints; relative to the scenario file)
//   duration: 4.0              (scripted motion length; default the last waypoint)
//   obstacles: [{name, sphere: {center, radius} | capsule: {a, b, radius} |
//                box: {center, half_extents, rpy}, velocity: [..]}]
//   random_obstacles: {count, seed, min: [..], max: [..], radius: [lo, hi], keep_out: [{center, radius}]}
//   braking: {stopping_time: 0.2 | deceleration: 8.0, delay: 0.01, resume: never | 0.5}   (closed loop)
//   persons: [{name, start: {xy: [x, y], heading}, script: [{walk: {to: [x, y], speed}} |
//              {reach: {hand: right|left, to: [x, y, z], speed}} | {wait: s}]} | {name, trace: file.csv},
//              sensor: {period, jitter, drift}]
//   ssm: {response: scaling|stop|pfl, body_speed, hand_speed, intrusion, person_uncertainty,
//         robot_uncertainty, robot_speed, arm_mass, payload}
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <starm/drive.hpp>
#include <starm/monitor.hpp>
#include <starm/sensor.hpp>
#include <starm/settings.hpp>
#include <starm/ssm.hpp>

namespace st::arm {

struct Scenario {
  std::string file;
  std::vector<ArmInstance> arms;
  std::vector<Obstacle> obstacles;
  SafetyConfig safety;
  BroadphaseConfig broad;
  std::string tracePath;        // CSV sensor trace, or
  std::vector<Script> scripts;  // scripted motion
  double duration = 0.0;
  // closed loop: how a STOPped arm brakes and resumes (defaults: safety.stopping_time,
  // safety.reaction_time, never resume)
  BrakeConfig braking;
  // persons in the cell and speed and separation monitoring (T_r = cycle + braking.delay,
  // T_s = braking.stopping_time: the drive's own stopping)
  struct Person {
    std::string name;
    PersonScript script;  // or
    std::string trace;    // CSV person trace (relative paths resolved)
    // its tracker's period and jitter (s) over the service: a pose older than period + jitter is
    // stale (every arm STOPs); 0: the obstacles' freshness (reaction + cycle)
    double sensorPeriod = 0.0, sensorJitter = 0.0;
    double sensorDrift = 0.0;  // how far its clock may run from the service's (ArmInstance::sensorDrift)
  };
  std::vector<Person> persons;
  SsmConfig ssm;
};

// Throws InputError naming the file, line and key. The overrides set keys of the settings table
// (starm/settings.hpp) over the file's, with the same checks; a bad one throws SettingError (the
// front end names its option).
Scenario loadScenario(const std::string& path, const std::vector<SettingOverride>& overrides = {});
std::unique_ptr<SensorSource> makeSensor(const Scenario& s);
Monitor makeMonitor(const Scenario& s);
// The scenario's persons, scripted or traced (a trace is read here: InputError naming its line).
PersonSet makePersons(const Scenario& s);
// The scenario's sensor in closed loop (drive.cpp): STOP brakes the arm per s.braking.
std::unique_ptr<ClosedLoopSensor> makeClosedLoopSensor(const Scenario& s);

// Deadlines: each cycle's compute time (readings applied + detection + persons) against a
// budget, by default the cycle time. A miss is counted and kept with its time (the first
// kMaxKept); a run with misses is flagged, not failed.
struct DeadlineWatch {
  static constexpr std::size_t kMaxKept = 10000;
  double budgetUs = 1000.0;
  std::uint64_t cycles = 0;
  std::uint64_t missed = 0;
  double worstUs = 0.0;
  double worstT = 0.0;  // s, cycle time of the worst cycle
  std::vector<std::pair<double, double>> misses;  // (t s, compute us)
  void see(double t, double us);
};

struct RunStats {
  std::uint64_t cycles = 0;
  std::vector<double> latencyUs;  // per cycle: readings applied + detection
  std::vector<double> firstStop;  // per arm, time of the first STOP (NaN if none)
  bool interrupted = false;       // stopRequested ended the run before the stream did
};

// Readings with equal time form one cycle. After each cycle onCycle(monitor) sees its warnings.
// stopRequested (if given) is asked before every cycle; true ends the run there (a signal, say).
// On bad input the exception propagates; stats holds the cycles completed so far.
void run(Monitor& m, SensorSource& src, RunStats& stats, const std::function<void(const Monitor&)>& onCycle,
         const std::function<bool()>& stopRequested = {});

double percentile(std::vector<double> v, double p);

}  // namespace st::arm
