// Time of impact by conservative advancement against dense time sampling of the exact distance:
// never later than the first sampled contact, never a miss, and no earlier than the separation
// could first have come within the slop of the clearance between the samples.
#include <gtest/gtest.h>
#include "test_scale.hpp"

#include <algorithm>
#include <random>
#include <vector>

#include <stcore/toi_advance.hpp>

namespace st {
namespace {

struct Rng {
  std::mt19937_64 gen;
  explicit Rng(std::uint64_t s) : gen(s) {}
  double u(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(gen); }
  Vec3 p(double h) { return {u(-h, h), u(-h, h), u(-h, h)}; }
};

TEST(ToiAdvance, HeadOnParallelCapsules) {
  // two parallel capsules 1 m apart closing at 1 m/s: contact (plus clearance 0.05) at 0.75 s
  const MovingCapsule a{{{0, 0, 0}, {1, 0, 0}, 0.1}, Vec3::Zero(), Vec3::Zero()};
  const MovingCapsule b{{{0, 1, 0}, {1, 1, 0}, 0.1}, Vec3(0, -1, 0), Vec3(0, -1, 0)};
  const AdvanceImpact r = toiAdvance(a, b, 0.05, 2.0);
  ASSERT_EQ(r.impact.outcome, Outcome::Hit);
  EXPECT_LE(r.impact.t, 0.75);
  EXPECT_GE(r.impact.t, 0.75 - tol::kAdvanceSlop / 1.0 - 1e-12);
  EXPECT_NEAR(r.distance, 0.8, 1e-15);
  // beyond the horizon: clear
  EXPECT_EQ(toiAdvance(a, b, 0.05, 0.7).impact.outcome, Outcome::Miss);
  // moving apart: clear; already inside the clearance: touching
  const MovingCapsule away{b.c, Vec3(0, 1, 0), Vec3(0, 1, 0)};
  EXPECT_EQ(toiAdvance(a, away, 0.05, 10.0).impact.outcome, Outcome::Miss);
  EXPECT_EQ(toiAdvance(a, b, 0.85, 1.0).impact.outcome, Outcome::Overlapping);
}

TEST(ToiAdvance, RotatingLinkSweepsIntoSphere) {
  // a link turning about its end point a at 1 rad/s: end b moves at 1 m/s tangentially.
  // Affine end-point motion, so b travels on the tangent line x = 1, y = t.
  const MovingCapsule link{{{0, 0, 0}, {1, 0, 0}, 0.05}, Vec3::Zero(), Vec3(0, 1, 0)};
  const MovingSphere ball{{{1.0, 0.5, 0.0}, 0.05}, Vec3::Zero()};
  const AdvanceImpact r = toiAdvance(link, ball, 0.0, 1.0);
  ASSERT_EQ(r.impact.outcome, Outcome::Hit);
  // contact when the segment from the origin to (1, t) is 0.1 from (1, 0.5)
  double lo = 0.0, hi = 0.5;
  for (int k = 0; k < 200; ++k) {
    const double m = 0.5 * (lo + hi);
    (distance(link.at(m), ball.at(m)) > 0.0 ? lo : hi) = m;
  }
  EXPECT_LE(r.impact.t, hi);
  EXPECT_GE(r.impact.t, hi - 1e-5);
}

TEST(ToiAdvance, NeverLaterThanDenseSamplingOnRandomMotions) {
  Rng rng(21);
  const int motions = test::scaledCount(10000);
  const int samples = 2000;
  const double horizon = 0.5;
  int hits = 0, touching = 0, clear = 0, capped = 0;
  std::vector<double> bracketed;  // how much earlier than the first sampled contact a hit is (s)
  for (int i = 0; i < motions; ++i) {
    const MovingCapsule a{{rng.p(0.4), rng.p(0.4), rng.u(0.01, 0.1)}, rng.p(1.5), rng.p(1.5)};
    const double clearance = rng.u(0.0, 0.05);
    const int kind = i % 3;
    MovingCapsule oc{{rng.p(0.5), rng.p(0.5), rng.u(0.01, 0.1)}, rng.p(1.5), rng.p(1.5)};
    const MovingSphere os{{rng.p(0.5), rng.u(0.01, 0.15)}, rng.p(1.0)};
    const Eigen::Matrix3d rot = Eigen::Quaterniond(rng.u(-1, 1), rng.u(-1, 1), rng.u(-1, 1), rng.u(-1, 1)).normalized().toRotationMatrix();
    const MovingBox ob{{rng.p(0.5), Vec3(rng.u(0.02, 0.2), rng.u(0.02, 0.2), rng.u(0.02, 0.2)), rot}, rng.p(1.0)};
    auto sep = [&](double t) {
      if (kind == 0) return distance(a.at(t), oc.at(t));
      if (kind == 1) return distance(a.at(t), os.at(t));
      return distance(a.at(t), ob.at(t));
    };
    const AdvanceImpact r = kind == 0   ? toiAdvance(a, oc, clearance, horizon)
                            : kind == 1 ? toiAdvance(a, os, clearance, horizon)
                                        : toiAdvance(a, ob, clearance, horizon);
    // the first sampled contact, and the earliest time the separation could have come within the
    // slop of the clearance: between samples it shrinks at most at the sum of the two fastest
    // points' speeds (a bound of its own, looser than the kernel's)
    const double step = horizon / samples;
    const double vOther = kind == 0 ? std::max(oc.va.norm(), oc.vb.norm()) : kind == 1 ? os.v.norm() : ob.v.norm();
    const double vMax = std::max(a.va.norm(), a.vb.norm()) + vOther;
    double first = -1.0, earliest = -1.0;
    for (int k = 0; k <= samples; ++k) {
      const double t = horizon * k / samples;
      const double s = sep(t);
      if (earliest < 0.0 && s - vMax * step <= clearance + tol::kAdvanceSlop) earliest = t;
      if (s <= clearance) {
        first = t;
        break;
      }
    }
    if (first >= 0.0) {
      ASSERT_NE(r.impact.outcome, Outcome::Miss) << "missed contact sampled at " << first << " s, motion " << i;
      ASSERT_LE(r.impact.t, first) << "motion " << i;
    }
    if (r.impact.outcome == Outcome::Overlapping) {
      ++touching;
      ASSERT_EQ(r.impact.t, 0.0);
      ASSERT_LE(sep(0.0), clearance + tol::kAdvanceSlop);
    } else if (r.impact.outcome == Outcome::Hit) {
      ++hits;
      ASSERT_LE(r.impact.t, horizon);
      if (r.capped) {
        ++capped;
      } else {
        // a reported contact is real: the shapes are within the clearance (plus the slop) then,
        // so not before the sampling says they can first be
        ASSERT_LE(sep(r.impact.t), clearance + tol::kAdvanceSlop + 1e-12) << "motion " << i;
        ASSERT_GE(earliest, 0.0) << "motion " << i;
        ASSERT_GE(r.impact.t, earliest) << "motion " << i;
        if (first >= 0.0) bracketed.push_back(first - r.impact.t);
      }
    } else {
      ++clear;
    }
  }
  // the sample covers all three regimes
  EXPECT_GT(hits, motions / 10);
  EXPECT_GT(clear, motions / 10);
  EXPECT_GT(touching, motions / 50);
  EXPECT_LT(capped, motions / 100);
  // and a hit is the first contact, not merely a lower bound: nine in ten within two samples of it
  ASSERT_GT(bracketed.size(), static_cast<std::size_t>(motions / 20));
  std::sort(bracketed.begin(), bracketed.end());
  EXPECT_LE(bracketed[bracketed.size() * 9 / 10], 2.0 * horizon / samples);
  std::printf("toi_advance: %d hits, %d touching, %d clear, %d capped of %d motions\n", hits, touching, clear, capped, motions);
}

}  // namespace
}  // namespace st
