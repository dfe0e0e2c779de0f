#pragma once
// Sensor input (§3.2): a stream of joint readings `t, arm, q[n], qdot[n]`. The source is an
// interface so a recorded trace, a scripted motion, or (later) a network feed can drive the
// monitor. Every reading carries where it came from, for error messages.
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <starm/arm.hpp>

namespace st::arm {

// Bad input at a boundary (trace line, YAML key); the message starts with the location.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Reading {
  double t = 0.0;
  int arm = -1;
  std::vector<double> q;
  std::vector<double> qdot;
  std::string where;  // "trace.csv:12" or "scenario.yaml: arms[0].waypoints"
};

class SensorSource {
 public:
  virtual ~SensorSource() = default;
  // Fills the next reading; false at the end of the stream. Throws InputError on malformed input.
  virtual bool next(Reading& r) = 0;
};

// CSV lines `t, arm, q1..qn, qdot1..qdotn`; arm by name; '#' comments and a header line allowed.
// One arm has one state at one time: a second line for it at the same time that differs is an
// InputError naming both lines; the same line repeated is read once.
class CsvSensor final : public SensorSource {
 public:
  CsvSensor(const std::string& path, std::vector<std::string> armNames, std::vector<int> dofs);
  bool next(Reading& r) override;

 private:
  std::ifstream in_;
  std::string path_;
  std::vector<std::string> names_;
  std::vector<int> dofs_;
  int line_ = 0;
  struct Last {
    bool seen = false;
    double t = 0.0;
    std::vector<double> q, qdot;
    int line = 0;
  };
  std::vector<Last> last_;  // per arm, its latest reading
};

// Piecewise-linear joint motion through waypoints, sampled every cycle: q interpolated, qdot
// the slope of the current piece (zero after the last waypoint).
struct Waypoint {
  double t = 0.0;
  std::vector<double> q;
};
struct Script {
  int arm = -1;
  std::vector<Waypoint> waypoints;  // increasing t
  std::string where;                // YAML key, for messages
};

class WaypointSensor final : public SensorSource {
 public:
  WaypointSensor(std::vector<Script> scripts, double period, double duration);
  bool next(Reading& r) override;

 private:
  std::vector<Script> scripts_;
  double period_;
  double duration_;
  long step_ = 0;
  std::size_t script_ = 0;
};

// Checks a reading against its arm: joint count, finite values, joint limits.
void validateReading(const ArmModel& m, const Reading& r);
// The same on raw joint values (dof each), allocation-free unless it throws; `where` names the
// reading in the message.
void validateJointState(const ArmModel& m, const double* q, const double* qdot, std::string_view where);

}  // namespace st::arm
