// Oriented 2-D boxes (stcore/box2.hpp) against references that share no code with them: overlap
// by Sutherland-Hodgman clipping of one box by the other (a positive intersection area) and by
// edge crossings, distance as the least vertex-to-edge distance of the two outlines, and time of
// entry by sampling that clearance over the horizon (128 steps) and bisecting its first contact.
// 10^5 random cases per query, mixing generic, aligned, parallel, touching, overlapping, aimed and
// resting pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include <stcore/box2.hpp>
#include "test_scale.hpp"

namespace st {
namespace {

const int kCases = test::scaledCount(100000);  // fewer under the sanitizers (test_scale.hpp)
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

// ---- reference geometry -----------------------------------------------------------------------

using Poly = std::vector<Vec2>;

Poly outline(const Box2& b, const Vec2& shift = Vec2::Zero()) {
  const Vec2 n(-b.axis.y(), b.axis.x());
  const Vec2 x = b.halfExtents.x() * b.axis, y = b.halfExtents.y() * n, c = b.center + shift;
  return {c + x + y, c - x + y, c - x - y, c + x - y};  // counter-clockwise
}

double crossOf(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// The part of `subject` on the left of every edge of the counter-clockwise convex `clip`.
Poly clipBy(Poly subject, const Poly& clip) {
  for (std::size_t i = 0; i < clip.size() && !subject.empty(); ++i) {
    const Vec2 a = clip[i], b = clip[(i + 1) % clip.size()];
    auto side = [&](const Vec2& p) { return crossOf(b - a, p - a); };
    Poly out;
    for (std::size_t j = 0; j < subject.size(); ++j) {
      const Vec2 p = subject[j], q = subject[(j + 1) % subject.size()];
      const double sp = side(p), sq = side(q);
      if (sp >= 0.0) out.push_back(p);
      if ((sp >= 0.0) != (sq >= 0.0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
    }
    subject = std::move(out);
  }
  return subject;
}

double area(const Poly& p) {
  double twice = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) twice += crossOf(p[i], p[(i + 1) % p.size()]);
  return 0.5 * twice;
}

double pointSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double u = d.squaredNorm() > 0.0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (a + u * d - p).norm();
}

bool insideConvex(const Poly& p, const Vec2& x) {
  for (std::size_t i = 0; i < p.size(); ++i)
    if (crossOf(p[(i + 1) % p.size()] - p[i], x - p[i]) < 0.0) return false;
  return true;
}

// Clearance of two boxes: the outlines' distance when apart, minus the square root of the
// intersection area when they overlap. Boxes that touch clip to a sliver of roundoff (about
// 1e-15 m^2): below kSliver the outlines' distance (about 0) decides.
constexpr double kSliver = 1e-12;  // m^2
double clearance(const Poly& a, const Poly& b) {
  const double common = area(clipBy(a, b));
  if (common > kSliver) return -std::sqrt(common);
  if (insideConvex(a, b[0]) || insideConvex(b, a[0])) return 0.0;
  double d = kInf;
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = 0; j < 4; ++j)
      d = std::min({d, pointSegment(a[i], b[j], b[(j + 1) % 4]), pointSegment(b[j], a[i], a[(i + 1) % 4])});
  return d;
}

// ---- random cases -----------------------------------------------------------------------------

struct Maker {
  std::mt19937_64 rng{20261203};
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); }

  Box2 box(double heading) {
    return {Vec2(uniform(-6.0, 6.0), uniform(-6.0, 6.0)), Vec2(std::cos(heading), std::sin(heading)),
            Vec2(uniform(0.05, 3.0), uniform(0.05, 1.5))};
  }
  // a pair of boxes: generic, axis-aligned, parallel, touching end to end, one inside the other
  std::array<Box2, 2> pair() {
    const double h = uniform(-kPi, kPi);
    switch (pick(5)) {
      case 0: return {box(h), box(uniform(-kPi, kPi))};
      case 1: return {box(0.0), box(pick(2) ? 0.5 * kPi : 0.0)};
      case 2: return {box(h), box(h + (pick(2) ? kPi : 0.0))};
      case 3: {
        Box2 a = box(h), b = box(h);
        b.center = a.center + (a.halfExtents.x() + b.halfExtents.x()) * a.axis;
        return {a, b};
      }
      default: {
        Box2 a = box(h), b = box(uniform(-kPi, kPi));
        b.center = a.center + uniform(-0.3, 0.3) * a.halfExtents.x() * a.axis;
        return {a, b};
      }
    }
  }
  // relative velocity of b: generic, aimed at a, along a's axis, at rest, slow
  Vec2 velocity(const Box2& a, const Box2& b) {
    switch (pick(5)) {
      case 0: return Vec2(uniform(-8.0, 8.0), uniform(-8.0, 8.0));
      case 1: {
        const Vec2 aim = a.center + Vec2(uniform(-1.0, 1.0), uniform(-1.0, 1.0)) - b.center;
        return aim.norm() > 0.0 ? Vec2(aim.normalized() * uniform(0.5, 8.0)) : Vec2(1.0, 0.0);
      }
      case 2: return uniform(-8.0, 8.0) * a.axis;
      case 3: return Vec2::Zero();
      default: return Vec2(uniform(-1e-3, 1e-3), uniform(-1e-3, 1e-3));
    }
  }
};

// ---- the tests --------------------------------------------------------------------------------

// The reference motion's clearance sampled at steps + 1 times over [0, horizon], and its first
// contact: the first sample within tol of contact, bisected down to it (kInf if none).
struct SampledClearance {
  double horizon = 0.0;
  std::vector<double> gap;
  double first = kInf;
  // the deepest sampled overlap before time t (kInf if none sampled)
  double deepestBefore(double t) const {
    double d = kInf;
    const int steps = static_cast<int>(gap.size()) - 1;
    for (int i = 0; i <= steps && horizon * i / steps < t; ++i) d = std::min(d, gap[i]);
    return d;
  }
};
template <class Gap>
SampledClearance sampleClearance(const Gap& gapAt, double horizon, int steps, double tol) {
  SampledClearance s{horizon, std::vector<double>(static_cast<std::size_t>(steps) + 1), kInf};
  for (int i = 0; i <= steps; ++i) {
    const double t = horizon * i / steps;
    s.gap[i] = gapAt(t);
    if (s.first == kInf && s.gap[i] <= tol) {
      double lo = i == 0 ? 0.0 : horizon * (i - 1) / steps, hi = t;
      for (int it = 0; it < 60 && hi > lo; ++it) {
        const double mid = 0.5 * (lo + hi);
        (gapAt(mid) <= tol ? hi : lo) = mid;
      }
      s.first = hi;
    }
  }
  return s;
}

TEST(Box2, DistanceAndOverlapMatchClippingAndOutlines) {
  Maker m;
  int apart = 0, overlapping = 0, band = 0;
  for (int k = 0; k < kCases; ++k) {
    const auto [a, b] = m.pair();
    const double ref = clearance(outline(a), outline(b));
    const double d = distance(a, b);
    const double tol = 1e-12 * 20.0;  // roundoff of coordinates up to about 20 m
    if (std::abs(ref) <= tol) {
      ++band;  // touching within roundoff: either answer
      EXPECT_LE(d, tol) << "case " << k;
      continue;
    }
    SCOPED_TRACE(::testing::Message() << "case " << k << " ref " << ref << " distance " << d);
    EXPECT_EQ(overlaps(a, b), ref < 0.0);
    EXPECT_EQ(overlaps(b, a), ref < 0.0);
    if (ref < 0.0) {
      ++overlapping;
      EXPECT_EQ(d, 0.0);
    } else {
      ++apart;
      EXPECT_NEAR(d, ref, tol);
      EXPECT_NEAR(distance(b, a), ref, tol);
      EXPECT_EQ(distanceApart(a, b), d);  // bit for bit, for a caller that has the separation
      // the projection gap bounds the distance from below
      EXPECT_GT(separation(a, b), 0.0);
      EXPECT_LE(separation(a, b), d + tol);
    }
  }
  EXPECT_GT(apart, kCases / 5);
  EXPECT_GT(overlapping, kCases / 5);
  EXPECT_GT(band, kCases / 50);  // the touching family
}

TEST(Box2, PointDistanceAndSegmentOverlapMatchOutlines) {
  Maker m;
  int touching = 0;
  for (int k = 0; k < kCases; ++k) {
    const Box2 b = m.box(m.uniform(-kPi, kPi));
    const Poly o = outline(b);
    const Vec2 p(m.uniform(-9.0, 9.0), m.uniform(-9.0, 9.0));
    double ref = 0.0;
    if (!insideConvex(o, p)) {
      ref = kInf;
      for (int j = 0; j < 4; ++j) ref = std::min(ref, pointSegment(p, o[j], o[(j + 1) % 4]));
    }
    EXPECT_NEAR(distance(p, b), ref, 1e-12 * 20.0) << "case " << k;
    // a segment from p, sometimes degenerate
    const Vec2 q = m.pick(8) == 0 ? p : Vec2(m.uniform(-9.0, 9.0), m.uniform(-9.0, 9.0));
    double gap = insideConvex(o, p) || insideConvex(o, q) ? 0.0 : kInf;
    if (gap > 0.0) {
      for (int j = 0; j < 4; ++j) {
        const Vec2 e0 = o[j], e1 = o[(j + 1) % 4];
        const bool crosses = crossOf(q - p, e0 - p) * crossOf(q - p, e1 - p) <= 0.0 &&
                             crossOf(e1 - e0, p - e0) * crossOf(e1 - e0, q - e0) <= 0.0 && (q - p).squaredNorm() > 0.0;
        gap = std::min({gap, crosses ? 0.0 : kInf, pointSegment(p, e0, e1), pointSegment(q, e0, e1),
                        pointSegment(e0, p, q), pointSegment(e1, p, q)});
      }
    }
    if (gap > 0.0 && gap <= 1e-12 * 20.0) {
      ++touching;
      continue;
    }
    EXPECT_EQ(overlaps(Segment{p, q}, b), gap == 0.0) << "case " << k << " gap " << gap;
  }
  EXPECT_LT(touching, kCases / 100);
}

TEST(Box2, TimeOfEntryMatchesSampledClearance) {
  Maker m;
  constexpr int kSteps = 128;
  const double horizon = 4.0, tol = 1e-9;
  int hit = 0, miss = 0, now = 0, sampledLater = 0;
  for (int k = 0; k < kCases; ++k) {
    const auto [a, b] = m.pair();
    const Vec2 v = m.velocity(a, b);
    const Poly oa = outline(a);
    auto gapAt = [&](double t) { return clearance(oa, outline(b, v * t)); };
    // the reference's first contact, sampled and bisected
    const SampledClearance ref = sampleClearance(gapAt, horizon, kSteps, tol);
    const double first = ref.first;
    auto deepestBefore = [&](double t) { return ref.deepestBefore(t); };
    const Impact e = timeOfEntry(a, b, v, horizon);
    SCOPED_TRACE(::testing::Message() << "case " << k << " outcome " << static_cast<int>(e.outcome) << " t " << e.t
                                      << " sampled first contact " << first);
    switch (e.outcome) {
      case Outcome::Overlapping:
        ++now;
        EXPECT_EQ(e.t, 0.0);
        EXPECT_LE(gapAt(0.0), 4.0 * tol::kLinearSlop);  // within the slop on every axis
        break;
      case Outcome::Hit:
        ++hit;
        ASSERT_GE(e.t, 0.0);
        ASSERT_LE(e.t, horizon);
        EXPECT_LE(gapAt(e.t), tol);          // the boxes touch at the time given ...
        EXPECT_GT(gapAt(0.0), -tol);         // ... were apart at the start ...
        EXPECT_GT(deepestBefore(e.t), -tol);  // ... and no sample overlapped earlier
        if (first > e.t + 1e-6) ++sampledLater;  // a brief corner overlap between two samples
        break;
      case Outcome::Miss:
        ++miss;
        EXPECT_GT(deepestBefore(kInf), -tol);  // never overlapping deeper than roundoff
        break;
      case Outcome::Separating: ADD_FAILURE() << "not an outcome of time of entry"; break;
    }
  }
  EXPECT_GT(hit, kCases / 10);
  EXPECT_GT(miss, kCases / 10);
  EXPECT_GT(now, kCases / 10);
  EXPECT_LT(sampledLater, kCases / 100);
}

// Relative acceleration of b: generic, braking along its velocity (it may stop short or inside),
// turning across it, none.
Vec2 acceleration(Maker& m, const Vec2& v) {
  switch (m.pick(4)) {
    case 0: return Vec2(m.uniform(-4.0, 4.0), m.uniform(-4.0, 4.0));
    case 1: return -m.uniform(0.5, 6.0) * v;
    case 2: return m.uniform(-3.0, 3.0) * Vec2(-v.y(), v.x());
    default: return Vec2::Zero();
  }
}

TEST(Box2, AcceleratedTimeOfEntryMatchesSampledClearance) {
  // the clearance along the curved path, sampled finely (1024 steps over 4 s) and bisected at
  // its first contact; fewer cases than the straight test, as each costs eight times the samples
  Maker m;
  const int cases = std::max(1000, kCases / 10);
  constexpr int kSteps = 1024;
  const double horizon = 4.0, tol = 1e-9, slop = tol::kLinearSlop;
  int hit = 0, miss = 0, now = 0, curved = 0, sampledLater = 0;
  for (int k = 0; k < cases; ++k) {
    const auto [a, b] = m.pair();
    const Vec2 v = m.velocity(a, b), acc = acceleration(m, v);
    const std::array<SeparatingAxis, 4> axes = separatingAxes(a, b);
    const Poly oa = outline(a);
    auto gapAt = [&](double t) { return clearance(oa, outline(b, v * t + 0.5 * acc * t * t)); };
    const SampledClearance ref = sampleClearance(gapAt, horizon, kSteps, tol);
    const double first = ref.first;
    auto deepestBefore = [&](double t) { return ref.deepestBefore(t); };
    // a root is accepted within slop (1 + extent) on every axis: that far apart at most
    double widest = 0.0;
    for (const SeparatingAxis& ax : axes) widest = std::max(widest, ax.extent);
    const double accepted = 2.0 * slop * (1.0 + widest);
    const Impact e = timeOfEntryAccelerated(axes, b.center - a.center, v, acc, horizon, slop);
    SCOPED_TRACE(::testing::Message() << "case " << k << " outcome " << static_cast<int>(e.outcome) << " t " << e.t
                                      << " sampled first contact " << first);
    switch (e.outcome) {
      case Outcome::Overlapping:
        ++now;
        EXPECT_EQ(e.t, 0.0);
        EXPECT_LE(gapAt(0.0), 4.0 * slop);
        break;
      case Outcome::Hit:
        ++hit;
        curved += acc.squaredNorm() > 0.0;
        ASSERT_GE(e.t, 0.0);
        ASSERT_LE(e.t, horizon);
        EXPECT_LE(gapAt(e.t), tol + accepted);  // touching at the time given ...
        EXPECT_GT(gapAt(0.0), -tol);            // ... apart at the start ...
        EXPECT_GT(deepestBefore(e.t), -tol);    // ... and no sample overlapped earlier
        if (first > e.t + 1e-6) ++sampledLater;  // a brief corner overlap between two samples
        break;
      case Outcome::Miss:
        ++miss;
        EXPECT_GT(deepestBefore(kInf), -tol);
        break;
      case Outcome::Separating: ADD_FAILURE() << "not an outcome of time of entry"; break;
    }
  }
  // (braking paths often stop short: fewer hits than on straight ones)
  EXPECT_GT(hit, cases / 20);
  EXPECT_GT(curved, cases / 20);
  EXPECT_GT(miss, cases / 10);
  EXPECT_GT(now, cases / 10);
  EXPECT_LT(sampledLater, cases / 100);
  std::printf("accelerated time of entry: %d hits (%d curved), %d overlapping, %d misses, %d sampled later of %d\n",
              hit, curved, now, miss, sampledLater, cases);
}

TEST(Box2, AcceleratedTimeOfEntryAnalytic) {
  // b 20 m ahead on a's axis (the boxes reach 3.4 m along it), closing at 10 m/s and braking
  const Box2 a{Vec2(0.0, 0.0), Vec2(1.0, 0.0), Vec2(2.5, 0.9)};
  const Box2 b{Vec2(20.0, 0.5), Vec2(0.0, 1.0), Vec2(2.5, 0.9)};
  const std::array<SeparatingAxis, 4> axes = separatingAxes(a, b);
  const Vec2 p = b.center - a.center, v(-10.0, 0.0);
  // at 2 m/s^2: 20 - 10 t + t^2 = 3.4, the smaller root 5 - sqrt(8.4) s
  const Impact e = timeOfEntryAccelerated(axes, p, v, Vec2(2.0, 0.0), 5.0, tol::kLinearSlop);
  ASSERT_EQ(e.outcome, Outcome::Hit);
  EXPECT_NEAR(e.t, 5.0 - std::sqrt(8.4), 1e-12);
  // at 3.1 m/s^2 it turns back after 100 / 6.2 = 16.13 m, short of the 16.6 m gap
  EXPECT_EQ(timeOfEntryAccelerated(axes, p, v, Vec2(3.1, 0.0), 10.0, tol::kLinearSlop).outcome, Outcome::Miss);
  // without acceleration it is the straight kernel's time, (20 - 3.4) / 10 s
  const Impact straight = timeOfEntryAccelerated(axes, p, v, Vec2::Zero(), 5.0, tol::kLinearSlop);
  ASSERT_EQ(straight.outcome, Outcome::Hit);
  EXPECT_NEAR(straight.t, 1.66, 1e-12);
  EXPECT_EQ(timeOfEntryAccelerated(axes, Vec2::Zero(), v, Vec2(2.0, 0.0), 1.0, tol::kLinearSlop).outcome,
            Outcome::Overlapping);
}

TEST(Box2, TimeOfEntryOnSeparatingAxesIsTheBoxPairs) {
  // the kernel on plain numbers, given the pair's axes, is the shape function
  const Box2 a{Vec2(0.0, 0.0), Vec2(1.0, 0.0), Vec2(2.5, 0.9)};
  const Box2 b{Vec2(20.0, 0.5), Vec2(0.0, 1.0), Vec2(2.5, 0.9)};
  const std::array<SeparatingAxis, 4> axes = separatingAxes(a, b);
  const Impact viaAxes = timeOfEntry(axes, b.center - a.center, Vec2(-10.0, 0.0), 5.0, tol::kLinearSlop);
  const Impact viaBoxes = timeOfEntry(a, b, Vec2(-10.0, 0.0), 5.0);
  ASSERT_EQ(viaAxes.outcome, Outcome::Hit);
  EXPECT_EQ(viaAxes.t, viaBoxes.t);
  // 20 m apart, reaches 2.5 + 0.9 m: (20 - 3.4) / 10 s
  EXPECT_NEAR(viaAxes.t, 1.66, 1e-12);
  // too late for a 1 s horizon; already overlapping when placed inside
  EXPECT_EQ(timeOfEntry(a, b, Vec2(-10.0, 0.0), 1.0).outcome, Outcome::Miss);
  EXPECT_EQ(timeOfEntry(a, a, Vec2::Zero(), 1.0).outcome, Outcome::Overlapping);
  // support along the axis is the half length, along a diagonal both halves projected
  EXPECT_DOUBLE_EQ(support(a, Vec2(1.0, 0.0)), 2.5);
  EXPECT_DOUBLE_EQ(support(a, Vec2(1.0, 1.0).normalized()), (2.5 + 0.9) / std::sqrt(2.0));
}

}  // namespace
}  // namespace st
