#pragma once
// The stopping study: does a STOP that really brakes the arm prevent contact, as a function of
// the monitor's safe time against the arm's stopping time? Courses: the shipped scenarios and
// seeded random two-Panda courses (bases, start and goal poses, timing drawn per course).
// Contact is an exact capsule distance <= 0 between any tested pair (no growth).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <starm/scenario.hpp>

namespace st::arm {

// Course `index` of the random family for `seed`: two Pandas reaching towards each other.
Scenario randomCourse(std::uint64_t seed, int index);

struct CourseOutcome {
  bool contact = false;
  double firstContact = 0.0;  // s, when contact (else 0)
  double minDistance = 0.0;   // m, smallest exact separation of a tested pair over the run
  bool contactWithMoving = false;  // the first contact involves a moving obstacle
  std::uint64_t cycles = 0;
  std::uint64_t stops = 0;
};

// Runs the scenario open or closed loop and watches every cycle's nearest tested pair.
CourseOutcome runCourse(const Scenario& s, bool closedLoop);

struct StudyConfig {
  int randomCourses = 200;
  std::uint64_t seed = 1;
  double stoppingTime = BrakeConfig{}.stoppingTime;  // s, the arms' real braking (braking.stopping_time for every course)
  // the monitor's stopping term (safe time = cycle + reaction + this), one row each
  std::vector<double> assumedStopping{0.0, 0.025, 0.05, 0.075, 0.1, 0.15, 0.2, 0.3};
  std::vector<std::string> shipped;  // scenario files run besides the random courses
};

struct StudyRow {
  double assumedStopping = 0.0;
  double safeTime = 0.0;  // s (of the random courses: cycle + reaction + assumed stopping)
  double needed = 0.0;    // s, stopping time + delay + one cycle
  int courses = 0;
  int contactsOpen = 0, contactsClosed = 0;
  int contactsClosedMoving = 0;  // of those, a moving obstacle ran into a braking / stopped arm
  double minDistanceClosed = 0.0;   // m, worst course
  double medianMinDistanceClosed = 0.0;
  std::vector<std::string> failures;  // courses with a closed-loop contact (up to 5 named)
};

struct ShippedRow {
  std::string name;
  double safeTime = 0.0;
  CourseOutcome open, closed;
};

struct StudyResult {
  std::vector<StudyRow> rows;
  std::vector<ShippedRow> shipped;  // each at its own safety terms
  int randomContactsOpen = 0;       // random courses that touch in open loop
};

StudyResult stoppingStudy(const StudyConfig& cfg);

// Persons beside working arms, closed loop: what a response (binary STOP or speed scaling) does
// to contacts, separation and the arms' task progress.
struct CoexistenceOutcome {
  std::uint64_t cycles = 0;
  std::uint64_t contacts = 0;      // arm cycles with a person capsule touching a moving arm capsule
  std::uint64_t contactsWithinLimit = 0, contactsAboveLimit = 0;  // of those, by the touched regions' PFL limits
  std::uint64_t pflCycles = 0;     // arm cycles below S_p allowed by power and force limiting (pfl)
  std::uint64_t violations = 0;    // arm cycles below S_p at the arm's speed without a STOP verdict
  std::uint64_t stopCycles = 0, scaledCycles = 0;
  int stops = 0;                   // STOPs the drives obeyed
  double minSeparation = 0.0;      // m, person to arm over the run
  double minSlack = 0.0;           // m, smallest separation - S_p over the run (negative: below S_p)
  double progress = 0.0;           // task progress: the arms' mean program time over the clock time
  double duration = 0.0;           // s, clock time of the run
};
// One scenario with its persons under the given response. onCycle (if given) sees every cycle.
CoexistenceOutcome runCoexistence(Scenario s, SsmResponse response,
                                  const std::function<void(const Monitor&, const SeparationMonitor&)>& onCycle = {});
// The reference: the same closed loop with the persons taken out, the task at its own pace (progress
// 1 unless the arms STOP each other). What no response to a person can beat: a response's time
// for the same work over this one is what the person costs it.
CoexistenceOutcome runWithoutPersons(Scenario s);
// One cycle's persons: posed at the monitor's time, the SSM verdicts, and (closed loop) the
// drives' response, the monitor's STOPs merged with the SSM's.
void separationStep(const Monitor& m, PersonSet& persons, SeparationMonitor& ssm, ClosedLoopSensor* drive);

}  // namespace st::arm
