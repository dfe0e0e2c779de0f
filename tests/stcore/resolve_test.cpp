// Elastic resolution against the conservation laws: momentum and kinetic energy to 1e-12
// relative for ball pairs, speed for reflections off infinitely massive obstacles; and the
// geometry of the impulse (along the contact normal only, normal relative velocity reversed).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stcore/resolve.hpp>

namespace st {
namespace {

template <int D>
Vec<D> randomVec(std::mt19937_64& rng, double h) {
  std::uniform_real_distribution<double> u(-h, h);
  Vec<D> v;
  for (int i = 0; i < D; ++i) v[i] = u(rng);
  return v;
}

template <int D>
void ballsConserve(unsigned seed, double massDecades) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> logm(-massDecades / 2, massDecades / 2), logn(-6, 6);
  for (int k = 0; k < 100000; ++k) {
    const Vec<D> va = randomVec<D>(rng, 10), vb = randomVec<D>(rng, 10);
    // contact normal of any length (the caller passes p_b - p_a)
    const Vec<D> n = randomVec<D>(rng, 1).normalized() * std::pow(10.0, logn(rng));
    const double ma = std::pow(10.0, logm(rng)), mb = std::pow(10.0, logm(rng));
    const auto out = resolveBalls<D>(va, ma, vb, mb, n);
    const Vec<D> p0 = ma * va + mb * vb, p1 = ma * out.a + mb * out.b;
    const double e0 = 0.5 * ma * va.squaredNorm() + 0.5 * mb * vb.squaredNorm();
    const double e1 = 0.5 * ma * out.a.squaredNorm() + 0.5 * mb * out.b.squaredNorm();
    ASSERT_LE((p1 - p0).norm(), 1e-12 * (ma * va.norm() + mb * vb.norm())) << k;
    ASSERT_LE(std::abs(e1 - e0), 1e-12 * e0) << k;
    // the impulse acts along n only: tangential velocities unchanged
    const Vec<D> u = n.normalized();
    const Vec<D> ta0 = va - va.dot(u) * u, ta1 = out.a - out.a.dot(u) * u;
    const Vec<D> tb0 = vb - vb.dot(u) * u, tb1 = out.b - out.b.dot(u) * u;
    ASSERT_LE((ta1 - ta0).norm(), 1e-12 * (va.norm() + vb.norm())) << k;
    ASSERT_LE((tb1 - tb0).norm(), 1e-12 * (va.norm() + vb.norm())) << k;
    // restitution 1: the normal relative velocity is reversed
    const double before = (vb - va).dot(u), after = (out.b - out.a).dot(u);
    ASSERT_NEAR(after, -before, 1e-12 * (va.norm() + vb.norm())) << k;
  }
}

TEST(Resolve, ConservesMomentumAndEnergy2D) { ballsConserve<2>(5, 4); }
TEST(Resolve, ConservesMomentumAndEnergy3D) { ballsConserve<3>(7, 4); }
// mass ratios up to 10^6: the light ball takes the impulse, the heavy one barely moves
TEST(Resolve, ConservesWithExtremeMassRatios) { ballsConserve<2>(8, 12); }

TEST(Resolve, EqualMassHeadOnSwapsVelocities) {
  const auto out = resolveBalls<2>({1, 0}, 1.0, {-1, 0}, 1.0, {1, 0});
  EXPECT_NEAR(out.a.x(), -1, 1e-15);
  EXPECT_NEAR(out.b.x(), 1, 1e-15);
}

TEST(Resolve, HeadOnUnequalMassesAnalytic) {
  // 1-D elastic collision: v_a' = ((ma - mb) va + 2 mb vb) / (ma + mb)
  const double ma = 3, mb = 1, va = 2, vb = -1;
  const auto out = resolveBalls<3>({va, 0, 0}, ma, {vb, 0, 0}, mb, {5, 0, 0});
  EXPECT_NEAR(out.a.x(), ((ma - mb) * va + 2 * mb * vb) / (ma + mb), 1e-15);
  EXPECT_NEAR(out.b.x(), ((mb - ma) * vb + 2 * ma * va) / (ma + mb), 1e-15);
}

TEST(Resolve, MovingAtTheSameVelocityNothingHappens) {
  const auto out = resolveBalls<2>({1, 2}, 1.0, {1, 2}, 5.0, {0.3, -0.7});
  EXPECT_EQ(out.a, Vec2(1, 2));
  EXPECT_EQ(out.b, Vec2(1, 2));
}

template <int D>
void reflectionKeepsSpeed(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> logn(-6, 6);
  for (int k = 0; k < 100000; ++k) {
    const Vec<D> v = randomVec<D>(rng, 10);
    // wall normal, or (ball - point) for a point obstacle: any length, either sign
    const Vec<D> n = randomVec<D>(rng, 1).normalized() * std::pow(10.0, logn(rng));
    const Vec<D> r = reflect<D>(v, n);
    ASSERT_NEAR(r.squaredNorm(), v.squaredNorm(), 1e-12 * v.squaredNorm()) << k;  // energy
    const Vec<D> u = n.normalized();
    ASSERT_NEAR(r.dot(u), -v.dot(u), 1e-12 * v.norm()) << k;
    ASSERT_LE(((r - r.dot(u) * u) - (v - v.dot(u) * u)).norm(), 1e-12 * v.norm()) << k;
    // reflecting twice restores the velocity
    ASSERT_LE((reflect<D>(r, n) - v).norm(), 1e-12 * v.norm()) << k;
  }
}

TEST(Resolve, WallAndPointReflectionKeepSpeed2D) { reflectionKeepsSpeed<2>(9); }
TEST(Resolve, WallAndPointReflectionKeepSpeed3D) { reflectionKeepsSpeed<3>(10); }

TEST(Resolve, ReflectAnalytic) {
  const Vec2 v(3, -4);
  const Vec2 r = reflect<2>(v, Vec2(0, 2));
  EXPECT_NEAR(r.x(), 3, 1e-15);
  EXPECT_NEAR(r.y(), 4, 1e-15);
  // ball striking a point obstacle at 45 degrees: normal from the point to the centre
  const Vec2 ball(1, 1), point(0, 0);
  const Vec2 out = reflect<2>(Vec2(-1, 0), ball - point);
  EXPECT_NEAR(out.x(), 0, 1e-15);
  EXPECT_NEAR(out.y(), 1, 1e-15);
}

}  // namespace
}  // namespace st
