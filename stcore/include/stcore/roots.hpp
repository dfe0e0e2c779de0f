#pragma once
// Real roots of low-degree polynomials, computed without catastrophic cancellation.
#include <array>

namespace st {

struct QuadraticRoots {
  int count = 0;                    // 0, 1 or 2 real roots
  std::array<double, 2> root{};     // ascending
};

// Roots of a*t^2 + b*t + c = 0. Uses q = -(b + sign(b) sqrt(disc)) / 2, roots q/a and c/q,
// so the root of small magnitude is not lost to cancellation. a == 0 degrades to linear.
QuadraticRoots solveQuadratic(double a, double b, double c);

struct PolynomialRoots {
  int count = 0;
  std::array<double, 4> root{};     // ascending, real roots only
};

// Real roots of a quartic c4 t^4 + c3 t^3 + c2 t^2 + c1 t + c0 in [lo, hi], by isolating
// intervals with the derivative's roots and bisection-safeguarded Newton. Robust for the
// near-degenerate cases of decelerating balls (tangency, double roots).
PolynomialRoots solveQuarticInInterval(double c4, double c3, double c2, double c1, double c0,
                                       double lo, double hi);

// Same for a cubic.
PolynomialRoots solveCubicInInterval(double c3, double c2, double c1, double c0, double lo,
                                     double hi);

}  // namespace st
