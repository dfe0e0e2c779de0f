#pragma once
// The report's evaluation (§5.1, Fig. 13) redone: collision checks against the space's
// decomposition factor, then the same question for 100 to 10000 balls.
#include <cstdint>
#include <ostream>
#include <vector>

#include <stcore/simulator.hpp>
#include <stpool/scenario.hpp>

namespace st::pool {

struct StudyRun {
  std::uint64_t checks = 0;   // ball-ball predictions (the report's collision checks)
  // The report's counting (§2, "at the end of every simulation step collision times are
  // calculated between various interacting objects within a space"): a global minimum step from
  // one event to the next, and after each, every pair within a space with a ball moving in it.
  std::uint64_t reportChecks = 0;
  // and in the same steps, one check per moving ball and leaf it is in, against the leaf's walls
  std::uint64_t reportBoundaryChecks = 0;
  std::uint64_t events = 0;   // simulator events, space boundary crossings included
  std::uint64_t collisions = 0;  // ball-ball, ball-cushion and pocket events
  double wallSeconds = 0.0;
  double cpuSeconds = 0.0;    // this thread's CPU time: the wall time on an idle core, without preemption
};

// 15 balls at seeded random places on a closed 9-ft table, `mobile` of them moving at `speed`,
// run for `duration` s on the given space.
StudyRun runFig13Case(int mobile, const SpaceSpec& space, std::uint64_t seed, double duration = 10.0,
                      double speed = 1.0);

// The same case with StudyRun::reportChecks counted as well (a second run of the same shot).
StudyRun runFig13CaseCounted(int mobile, const SpaceSpec& space, std::uint64_t seed, double duration = 10.0);

// n balls, all moving at 1 m/s, in a square box sized for 10 % area coverage, for `duration` s.
StudyRun runBoxCase(int n, const SpaceSpec& space, std::uint64_t seed, double duration);

// The report's counting after one event: over every leaf of the space (no space: one region of
// every ball), the pairs in it of which at least one ball moves.
std::uint64_t reportChecksNow(const Simulator<2>& sim);
// And the checks against the spaces' boundaries: one per moving ball and leaf it is in (none
// without a space).
std::uint64_t reportBoundaryChecksNow(const Simulator<2>& sim);

enum class Counting { Events, Report };

// Prints the study: Fig. 13 in the event-driven counting (with Counting::Report, the report's
// counting beside it), then the same question for 100 to 10000 balls (about a minute on one core).
void printFig13Study(std::ostream& os, Counting counting = Counting::Events);

}  // namespace st::pool
