// Distance kernels against FCL (independent implementation) and against dense sampling.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <cstdio>
#include <random>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <stcore/distance.hpp>

namespace st {
namespace {

constexpr int kPairs = 100000;
constexpr double kAgree = 1e-9;  // metres

struct Rng {
  std::mt19937_64 gen;
  explicit Rng(std::uint64_t seed) : gen(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(gen); }
  Vec3 point(double half) { return {uniform(-half, half), uniform(-half, half), uniform(-half, half)}; }
  Vec3 direction() {
    Vec3 v;
    do v = point(1.0);
    while (v.squaredNorm() < 1e-4 || v.squaredNorm() > 1.0);
    return v.normalized();
  }
  Eigen::Matrix3d rotation() {
    Eigen::Quaterniond q(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    return q.normalized().toRotationMatrix();
  }
  Capsule capsule(double half) {
    const Vec3 c = point(half);
    const Vec3 d = direction() * uniform(0.0, 0.6);
    return {c - 0.5 * d, c + 0.5 * d, uniform(0.01, 0.15)};
  }
};

// Golden-section search on the distance from p(s) to the other segment (convex in s, each
// evaluation an exact point-segment distance): an independent truth, tight to roundoff.
double goldenMin(const std::function<double(double)>& f) {
  double lo = 0.0, hi = 1.0;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int k = 0; k < 200; ++k) {
    const double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
    if (f(m1) <= f(m2)) hi = m2;
    else lo = m1;
  }
  return std::min({f(0.0), f(1.0), f(0.5 * (lo + hi))});
}

// FCL's capsule is centred on its frame origin with its segment along z.
fcl::Transform3d capsuleFrame(const Capsule& c) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = 0.5 * (c.a + c.b);
  const Vec3 d = c.b - c.a;
  if (d.norm() > 0.0) tf.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), d).toRotationMatrix();
  return tf;
}

fcl::Transform3d translation(const Vec3& p) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = p;
  return tf;
}

// FCL's distance, or a negative number when FCL reports a collision.
double fclDistance(const fcl::CollisionGeometryd& g1, const fcl::Transform3d& tf1, const fcl::CollisionGeometryd& g2,
                   const fcl::Transform3d& tf2) {
  fcl::DistanceRequestd req;
  req.gjk_solver_type = fcl::GST_INDEP;
  // GJK's stopping tolerance: FCL's default (1e-6) is far coarser than the agreement we test
  req.distance_tolerance = 1e-15;
  fcl::DistanceResultd res;
  return fcl::distance(&g1, tf1, &g2, tf2, req, res);
}

bool fclCollide(const fcl::CollisionGeometryd& g1, const fcl::Transform3d& tf1, const fcl::CollisionGeometryd& g2,
                const fcl::Transform3d& tf2) {
  fcl::CollisionRequestd req;
  req.gjk_solver_type = fcl::GST_INDEP;
  fcl::CollisionResultd res;
  return fcl::collide(&g1, tf1, &g2, tf2, req, res) > 0;
}

// Runs `pairs` random cases of one shape pair; each case returns {ours, fcl's, fcl collides}.
template <class Case>
void compareWithFcl(int pairs, Case&& oneCase, const char* what) {
  int separated = 0;
  int overlapping = 0;
  double worst = 0.0;
  for (int i = 0; i < pairs; ++i) {
    const auto [ours, theirs, collides] = oneCase(i);
    if (collides) {
      ++overlapping;
      EXPECT_EQ(ours, 0.0) << what << " case " << i << ": FCL reports a collision";
      continue;
    }
    ++separated;
    worst = std::max(worst, std::abs(ours - theirs));
    ASSERT_NEAR(ours, theirs, kAgree) << what << " case " << i;
  }
  // both regimes must actually be exercised
  EXPECT_GT(separated, pairs / 2) << what;
  EXPECT_GT(overlapping, pairs / 50) << what;
  std::printf("%s: %d separated pairs, worst |ours - fcl| = %.3g m; %d overlapping pairs\n", what, separated, worst,
              overlapping);
}

TEST(DistanceVsFcl, CapsuleCapsule) {
  Rng rng(1);
  compareWithFcl(kPairs, [&](int) {
    const Capsule a = rng.capsule(0.6);
    const Capsule b = rng.capsule(0.6);
    const fcl::Capsuled ga(a.radius, (a.b - a.a).norm());
    const fcl::Capsuled gb(b.radius, (b.b - b.a).norm());
    const auto ta = capsuleFrame(a);
    const auto tb = capsuleFrame(b);
    return std::tuple{distance(a, b), fclDistance(ga, ta, gb, tb), fclCollide(ga, ta, gb, tb)};
  }, "capsule-capsule");
}

TEST(DistanceVsFcl, CapsuleSphere) {
  Rng rng(2);
  compareWithFcl(kPairs, [&](int) {
    const Capsule a = rng.capsule(0.5);
    const Sphere s{rng.point(0.5), rng.uniform(0.01, 0.2)};
    const fcl::Capsuled ga(a.radius, (a.b - a.a).norm());
    const fcl::Sphered gs(s.radius);
    const auto ta = capsuleFrame(a);
    const auto ts = translation(s.center);
    return std::tuple{distance(a, s), fclDistance(ga, ta, gs, ts), fclCollide(ga, ta, gs, ts)};
  }, "capsule-sphere");
}

TEST(DistanceVsFcl, CapsuleBox) {
  Rng rng(3);
  compareWithFcl(kPairs, [&](int) {
    const Capsule a = rng.capsule(0.8);
    const Box b{rng.point(0.8), Vec3(rng.uniform(0.02, 0.3), rng.uniform(0.02, 0.3), rng.uniform(0.02, 0.3)),
                rng.rotation()};
    const fcl::Capsuled ga(a.radius, (a.b - a.a).norm());
    const fcl::Boxd gb(2.0 * b.halfExtents);
    const auto ta = capsuleFrame(a);
    fcl::Transform3d tb = fcl::Transform3d::Identity();
    tb.translation() = b.center;
    tb.linear() = b.rotation;
    // FCL has no capsule-box kernel; its GJK stops up to ~3e-9 m short when the rounded capsule
    // nearly touches the box, and fails outright (mm errors) on a zero-radius capsule. So ask it
    // about a thinner capsule on the same segment, which stays >= r/2 away from the box:
    // dist(capsule_r, box) = dist(capsule_rho, box) - (r - rho) for separated shapes.
    const double rho = 0.5 * a.radius;
    const fcl::Capsuled core(rho, (a.b - a.a).norm());
    const double theirs = fclDistance(core, ta, gb, tb) - (a.radius - rho);
    return std::tuple{distance(a, b), theirs, fclCollide(ga, ta, gb, tb)};
  }, "capsule-box");
}

// ---- degenerate and independent checks --------------------------------------------------------

double sampledSegmentDistance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  return goldenMin([&](double s) { return std::sqrt(pointSegmentDistanceSq(p0 + s * (p1 - p0), q0, q1)); });
}

TEST(SegmentSegment, ParallelCollinearAndPoints) {
  const Vec3 x = Vec3::UnitX();
  const Vec3 y = Vec3::UnitY();
  auto dist = [](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return std::sqrt(closestSegmentSegment(a, b, c, d).distanceSq);
  };
  // parallel, overlapping in projection: the line distance
  EXPECT_NEAR(dist({0, 0, 0}, 2 * x, y + 0.5 * x, y + 3 * x), 1.0, 1e-15);
  // anti-parallel, overlapping
  EXPECT_NEAR(dist({0, 0, 0}, 2 * x, y + 3 * x, y + 0.5 * x), 1.0, 1e-15);
  // parallel, disjoint in projection: end to end
  EXPECT_NEAR(dist({0, 0, 0}, x, y + 3 * x, y + 4 * x), std::sqrt(4.0 + 1.0), 1e-15);
  EXPECT_NEAR(dist(x, {0, 0, 0}, y + 4 * x, y + 3 * x), std::sqrt(4.0 + 1.0), 1e-15);
  // collinear, overlapping and disjoint
  EXPECT_EQ(dist({0, 0, 0}, 2 * x, x, 3 * x), 0.0);
  EXPECT_NEAR(dist({0, 0, 0}, x, 3 * x, 2 * x), 1.0, 1e-15);
  // zero-length segments
  EXPECT_NEAR(dist(y, y, {0, 0, 0}, 2 * x), 1.0, 1e-15);
  EXPECT_NEAR(dist({0, 0, 0}, 2 * x, 3 * x + y, 3 * x + y), std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(dist(y, y, x, x), std::sqrt(2.0), 1e-15);
  // crossing
  EXPECT_NEAR(dist(-x, x, Vec3(0, -1, 0.25), Vec3(0, 1, 0.25)), 0.25, 1e-15);
}

TEST(SegmentSegment, NearlyParallelAgainstSampling) {
  Rng rng(4);
  for (int i = 0; i < 300; ++i) {
    const Vec3 p0 = rng.point(0.5);
    const Vec3 d = rng.direction() * rng.uniform(0.05, 0.6);
    // tilt by 1e-4 .. 1e-9 rad, offset sideways, slide along: the regime where the determinant vanishes
    const double tilt = std::pow(10.0, rng.uniform(-9.0, -4.0));
    const Vec3 side = d.unitOrthogonal();
    const Vec3 q0 = p0 + rng.uniform(-0.7, 0.7) * d + rng.uniform(0.0, 0.1) * side;
    const Vec3 q1 = q0 + rng.uniform(0.2, 1.5) * (d + tilt * d.norm() * d.cross(side).normalized());
    const double ours = std::sqrt(closestSegmentSegment(p0, p0 + d, q0, q1).distanceSq);
    const double truth = sampledSegmentDistance(p0, p0 + d, q0, q1);
    ASSERT_LE(ours, truth + 1e-12) << i;        // never above an attained distance
    ASSERT_NEAR(ours, truth, 1e-10) << i;
  }
}

TEST(SegmentSegment, NearlyParallelTiltedTowardsEachOther) {
  // tilted by 1e-10 .. 1e-5 rad in the plane that holds the offset (so the distance changes at
  // first order along the overlap, and the nearest points are at one end of it, either one)
  // rather than across it: below the parallel threshold (sin^2 <= 1e-14, 1e-7 rad) the kernel
  // must still pick the nearer end, not an arbitrary one (it did: up to 1e-7 times the length too
  // far, found against FCL on a person's capsules beside an arm, tests/models/arm/person_fcl_test)
  Rng rng(6);
  int belowThreshold = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p0 = rng.point(0.5);
    const Vec3 d = rng.direction() * rng.uniform(0.05, 0.6);
    const double tilt = std::pow(10.0, rng.uniform(-10.0, -5.0)) * (i % 2 ? 1.0 : -1.0);
    const Vec3 side = (rng.uniform(0, 1) * d.unitOrthogonal() + rng.uniform(0, 1) * d.cross(d.unitOrthogonal()).normalized())
                          .normalized();
    const Vec3 q0 = p0 + rng.uniform(-0.7, 0.7) * d + rng.uniform(0.001, 0.1) * side;
    const Vec3 q1 = q0 + rng.uniform(0.2, 1.5) * (d + tilt * d.norm() * side);
    belowThreshold += tilt * tilt < 1e-14;
    for (const bool swap : {false, true}) {
      const double ours = swap ? std::sqrt(closestSegmentSegment(q0, q1, p0, p0 + d).distanceSq)
                               : std::sqrt(closestSegmentSegment(p0, p0 + d, q0, q1).distanceSq);
      const double truth = sampledSegmentDistance(p0, p0 + d, q0, q1);
      ASSERT_LE(ours, truth + 1e-12) << i << " tilt " << tilt;  // never above an attained distance
      ASSERT_NEAR(ours, truth, 1e-12) << i << " tilt " << tilt << (swap ? " swapped" : "");
    }
  }
  EXPECT_GT(belowThreshold, 500);
}

TEST(SegmentBox, AgainstGoldenSectionOnConvexDistance) {
  // the distance from the segment to the box is convex in the segment parameter: golden-section
  // search on exact point-box distances is an independent truth
  Rng rng(5);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 h(rng.uniform(0.01, 0.4), rng.uniform(0.01, 0.4), rng.uniform(0.01, 0.4));
    Vec3 p0 = rng.point(0.8);
    Vec3 p1 = rng.point(0.8);
    if (i % 4 == 0) p1 = p0 + Vec3(0, 0, rng.uniform(-0.5, 0.5));  // axis-parallel segments
    const double truth =
        goldenMin([&](double s) { return std::sqrt(pointAlignedBoxDistanceSq(p0 + s * (p1 - p0), h)); });
    const double ours = std::sqrt(segmentAlignedBoxDistanceSq(p0, p1, h));
    ASSERT_LE(ours, truth + 1e-12) << i;
    ASSERT_NEAR(ours, truth, 1e-9) << i;
  }
}

TEST(SphereShapes, Exact) {
  const Sphere a{{0, 0, 0}, 0.5};
  const Sphere b{{2, 0, 0}, 0.25};
  EXPECT_DOUBLE_EQ(distance(a, b), 1.25);
  const Box box{{0, 0, 0}, {1, 1, 1}, Eigen::AngleAxisd(0.3, Vec3::UnitZ()).toRotationMatrix()};
  const Sphere s{{0, 0, 3}, 0.5};
  EXPECT_NEAR(distance(s, box), 1.5, 1e-15);
  EXPECT_EQ(distance(Sphere{{0.5, 0.5, 0.5}, 0.1}, box), 0.0);
}

}  // namespace
}  // namespace st
