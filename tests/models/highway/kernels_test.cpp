// The disc-entry kernel under constant acceleration against dense sampling of the distance
// itself: generic curving paths, tiny radii with slow approaches (where a quartic written as
// p.p - R^2 loses the radius to cancellation) and near-tangent (grazing) passes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels.hpp"

namespace st::highway::detail {
namespace {

// First s in [0, len] with |p + v s + a s^2 / 2| <= R: a fine grid, every bracketed local minimum
// refined by golden section, the crossing by bisection. minGap: the smallest clearance found
// (how close a miss came, or how deep a graze went).
double sampledEntry(const Vec2& p, const Vec2& v, const Vec2& a, double R, double len, double& minGap) {
  auto g = [&](double s) { return (p + v * s + (0.5 * s * s) * a).norm() - R; };
  auto crossing = [&](double lo, double hi) {  // g(lo) > 0 >= g(hi)
    for (int it = 0; it < 200 && hi - lo > 1e-16 * std::max(1.0, hi); ++it) {
      const double mid = 0.5 * (lo + hi);
      (g(mid) > 0.0 ? lo : hi) = mid;
    }
    return hi;
  };
  constexpr int kGrid = 8192;
  minGap = g(0.0);
  if (minGap <= 0.0) return 0.0;
  double prev = 0.0, gPrev = minGap;
  for (int i = 1; i <= kGrid; ++i) {
    const double s = len * i / kGrid, gs = g(s);
    if (gs <= 0.0) {
      minGap = std::min(minGap, gs);
      return crossing(prev, s);
    }
    // a local minimum between grid points may dip below zero
    if (i < kGrid) {
      const double next = len * (i + 1) / kGrid;
      if (gs <= gPrev && gs <= g(next)) {
        double lo = prev, hi = next;
        for (int it = 0; it < 200; ++it) {
          const double m1 = hi - 0.618033988749895 * (hi - lo), m2 = lo + 0.618033988749895 * (hi - lo);
          (g(m1) < g(m2) ? hi : lo) = g(m1) < g(m2) ? m2 : m1;
        }
        const double sMin = 0.5 * (lo + hi);
        minGap = std::min(minGap, g(sMin));
        if (g(sMin) <= 0.0) return crossing(prev, sMin);
      }
    }
    minGap = std::min(minGap, gs);
    prev = s;
    gPrev = gs;
  }
  return kInf;
}

TEST(Kernels, AcceleratingDiscEntryMatchesDenseSampling) {
  std::mt19937_64 rng(1717);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto logUni = [&](double lo, double hi) { return std::pow(10.0, lo + (hi - lo) * U(rng)); };
  auto unit = [&]() {
    const double th = 2.0 * 3.14159265358979323846 * U(rng);
    return Vec2(std::cos(th), std::sin(th));
  };
  int hits = 0, tiny = 0, grazing = 0;
  for (int k = 0; k < 6000; ++k) {
    const int family = k % 3;
    double R = 0.0, len = 0.0;
    Vec2 p, v, a;
    const Vec2 u = unit(), w(-u.y(), u.x());
    if (family == 0) {  // generic: curving paths that pass, turn and come back
      R = 0.5 + 3.0 * U(rng);
      p = Vec2(20 * U(rng) - 10, 20 * U(rng) - 10), v = Vec2(10 * U(rng) - 5, 10 * U(rng) - 5);
      a = Vec2(8 * U(rng) - 4, 8 * U(rng) - 4), len = 0.5 + 9.5 * U(rng);
    } else if (family == 1) {  // tiny radii, slow approaches (walking pace to motorway), gently braking
      R = logUni(-7, -3);
      const double speed = logUni(-1, 1.5);
      p = (1.0 + 3.0 * U(rng)) * u + 0.5 * R * U(rng) * w;
      v = -speed * u, a = 0.1 * speed * speed * u * U(rng);
      len = 1.2 * p.norm() / speed;
    } else {  // near-tangent: aimed to pass at R (1 +- 10^-3..10^-12), braking
      R = 0.5 + 2.0 * U(rng);
      const double miss = R * (1.0 + (U(rng) < 0.5 ? -1.0 : 1.0) * logUni(-12, -3));
      p = (5.0 + 5.0 * U(rng)) * u + miss * w, v = -(1.0 + 4.0 * U(rng)) * u;
      a = 0.05 * (0.1 + U(rng)) * u, len = 2.0 * p.norm() / v.norm();  // braking along the approach: the line stays
    }
    const Piece pc{p, v, a, 0.0, len};
    double minGap = 0.0;
    const double want = sampledEntry(p, v, a, R, len, minGap);
    const Impact entry = discEntry(pc, Vec2::Zero(), R);
    ASSERT_NE(entry.outcome, Outcome::Separating) << "case " << k;  // not an outcome of an entry
    const double got = entry.acts() ? entry.actTime() : kInf;
    const double scale = p.norm() + R + v.norm() * len + a.norm() * len * len;
    // a pass within this of the circle may go either way: near a tangent the entry time is
    // ill-conditioned (it moves with the square root of the depth), and the inputs are only so exact
    const double band = 1e-9 * scale;
    if (std::abs(minGap) <= band) {
      ++grazing;
      if (got < kInf) {
        EXPECT_LE((p + v * got + 0.5 * got * got * a).norm() - R, band) << "case " << k;
      }
      continue;
    }
    if (want == kInf) {
      EXPECT_EQ(got, kInf) << "case " << k << " family " << family << " minGap " << minGap;
      continue;
    }
    if (want == 0.0) {  // inside already
      EXPECT_EQ(entry.outcome, Outcome::Overlapping) << "case " << k;
      EXPECT_EQ(got, 0.0) << "case " << k;
      continue;
    }
    EXPECT_EQ(entry.outcome, Outcome::Hit) << "case " << k;
    ++hits;
    tiny += family == 1;
    // at the entry the distance is the radius: a root from p.p - R^2 misses it by about
    // eps |p|^2 / (2 R), far more than this for the tiny radii. Where the path only just dips
    // inside, entry and exit are a near double root, found only to about the root of the roundoff:
    // there the residual is held to the band, and the time (which moves with the square root of
    // the depth) is not compared.
    const bool shallow = -minGap <= 1e-6 * R;
    const double residual = (p + v * got + 0.5 * got * got * a).norm() - R;
    EXPECT_LE(std::abs(residual), (shallow ? 1e-9 : 1e-12) * scale) << "case " << k << " family " << family << " got " << got;
    if (!shallow) {
      EXPECT_NEAR(got, want, 1e-10 * std::max(1.0, want)) << "case " << k << " family " << family << std::hexfloat
                                                           << " p=" << p.transpose() << " v=" << v.transpose()
                                                           << " a=" << a.transpose() << " R=" << R << " len=" << len;
    }
  }
  EXPECT_GT(hits, 2000);
  EXPECT_GT(tiny, 1000);
  EXPECT_GT(grazing, 10);
}

}  // namespace
}  // namespace st::highway::detail
