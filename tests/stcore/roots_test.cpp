// Root solvers against independent truth.
// Quadratics: the roots of the exact polynomial (double coefficients taken as exact) bracketed at
// the vertex and bisected in long double; the sign of the discriminant in binary128, where
// products of doubles are exact. A root is accepted
// within a few ulps times its condition number: a cancelling formula fails this by orders of
// magnitude on the cancellation-prone cases.
// Cubics and quartics: built from known roots chosen as small dyadic rationals, so the expanded
// coefficients are exact in double and the known roots (double roots included) are the true roots
// of the polynomial the solver sees.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <stcore/roots.hpp>

namespace st {
namespace {

__extension__ typedef __float128 Quad;  // GCC binary128: 113-bit mantissa
constexpr double kEps = 0x1p-52;

Quad qabs(Quad x) { return x < 0 ? -x : x; }
// Root truth by bisection in long double (64-bit mantissa, 2^11 times finer than double): its
// error is a small fraction of the tolerance below. binary128 would be exact but is ~100x slower.
using Wide = long double;
Wide wideValue(double a, double b, double c, Wide t) { return (Wide(a) * t + Wide(b)) * t + Wide(c); }

// One root of a*t^2+b*t+c on [lo, hi] (values of opposite sign at the ends).
double bisectQuadratic(double a, double b, double c, Wide lo, Wide hi) {
  const bool loNeg = wideValue(a, b, c, lo) < 0;
  for (int it = 0; it < 400; ++it) {
    const Wide mid = (lo + hi) / 2;
    if (mid == lo || mid == hi) break;
    if ((wideValue(a, b, c, mid) < 0) == loNeg) lo = mid;
    else hi = mid;
  }
  return static_cast<double>((lo + hi) / 2);
}

struct TrueQuadratic {
  // 0 or 2 when the sign of the discriminant is beyond the rounding of the double discriminant;
  // -1 when it is not (a tangent double root: 0 or 2 nearly equal roots are both right).
  int count = 0;
  double r[2] = {0, 0};
  double vertex = 0;
  double discSlack = 0;  // rounding bound of b^2 - 4ac computed in double
};

TrueQuadratic trueQuadratic(double a, double b, double c) {
  TrueQuadratic out;
  const Quad disc = Quad(b) * Quad(b) - 4 * Quad(a) * Quad(c);  // exact but for one rounding
  out.discSlack = 4 * kEps * (b * b + 4 * std::abs(a * c));
  const Wide vertex = -Wide(b) / (2 * Wide(a));
  out.vertex = static_cast<double>(vertex);
  if (qabs(disc) <= Quad(out.discSlack)) {
    out.count = -1;
    return out;
  }
  if (disc < 0) return out;
  // Each root lies on its own side of the vertex, within |vertex| + sqrt(|c/a|) of it. A guess
  // only narrows the bracket (for speed); a bracket is kept only if the sign test confirms it, so
  // the truth never rests on a closed formula.
  const Wide reach = std::abs(vertex) + std::sqrt(std::abs(Wide(c) / Wide(a))) + 1;
  const Wide la = a, lb = b, lc = c;
  const Wide ld = std::sqrt(std::max(Wide(0), lb * lb - 4 * la * lc));
  const Wide lq = -0.5L * (lb + (lb < 0 ? -ld : ld));
  Wide guess[2] = {lq / la, lc / lq};
  if (guess[0] > guess[1]) std::swap(guess[0], guess[1]);
  out.count = 2;
  for (int i = 0; i < 2; ++i) {
    const Wide g = guess[i];
    const Wide side = i == 0 ? vertex - reach : vertex + reach;
    out.r[i] = std::numeric_limits<double>::quiet_NaN();
    for (Wide width : {1e-15L, 1e-9L}) {
      const Wide w = std::abs(g) * width + 1e-300L;
      const bool bracketed = (wideValue(a, b, c, g - w) < 0) != (wideValue(a, b, c, g + w) < 0) &&
                             (i == 0 ? g + w <= vertex : g - w >= vertex);
      if (bracketed) {
        out.r[i] = bisectQuadratic(a, b, c, g - w, g + w);
        break;
      }
    }
    if (std::isnan(out.r[i])) out.r[i] = bisectQuadratic(a, b, c, side, vertex);
  }
  return out;
}

// Error bound for a computed root r of a quadratic: a few ulps of the backward error of the
// coefficients and of the discriminant, divided by the slope |p'(r)| (the root's sensitivity).
double rootTolerance(double a, double b, double c, double r) {
  const double slope = std::abs(static_cast<double>(2 * Wide(a) * Wide(r) + Wide(b)));
  const double coeff = std::abs(a) * r * r + std::abs(b * r) + std::abs(c);
  const double discTerm = (b * b + 4 * std::abs(a * c)) / (4 * std::abs(a));
  return 8 * kEps * (coeff + discTerm) / slope + 1e-300;
}

void checkQuadratic(double a, double b, double c) {
  const QuadraticRoots got = solveQuadratic(a, b, c);
  const TrueQuadratic want = trueQuadratic(a, b, c);
  SCOPED_TRACE(::testing::Message() << std::hexfloat << "a=" << a << " b=" << b << " c=" << c);
  if (want.count == -1) {
    // tangent: either no root or two roots at the vertex, within the discriminant's rounding
    ASSERT_TRUE(got.count == 0 || got.count == 2);
    const double spread = std::sqrt(want.discSlack) / std::abs(a) + 8 * kEps * std::abs(want.vertex);
    for (int i = 0; i < got.count; ++i) ASSERT_NEAR(got.root[i], want.vertex, spread);
    return;
  }
  ASSERT_EQ(got.count, want.count);
  if (got.count == 2) {
    ASSERT_LE(got.root[0], got.root[1]);
    for (int i = 0; i < 2; ++i)
      ASSERT_NEAR(got.root[i], want.r[i], rootTolerance(a, b, c, want.r[i])) << "root " << i;
  }
}

double signedMagnitude(std::mt19937_64& rng, int minExp, int maxExp) {
  std::uniform_real_distribution<double> mant(1.0, 10.0);
  std::uniform_int_distribution<int> ex(minExp, maxExp);
  const double v = mant(rng) * std::pow(10.0, ex(rng));
  return (rng() & 1) ? v : -v;
}

TEST(Quadratic, RandomCoefficientsAgainstBisection) {
  std::mt19937_64 rng(11);
  for (int k = 0; k < 100000; ++k) {
    checkQuadratic(signedMagnitude(rng, -20, 20), signedMagnitude(rng, -20, 20), signedMagnitude(rng, -20, 20));
    if (HasFatalFailure()) return;
  }
}

TEST(Quadratic, CancellationProneRootsOfVeryDifferentSize) {
  // roots r1 ~ 10^e1, r2 ~ 10^e2 with e2 - e1 up to 24: b^2 >> 4ac, where the textbook formula
  // loses the small root entirely
  std::mt19937_64 rng(12);
  int checked = 0;
  for (int k = 0; k < 100000; ++k) {
    const double a = signedMagnitude(rng, -3, 3);
    const double r1 = signedMagnitude(rng, -12, 12);
    const double r2 = signedMagnitude(rng, -12, 12);
    checkQuadratic(a, -a * (r1 + r2), a * r1 * r2);
    if (HasFatalFailure()) return;
    ++checked;
  }
  EXPECT_EQ(checked, 100000);
  // one explicit case: roots 1e-9 and 1e9; the textbook formula returns 0 for the small root
  const QuadraticRoots r = solveQuadratic(1.0, -(1e9 + 1e-9), 1.0);
  ASSERT_EQ(r.count, 2);
  EXPECT_NEAR(r.root[0], 1e-9, 1e-9 * 4 * kEps);
  EXPECT_NEAR(r.root[1], 1e9, 1e9 * 4 * kEps);
}

TEST(Quadratic, NearTangentDiscriminant) {
  // b^2 close to 4ac: double root, two close roots, or none
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> rel(-1e-6, 1e-6);
  for (int k = 0; k < 100000; ++k) {
    const double a = signedMagnitude(rng, -6, 6);
    const double r = signedMagnitude(rng, -6, 6);
    const double c = a * r * r * (1.0 + ((k % 4 == 0) ? 0.0 : rel(rng) * std::pow(10.0, -static_cast<double>(k % 10))));
    checkQuadratic(a, -2 * a * r, c);
    if (HasFatalFailure()) return;
  }
}

TEST(Quadratic, DegenerateCases) {
  // a == 0: linear
  QuadraticRoots r = solveQuadratic(0.0, 2.0, -3.0);
  ASSERT_EQ(r.count, 1);
  EXPECT_EQ(r.root[0], 1.5);
  // nothing but a constant: no roots, including the zero polynomial
  EXPECT_EQ(solveQuadratic(0.0, 0.0, 1.0).count, 0);
  EXPECT_EQ(solveQuadratic(0.0, 0.0, 0.0).count, 0);
  // c == 0: one root exactly zero
  r = solveQuadratic(2.0, -6.0, 0.0);
  ASSERT_EQ(r.count, 2);
  EXPECT_EQ(r.root[0], 0.0);
  EXPECT_EQ(r.root[1], 3.0);
  // b == 0: symmetric roots
  r = solveQuadratic(1.0, 0.0, -4.0);
  ASSERT_EQ(r.count, 2);
  EXPECT_EQ(r.root[0], -2.0);
  EXPECT_EQ(r.root[1], 2.0);
  EXPECT_EQ(solveQuadratic(1.0, 0.0, 4.0).count, 0);
  // a tiny against b (parallel motion): solved as linear; the root kept is the small one, the
  // other (~ -b/a) being beyond any horizon
  std::mt19937_64 rng(14);
  for (int k = 0; k < 10000; ++k) {
    const double b = signedMagnitude(rng, -3, 3), c = signedMagnitude(rng, -3, 3);
    const double a = b * 1e-16 * std::uniform_real_distribution<double>(-1, 1)(rng);
    const QuadraticRoots q = solveQuadratic(a, b, c);
    ASSERT_GE(q.count, 1);
    // the true small root, by binary128 bisection between 0 and twice the linear root
    const double lin = -c / b;
    const double want = (a == 0.0) ? lin : bisectQuadratic(a, b, c, 0, 2 * Wide(lin));
    bool found = false;
    for (int i = 0; i < q.count; ++i) found |= std::abs(q.root[i] - want) <= 1e-13 * std::abs(want);
    ASSERT_TRUE(found) << a << " " << b << " " << c;
  }
}

// ---- cubic and quartic from known dyadic roots ------------------------------------------------

struct Poly {
  std::array<double, 5> c{};  // c[0] t^4 + ... + c[4]; exact
  std::vector<double> realRoots;  // distinct, with multiplicity noted below
  std::vector<int> multiplicity;
};

// Multiplies the polynomial (highest degree first, `deg` its degree) by (t - r).
void mulLinear(std::array<double, 5>& c, int& deg, double r) {
  std::array<double, 5> out{};
  // c holds coefficients in the last deg+1 slots
  for (int i = 4 - deg; i <= 4; ++i) {
    out[i - 1] += c[i];
    out[i] -= r * c[i];
  }
  c = out;
  ++deg;
}
void mulQuadratic(std::array<double, 5>& c, int& deg, double p, double q) {  // (t^2 + p t + q)
  std::array<double, 5> out{};
  for (int i = 4 - deg; i <= 4; ++i) {
    out[i - 2] += c[i];
    out[i - 1] += p * c[i];
    out[i] += q * c[i];
  }
  c = out;
  deg += 2;
}

double dyadic(std::mt19937_64& rng, int range) {  // k/8 with |k| <= range
  return static_cast<double>(static_cast<int>(rng() % (2 * range + 1)) - range) / 8.0;
}

// A random polynomial of degree `degree` (3 or 4) with the given multiplicity pattern:
// pattern lists multiplicities of distinct real roots; the rest of the degree is one complex pair.
Poly buildPoly(std::mt19937_64& rng, int degree, const std::vector<int>& pattern) {
  Poly p;
  std::array<double, 5> c{};
  c[4] = static_cast<double>(1 + rng() % 7) * ((rng() & 1) ? 0.5 : -2.0);  // leading coefficient
  int deg = 0;
  int used = 0;
  std::vector<double> roots;
  for (int m : pattern) {
    double r;
    do {
      r = dyadic(rng, 40);
    } while (std::find(roots.begin(), roots.end(), r) != roots.end());
    roots.push_back(r);
    p.realRoots.push_back(r);
    p.multiplicity.push_back(m);
    for (int k = 0; k < m; ++k) mulLinear(c, deg, r);
    used += m;
  }
  if (degree - used == 2) {
    // t^2 + P t + Q with P^2 < 4Q: a complex pair (centre -P/2, half-width sqrt(Q - P^2/4))
    const double centre = dyadic(rng, 40), width = static_cast<double>(1 + rng() % 16) / 8.0;
    mulQuadratic(c, deg, -2 * centre, centre * centre + width * width);
    used += 2;
  }
  EXPECT_EQ(used, degree);
  p.c = c;
  return p;
}

// A simple root r is found to within the evaluation noise of p near r over the slope there:
// 16 eps sum |c_i||r|^i / |p'(r)| (Horner's error bound for degree 4 is ~8 eps sum |c_i||r|^i).
// A root of multiplicity m is a simple root of the (m-1)-th derivative, which is what a solver
// working through critical points finds, so the same bound applies to that derivative.
double polyRootTolerance(const std::array<double, 5>& c, double r, int multiplicity) {
  std::array<double, 5> d = c;  // highest degree first, padded at the front
  for (int k = 1; k < multiplicity; ++k) {
    std::array<double, 5> next{};
    for (int i = 0; i < 4; ++i) next[i + 1] = d[i] * static_cast<double>(4 - i);
    d = next;
  }
  double noise = 0, slope = 0;
  for (int i = 0; i < 5; ++i) noise = noise * std::abs(r) + std::abs(d[i]);
  for (int i = 0; i < 4; ++i) slope = slope * r + d[i] * static_cast<double>(4 - i);
  // plus the solver's stopping width, 1e-15 relative (absolute below 1)
  return 16 * kEps * noise / std::abs(slope) + 4e-15 * std::max(1.0, std::abs(r));
}

void checkPoly(const Poly& p, int degree, double lo, double hi) {
  const PolynomialRoots got = degree == 4
      ? solveQuarticInInterval(p.c[0], p.c[1], p.c[2], p.c[3], p.c[4], lo, hi)
      : solveCubicInInterval(p.c[1], p.c[2], p.c[3], p.c[4], lo, hi);
  std::vector<std::pair<double, int>> want;
  for (std::size_t i = 0; i < p.realRoots.size(); ++i)
    if (p.realRoots[i] >= lo && p.realRoots[i] <= hi) want.push_back({p.realRoots[i], p.multiplicity[i]});
  std::sort(want.begin(), want.end());
  ::testing::Message m;
  m << "coeffs";
  for (double ci : p.c) m << " " << ci;
  m << " interval [" << lo << ", " << hi << "] expected";
  for (auto& w : want) m << " " << w.first << "(x" << w.second << ")";
  m << " got";
  for (int i = 0; i < got.count; ++i) m << " " << got.root[i];
  SCOPED_TRACE(m);
  ASSERT_EQ(got.count, static_cast<int>(want.size()));
  for (int i = 0; i < got.count; ++i) {
    if (i > 0) {
      ASSERT_LT(got.root[i - 1], got.root[i]);
    }
    ASSERT_NEAR(got.root[i], want[i].first, polyRootTolerance(p.c, want[i].first, want[i].second));
  }
}

void runPatterns(int degree, const std::vector<std::vector<int>>& patterns, unsigned seed, int cases) {
  std::mt19937_64 rng(seed);
  for (int k = 0; k < cases; ++k) {
    const auto& pattern = patterns[k % patterns.size()];
    const Poly p = buildPoly(rng, degree, pattern);
    // intervals: mostly covering all roots, sometimes cutting through them, sometimes ending on one
    double lo = -6, hi = 6;
    switch (k % 4) {
      case 1: lo = dyadic(rng, 48) - 1.0 / 16; hi = lo + static_cast<double>(1 + rng() % 64) / 8.0; break;
      case 2: lo = p.realRoots.front(); hi = 6; break;  // a root exactly at lo
      case 3: lo = -6; hi = p.realRoots.back(); break;  // a root exactly at hi
      default: break;
    }
    checkPoly(p, degree, lo, hi);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

TEST(Quartic, SimpleRootsFromKnownRoots) {
  runPatterns(4, {{1, 1, 1, 1}, {1, 1}}, 21, 100000);
}

TEST(Quartic, DoubleRoots) {
  runPatterns(4, {{2, 1, 1}, {1, 2, 1}, {2, 2}, {2}}, 22, 100000);
}

TEST(Quartic, TripleRoot) {
  runPatterns(4, {{3, 1}, {1, 3}}, 23, 20000);
}

TEST(Cubic, FromKnownRoots) {
  runPatterns(3, {{1, 1, 1}, {1}, {2, 1}, {1, 2}}, 24, 100000);
}

}  // namespace
}  // namespace st
