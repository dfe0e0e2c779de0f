#pragma once
// Closed loop: a STOP halts the arm that received it. Each arm follows its nominal motion (the
// scripted or recorded readings) in its own program time tau; a STOP makes the program clock
// slow down linearly (ds/dt = -1 / stopping time, s = dtau/dt) until it stands, so the arm stays on
// its path and every joint decelerates at |qdot_nominal| / stopping time (a path-maintaining stop
// with power kept: IEC 60204-1 stop category 2). A joint moving at w comes to rest w * delay + w * T / 2 after the
// STOP's braking command. The arm stays stopped until the resume rule lets it go: never, or once
// the threat has been clear for a settable time; it then ramps back up at the same rate.
#include <deque>
#include <limits>
#include <memory>
#include <vector>

#include <starm/monitor.hpp>
#include <starm/sensor.hpp>

namespace st::arm {

class Monitor;
class SeparationMonitor;

struct BrakeConfig {
  // the defaults follow the monitor's safety terms (settings: braking.* follows safety.*)
  double stoppingTime = SafetyConfig{}.stoppingTime;  // s, full speed to rest (used when deceleration is 0)
  double deceleration = 0.0;   // rad/s^2, > 0: the fastest joint brakes at this; stopping time from it
  double delay = SafetyConfig{}.reactionTime;  // s, STOP cycle to the start of braking (at least the next reading)
  // resume once no warning for this long (s); infinity: never
  double resumeAfter = std::numeric_limits<double>::infinity();
  bool resumes() const { return resumeAfter < std::numeric_limits<double>::infinity(); }
};

// Program-clock speed s(t) = clamp(s0 + rate (t - t0), 0, 1) for t >= t0 (s0 before): a ramp.
struct Ramp {
  double t0 = 0.0;
  double s0 = 1.0;
  double rate = 0.0;  // 1/s; negative brakes, positive resumes
  double at(double t) const;
  // integral of s over [a, b], exact
  double integral(double a, double b) const;
};

// Scaled: the program speed follows a speed factor below 1 (speed and separation monitoring).
enum class DriveMode { Following, Braking, Stopped, Resuming, Scaled };

// One arm's drive state (pure: no monitor, no sensor), so the profile can be tested on its own.
class ArmDrive {
 public:
  explicit ArmDrive(BrakeConfig cfg = {}) : cfg_(cfg) {}

  // Program time at cycle time t (t not decreasing); first call starts the clock with tau = t.
  double advance(double t);
  double speed() const { return s_; }  // s at the last advance
  // The program speed a STOP observed at the last advance would brake from (it is held until
  // braking starts `delay` later): s now while following, scaled or braking; on a resume ramp the
  // ramp's speed at that start; 0 stopped.
  double brakingSpeed() const;
  double tau() const { return tau_; }
  DriveMode mode() const { return mode_; }
  // The monitor's verdict of the cycle at t: warned (a threat), stop (STOP held). `rate` is the
  // largest nominal joint rate now (rad/s), used when braking by deceleration. blocked: a graded
  // check (speed scaling) allows no motion now; a stopped arm does not resume while it holds.
  void observe(double t, bool warned, bool stop, double rate, bool blocked = false);
  // Speed scaling: from `delay` after the cycle at t the program speed heads for `factor` (0..1),
  // changing at 1 / stoppingTime per second, the braking rate (a scaled arm is one that braked
  // part way, so its speed is never above the ramp a STOP would have made). A STOP overrides it;
  // a stopped arm goes again only by the resume rule. factor 1 lets it back to following.
  void limit(double t, double factor);
  // stopped and no rule will resume it
  bool heldForGood() const { return mode_ == DriveMode::Stopped && !cfg_.resumes(); }
  int stops() const { return stops_; }
  int resumes() const { return resumes_; }

 private:
  BrakeConfig cfg_;
  DriveMode mode_ = DriveMode::Following;
  Ramp ramp_;
  bool started_ = false;
  double last_ = 0.0;  // time of the last advance
  double tau_ = 0.0;
  double lag_ = 0.0;   // t - tau while following
  double s_ = 1.0;
  // Scaled: the factor the speed heads for, and factors still on their way (effective time, factor)
  double target_ = 1.0;
  std::deque<std::pair<double, double>> targets_;
  void advanceScaled(double t);
  double lastThreat_ = -std::numeric_limits<double>::infinity();
  int stops_ = 0, resumes_ = 0;
};

// A sensor source in closed loop: the underlying readings are the nominal motion; each arm's
// reading at cycle time t is its nominal motion at its program time, rates scaled by s. Call
// observe(monitor, t) after every cycle (the run's onCycle does it). Nominal readings are
// checked as they arrive (validateReading), so bad input is named where it is in the trace;
// a model without joints (a remote client knows only the joint count) skips the check.
class ClosedLoopSensor final : public SensorSource {
 public:
  ClosedLoopSensor(std::unique_ptr<SensorSource> nominal, std::vector<ArmModel> models, BrakeConfig cfg);
  bool next(Reading& r) override;
  // With speed and separation monitoring: its STOP counts as the monitor's, its factor scales the
  // arm. Under the binary STOP response a person's STOP is a threat like the monitor's: the arm
  // resumes `braking.resume` after the last. Under a graded one (scaling, pfl) it is not: the arm
  // resumes as soon as the factor is above 0 again, up the factor's ramp (the factor grows with
  // the separation, so there is nothing to chatter); the monitor's threats still hold it.
  void observe(const Monitor& m, double t, const SeparationMonitor* ssm = nullptr);
  // The same from a verdict that came another way (the network): warned, STOP held; blocked: a
  // graded check allows no motion (ArmDrive::observe).
  void observeArm(int arm, double t, bool warned, bool stop, bool blocked = false);
  // A speed factor for the arm from the cycle at t (ArmDrive::limit).
  void limitArm(int arm, double t, double factor);
  const ArmDrive& drive(int arm) const { return arms_[arm].drive; }

 private:
  struct Sample {
    double t;
    std::vector<double> q, qdot;
  };
  struct ArmFeed {
    ArmDrive drive;
    std::vector<Sample> buffer;  // nominal samples from the one at or before tau on
    std::size_t head = 0;        // first live sample in buffer
    bool seen = false;
  };
  void sampleAt(ArmFeed& f, double tau, Reading& r) const;

  std::unique_ptr<SensorSource> nominal_;
  std::vector<ArmModel> models_;
  std::vector<ArmFeed> arms_;
};

}  // namespace st::arm
