#pragma once
// Speed and separation monitoring (ISO/TS 15066:2016 §5.5.4): every cycle, per arm and person,
// the protective separation distance
//
//   S_p = S_h + S_r + S_s + C + Z_d + Z_r                                         formula (1)
//
// against the current separation (the smallest exact distance between the person's capsules
// and the arm's), and a verdict: the speed factor (0..1 of the arm's top speed) that keeps S_p,
// or STOP where none does. With constant speeds and the closed loop's path-maintaining stop (the
// program speed falls linearly to 0 over the stopping time T_s, starting T_r after the cycle):
//
//   S_h = v_h (T_r + T_s)   the person's motion while the robot reacts and stops,  formula (2)
//   S_r = v_r T_r           the robot's motion while it reacts,                    formula (3)
//   S_s = v_r T_s / 2       the robot's motion while it stops (linear ramp),        formula (4)
//
// v_h the person's approach speed (ISO 13855: 1.6 m/s walking, 2.0 m/s a hand), v_r the robot's
// speed (the fastest capsule end point of the arm, whatever its direction: an upper bound on the
// speed towards the person), C the intrusion distance (ISO 13855: reach beyond what the sensor
// sees), Z_d the person's position uncertainty (the tracker), Z_r the robot's (its encoders and
// capsule fit). The person's capsules grown by S_h are their reachable set over T_r + T_s.
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <starm/person.hpp>

namespace st::arm {

class Monitor;

enum class SsmResponse {
  Stop,     // binary: STOP while the separation is below S_p at the arm's top speed
  Scaling,  // graded: the largest speed factor keeping S_p; STOP only where the present speed breaks S_p
};
const char* toString(SsmResponse r);

struct SsmConfig {
  double bodySpeed = 1.6;           // v_h of the body, m/s (ISO 13855 §6.2: walking)
  double handSpeed = 2.0;           // v_h of a hand, m/s (ISO 13855: hand and arm approach)
  double cycleTime = 0.001;         // T_c, s: the monitor's cycle
  double reactionTime = 0.011;      // T_r, s: a cycle to see + the reaction until braking starts
  double stoppingTime = 0.2;        // T_s, s: the drive's stopping time (braking.stopping_time)
  double intrusion = 0.0;           // C, m: the body capsules are the person, nothing unseen beyond
  double personUncertainty = 0.05;  // Z_d, m: the skeleton tracker's error
  double robotUncertainty = 0.01;   // Z_r, m: joint encoders and capsule fit
  double robotSpeed = 1.0;          // m/s, the arm's top speed: speed factor 1
  SsmResponse response = SsmResponse::Scaling;
};

// The terms of formula (1), each in metres.
struct SeparationTerms {
  double sh = 0.0, sr = 0.0, ss = 0.0, c = 0.0, zd = 0.0, zr = 0.0;
  double total() const { return sh + sr + ss + c + zd + zr; }
  const char* dominant() const;  // "S_h", "S_r", ... the largest term
};

// Formulae (1)-(4) for a person part at speed vh and the robot at speed vr.
SeparationTerms protectiveSeparation(const SsmConfig& c, double vh, double vr);
// The largest robot speed (m/s) that keeps S_p at the next cycle: after one more cycle T_c the
// person may be vh T_c and the robot v T_c closer, so S_p(v) <= d - (vh + v) T_c:
//   v = (d - vh T_c - S_p(vh, 0)) / (T_r + T_s / 2 + T_c).
// Negative: no speed does. The drive slows at its braking rate after T_r, so a person coming on
// fast can still outrun the factor: then S_p at the arm's present speed breaks and the verdict
// is STOP, in time by formula (1).
double allowedRobotSpeed(const SsmConfig& c, double vh, double d);

struct SsmVerdict {
  double separation = std::numeric_limits<double>::infinity();  // m, nearest person capsule to the arm
  double required = 0.0;      // m, S_p of the binding pair (the pair of smallest distance - S_p)
  double slack = std::numeric_limits<double>::infinity();  // m, that pair's distance - S_p
  SeparationTerms terms;      // of the binding pair
  double robotSpeed = 0.0;    // m/s, v_r now
  double allowedSpeed = std::numeric_limits<double>::infinity();  // m/s
  double factor = 1.0;        // speed factor for the arm (0..1 of SsmConfig::robotSpeed)
  bool stop = false;
  bool violated = false;      // separation < S_p at the arm's present speed
  int person = -1, part = -1, armBody = -1;  // the binding pair (-1: no person present)
};

struct SsmCounters {
  std::uint64_t cycles = 0;
  std::uint64_t stopCycles = 0;    // arm cycles with a STOP verdict
  std::uint64_t scaledCycles = 0;  // arm cycles with 0 < factor < 1
  std::uint64_t violations = 0;    // arm cycles with separation < S_p and no STOP verdict
  std::uint64_t contacts = 0;      // arm cycles with a person capsule touching a moving arm capsule
  double minSeparation = std::numeric_limits<double>::infinity();
};

// The persons of a scenario: their names and where each is at a time.
class PersonSet {
 public:
  void add(std::string name, std::unique_ptr<PersonTrack> track);
  int size() const { return static_cast<int>(names_.size()); }
  const std::string& name(int i) const { return names_[i]; }
  // Poses every person at t; present(i) false when its track has nothing for t.
  void pose(double t);
  const Skeleton& skeleton(int i) const { return skeletons_[i]; }
  bool present(int i) const { return present_[i] != 0; }

 private:
  std::vector<std::string> names_;
  std::vector<std::unique_ptr<PersonTrack>> tracks_;
  std::vector<Skeleton> skeletons_;
  std::vector<char> present_;
};

class SeparationMonitor {
 public:
  SeparationMonitor(SsmConfig cfg, int arms);
  // The cycle's verdicts from the monitor's arm capsules (at its cycle time) and the posed persons.
  void cycle(const Monitor& m, const PersonSet& persons);
  const SsmVerdict& verdict(int arm) const { return verdicts_[arm]; }
  const SsmConfig& config() const { return cfg_; }
  const SsmCounters& counters() const { return counters_; }

 private:
  SsmConfig cfg_;
  std::vector<SsmVerdict> verdicts_;
  SsmCounters counters_;
};

}  // namespace st::arm
