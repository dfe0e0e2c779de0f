#pragma once
// The report's evaluation (§5.1, Fig. 13) redone: collision checks against the space's
// decomposition factor, then the same question for 100 to 10000 balls.
#include <cstdint>
#include <ostream>
#include <vector>

#include <stpool/scenario.hpp>

namespace st::pool {

struct StudyRun {
  std::uint64_t checks = 0;   // ball-ball predictions (the report's collision checks)
  std::uint64_t events = 0;   // simulator events, space boundary crossings included
  std::uint64_t collisions = 0;  // ball-ball, ball-cushion and pocket events
  double wallSeconds = 0.0;
  double cpuSeconds = 0.0;    // this thread's CPU time: the wall time on an idle core, without preemption
};

// 15 balls at seeded random places on a closed 9-ft table, `mobile` of them moving at `speed`,
// run for `duration` s on the given space.
StudyRun runFig13Case(int mobile, const SpaceSpec& space, std::uint64_t seed, double duration = 10.0,
                      double speed = 1.0);

// n balls, all moving at 1 m/s, in a square box sized for 10 % area coverage, for `duration` s.
StudyRun runBoxCase(int n, const SpaceSpec& space, std::uint64_t seed, double duration);

// Prints both tables (takes about a minute on one core).
void printFig13Study(std::ostream& os);

}  // namespace st::pool
