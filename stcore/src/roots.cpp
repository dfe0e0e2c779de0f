#include <stcore/roots.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <stcore/tolerances.hpp>

namespace st {

QuadraticRoots solveQuadratic(double a, double b, double c) {
  QuadraticRoots r;
  if (a == 0.0) {
    // linear: b t + c = 0. Only an exactly zero a: a merely small one needs no special case (the
    // small root c/q below stays exact to rounding), and comparing a with b and c, which carry
    // other units, would drop real roots.
    if (b != 0.0) {
      r.count = 1;
      r.root[0] = -c / b;
    }
    return r;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return r;
  if (disc == 0.0) {
    r.count = 2;
    r.root[0] = r.root[1] = -0.5 * b / a;
    return r;
  }
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  double r1 = q / a;
  double r2 = (q != 0.0) ? c / q : -r1;
  if (!std::isfinite(r1)) {
    // a so small that q / a overflows: that root is beyond any horizon
    r.count = 1;
    r.root[0] = r2;
    return r;
  }
  if (r1 > r2) std::swap(r1, r2);
  r.count = 2;
  r.root = {r1, r2};
  return r;
}

namespace {

// Evaluates a polynomial given by coefficients from highest degree down.
template <std::size_t N>
double horner(const std::array<double, N>& c, double t) {
  double v = 0.0;
  for (double ci : c) v = v * t + ci;
  return v;
}

// The one root of a polynomial that changes sign on [lo, hi]: Newton steps kept inside the
// bracket, bisection when Newton leaves it or stalls.
template <std::size_t N>
double refineBracketed(const std::array<double, N>& c, double lo, double hi) {
  std::array<double, N - 1> d{};
  for (std::size_t i = 0; i + 1 < N; ++i) d[i] = c[i] * static_cast<double>(N - 1 - i);
  double flo = horner(c, lo);
  double t = 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const double f = horner(c, t);
    if (f == 0.0) return t;
    if ((f < 0.0) == (flo < 0.0)) {
      lo = t;
      flo = f;
    } else {
      hi = t;
    }
    const double df = horner(d, t);
    double next = (df != 0.0) ? t - f / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const double resolution = tol::kRootResolution * std::max(1.0, std::abs(t));
    if (std::abs(next - t) <= resolution || hi - lo <= resolution)
      return next;
    t = next;
  }
  return t;
}

// Real roots in [lo, hi] of a polynomial, given the sorted critical points (roots of its
// derivative) in that interval: between consecutive critical points it is monotone, so each
// piece holds at most one root. Double roots (touching) show up as a critical value of zero.
template <std::size_t N>
PolynomialRoots rootsBetweenCriticalPoints(const std::array<double, N>& c, const double* crit,
                                           int ncrit, double lo, double hi) {
  PolynomialRoots out;
  std::array<double, 6> knots{};
  int nk = 0;
  knots[nk++] = lo;
  for (int i = 0; i < ncrit; ++i)
    if (crit[i] > lo && crit[i] < hi) knots[nk++] = crit[i];
  knots[nk++] = hi;
  // p(t) counts as zero within the rounding of its evaluation (Horner: ~2n eps sum |c_i| |t|^i)
  // plus what p can change over the solver's resolution in t (tol::kRootResolution, as in
  // refineBracketed), since knots are critical points found to that resolution; both bounded by
  // the majorant sum |c_i| s^i and its derivatives at s = |t| + dt. A fixed fraction of the largest
  // coefficient is wrong both ways: away from |t| ~ 1 the rounding exceeds it and a double root
  // splits in two or vanishes.
  auto isZero = [&](double t, double f) {
    const double dt = tol::kRootResolution * std::max(1.0, std::abs(t)), s = std::abs(t) + dt;
    double m = 0.0, m1 = 0.0, m2 = 0.0;
    for (double ci : c) {
      m2 = m2 * s + 2.0 * m1;
      m1 = m1 * s + m;
      m = m * s + std::abs(ci);
    }
    const double rounding = 2.0 * static_cast<double>(N) * std::numeric_limits<double>::epsilon() * m;
    return std::abs(f) <= rounding + m1 * dt + 0.5 * m2 * dt * dt;
  };
  auto push = [&](double t) {
    if (out.count > 0 && std::abs(out.root[out.count - 1] - t) <= tol::kRootMerge * std::max(1.0, std::abs(t))) return;
    if (out.count < 4) out.root[out.count++] = t;
  };
  for (int i = 0; i + 1 < nk; ++i) {
    const double a = knots[i], b = knots[i + 1];
    const double fa = horner(c, a), fb = horner(c, b);
    if (isZero(a, fa)) {
      push(a);
      continue;
    }
    // a zero at b is pushed by the next piece (or below, for hi)
    if ((fa < 0.0) != (fb < 0.0) && !isZero(b, fb)) push(refineBracketed(c, a, b));
  }
  const double fhi = horner(c, hi);
  if (isZero(hi, fhi)) push(hi);
  return out;
}

}  // namespace

PolynomialRoots solveCubicInInterval(double c3, double c2, double c1, double c0, double lo,
                                     double hi) {
  if (c3 == 0.0) {
    PolynomialRoots out;
    const QuadraticRoots q = solveQuadratic(c2, c1, c0);
    for (int i = 0; i < q.count; ++i)
      if (q.root[i] >= lo && q.root[i] <= hi &&
          (out.count == 0 || q.root[i] != out.root[out.count - 1]))
        out.root[out.count++] = q.root[i];
    return out;
  }
  const QuadraticRoots crit = solveQuadratic(3.0 * c3, 2.0 * c2, c1);
  return rootsBetweenCriticalPoints(std::array<double, 4>{c3, c2, c1, c0}, crit.root.data(),
                                    crit.count, lo, hi);
}

PolynomialRoots solveQuarticInInterval(double c4, double c3, double c2, double c1, double c0,
                                       double lo, double hi) {
  if (c4 == 0.0) return solveCubicInInterval(c3, c2, c1, c0, lo, hi);
  // critical points: roots of the derivative cubic, found the same way
  const PolynomialRoots crit =
      solveCubicInInterval(4.0 * c4, 3.0 * c3, 2.0 * c2, c1, lo, hi);
  return rootsBetweenCriticalPoints(std::array<double, 5>{c4, c3, c2, c1, c0}, crit.root.data(),
                                    crit.count, lo, hi);
}

}  // namespace st
