// The conflict kernels against hand-computed values: SSAM's angle thresholds, DRAC, MaxDeltaV.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <sthighway/conflict.hpp>

namespace st::highway {
namespace {

constexpr double kPi = 3.14159265358979323846;
double rad(double deg) { return deg * kPi / 180.0; }

TEST(Conflict, RelativeHeadingFoldsIntoZeroTo180) {
  EXPECT_NEAR(relativeHeadingDeg(0.0, 0.0), 0.0, 1e-12);
  EXPECT_NEAR(relativeHeadingDeg(rad(10), rad(350)), 20.0, 1e-9);  // across the wrap
  EXPECT_NEAR(relativeHeadingDeg(rad(-170), rad(170)), 20.0, 1e-9);
  EXPECT_NEAR(relativeHeadingDeg(rad(90), 0.0), 90.0, 1e-9);
  EXPECT_NEAR(relativeHeadingDeg(0.0, rad(90)), 90.0, 1e-9);       // symmetric
  EXPECT_NEAR(relativeHeadingDeg(rad(180), 0.0), 180.0, 1e-9);
  EXPECT_NEAR(relativeHeadingDeg(rad(725), rad(5)), 0.0, 1e-9);    // two turns apart
}

TEST(Conflict, TypeBySsamThresholds) {
  const ConflictConfig ssam;
  EXPECT_EQ(conflictType(0.0, ssam), ConflictType::RearEnd);
  EXPECT_EQ(conflictType(29.9, ssam), ConflictType::RearEnd);
  EXPECT_EQ(conflictType(30.0, ssam), ConflictType::LaneChange);  // "below 30" is a rear-end
  EXPECT_EQ(conflictType(60.0, ssam), ConflictType::LaneChange);
  EXPECT_EQ(conflictType(85.0, ssam), ConflictType::LaneChange);  // "above 85" is a crossing
  EXPECT_EQ(conflictType(85.1, ssam), ConflictType::Crossing);
  EXPECT_EQ(conflictType(180.0, ssam), ConflictType::Crossing);
  // the thresholds are the caller's
  const ConflictConfig tight{10.0, 45.0};
  EXPECT_EQ(conflictType(20.0, tight), ConflictType::LaneChange);
  EXPECT_EQ(conflictType(50.0, tight), ConflictType::Crossing);
  EXPECT_STREQ(toString(ConflictType::RearEnd), "rear_end");
  EXPECT_STREQ(toString(ConflictType::Road), "road");
}

TEST(Conflict, DracIsClosingSpeedSquaredOverTwiceTheGap) {
  // follower 30 m/s, leader 20 m/s, 10 m apart: TTC 1 s, DRAC = 10^2 / (2 * 10) = 5 m/s^2
  EXPECT_DOUBLE_EQ(decelerationToAvoid(10.0, 1.0), 5.0);
  // 4 m/s towards a curb 2 m away: TTC 0.5 s, 16 / 4 = 4 m/s^2
  EXPECT_DOUBLE_EQ(decelerationToAvoid(4.0, 0.5), 4.0);
  EXPECT_EQ(decelerationToAvoid(0.0, 1.0), 0.0);   // not closing
  EXPECT_EQ(decelerationToAvoid(-3.0, 0.0), 0.0);  // touching, moving apart
  EXPECT_EQ(decelerationToAvoid(3.0, 0.0), std::numeric_limits<double>::infinity());
}

TEST(Conflict, DeltaVOfAPerfectlyInelasticImpact) {
  // a car (1500 kg, 30 m/s) into a truck (15 t, 20 m/s) ahead: common velocity
  // (1500*30 + 15000*20)/16500 = 20.909 m/s; the car loses 9.0909, the truck gains 0.9091
  const Vec2 car(30.0, 0.0), truck(20.0, 0.0);
  EXPECT_NEAR(deltaV(1500.0, car, 15000.0, truck), 30.0 - 345000.0 / 16500.0, 1e-12);
  EXPECT_NEAR(deltaV(15000.0, truck, 1500.0, car), 345000.0 / 16500.0 - 20.0, 1e-12);
  EXPECT_NEAR(maxDeltaV(1500.0, car, 15000.0, truck), 100.0 / 11.0, 1e-12);
  EXPECT_NEAR(maxDeltaV(15000.0, truck, 1500.0, car), 100.0 / 11.0, 1e-12);  // symmetric
  // two equal cars crossing at right angles at 10 m/s: |dv| = 10 sqrt 2, each takes half
  EXPECT_NEAR(maxDeltaV(1500.0, Vec2(10.0, 0.0), 1500.0, Vec2(0.0, 10.0)), 5.0 * std::sqrt(2.0), 1e-12);
  // momentum is conserved: m_a dv_a = m_b dv_b
  EXPECT_NEAR(1500.0 * deltaV(1500.0, car, 15000.0, truck), 15000.0 * deltaV(15000.0, truck, 1500.0, car), 1e-9);
}

}  // namespace
}  // namespace st::highway
