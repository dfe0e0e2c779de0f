#pragma once
// The calling thread's CPU time (s, from an arbitrary origin), for what a stage, a step or a run
// costs: on a shared machine wall time would measure the neighbours. POSIX's per-thread clock;
// the core keeps it as Box2D's keeps the timer its b2Profile is filled with.
#include <time.h>

namespace st {

inline double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace st
