#include <gtest/gtest.h>

#include <random>
#include <stcore/resolve.hpp>

namespace st {
namespace {

TEST(Resolve, EqualMassHeadOnSwapsVelocities) {
  const auto out = resolveBalls<2>({1, 0}, 1.0, {-1, 0}, 1.0, {1, 0});
  EXPECT_NEAR(out.a.x(), -1, 1e-15);
  EXPECT_NEAR(out.b.x(), 1, 1e-15);
}

TEST(Resolve, ConservesMomentumAndEnergyRandom) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-10, 10), m(0.01, 100);
  for (int k = 0; k < 100000; ++k) {
    const Vec3 va(u(rng), u(rng), u(rng)), vb(u(rng), u(rng), u(rng)), n(u(rng), u(rng), u(rng));
    const double ma = m(rng), mb = m(rng);
    const auto out = resolveBalls<3>(va, ma, vb, mb, n);
    const Vec3 p0 = ma * va + mb * vb, p1 = ma * out.a + mb * out.b;
    const double e0 = 0.5 * ma * va.squaredNorm() + 0.5 * mb * vb.squaredNorm();
    const double e1 = 0.5 * ma * out.a.squaredNorm() + 0.5 * mb * out.b.squaredNorm();
    ASSERT_LE((p1 - p0).norm(), 1e-12 * (ma * va.norm() + mb * vb.norm()));
    ASSERT_LE(std::abs(e1 - e0), 1e-12 * e0);
  }
}

TEST(Resolve, ReflectKeepsSpeed) {
  const Vec2 v(3, -4);
  const Vec2 r = reflect<2>(v, Vec2(0, 2));
  EXPECT_NEAR(r.x(), 3, 1e-15);
  EXPECT_NEAR(r.y(), 4, 1e-15);
}

}  // namespace
}  // namespace st
