#pragma once
// How many random cases a brute-force reference test runs: n, or n times STSIM_TEST_SCALE (a
// fraction in (0, 1]) when that is set. CI's sanitizer run sets it: there the point is memory
// and undefined behaviour along the same code paths, and the full count runs in the README's test
// command. A test scales its "not all misses" floors with the same function, so every check
// keeps its meaning.
#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace st::test {

inline double caseScale() {
  static const double scale = [] {
    const char* s = std::getenv("STSIM_TEST_SCALE");
    const double v = s ? std::atof(s) : 1.0;
    return v > 0.0 && v <= 1.0 ? v : 1.0;
  }();
  return scale;
}

inline int scaledCount(int n) { return std::max(1, static_cast<int>(std::ceil(n * caseScale()))); }

}  // namespace st::test
