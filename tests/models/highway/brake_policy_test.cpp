// The brake-on-warning policy against analytic cases: a foe ahead in the path and slower needs
// closing^2 / (2 gap), capped at the maximum; a foe behind, beside, faster, or one that needs less
// than the threshold, no braking.
#include <gtest/gtest.h>

#include <numbers>

#include <sthighway/brake_policy.hpp>

namespace st::highway {
namespace {

// a 5 m x 1.8 m car on the x axis (or along `heading` from the origin) at `x` m
VehicleState car(double x, double speed, double heading = 0.0) {
  VehicleState v;
  v.position = Vec2(x, 0.0);
  v.speed = speed;
  v.heading = heading;
  return v;
}

const BrakeSettings kSettings{3.0, 9.0, 1.0};

TEST(BrakePolicy, SlowerFoeAheadNeedsTheGapsDeceleration) {
  // 20 m between centres: gap 20 - 5 - 1 = 14 m, closing 15 m/s: 225 / 28 m/s^2 down to 5 m/s
  const auto b = brakeFor(car(0.0, 20.0), car(20.0, 5.0), kSettings);
  ASSERT_TRUE(b.has_value());
  EXPECT_DOUBLE_EQ(b->deceleration, 225.0 / 28.0);
  EXPECT_DOUBLE_EQ(b->targetSpeed, 5.0);
  EXPECT_DOUBLE_EQ(b->duration, 15.0 / (225.0 / 28.0));
}

TEST(BrakePolicy, TheSameAlongAnyHeading) {
  const double north = 0.5 * std::numbers::pi;
  VehicleState ego = car(0.0, 20.0, north), foe = car(0.0, 5.0, north);
  foe.position = Vec2(0.0, 20.0);
  const auto b = brakeFor(ego, foe, kSettings);
  ASSERT_TRUE(b.has_value());
  EXPECT_NEAR(b->deceleration, 225.0 / 28.0, 1e-12);
  EXPECT_NEAR(b->targetSpeed, 5.0, 1e-12);
}

TEST(BrakePolicy, CappedAtTheMaximum) {
  // gap 8 - 5 - 1 = 2 m at 20 m/s closing needs 100 m/s^2: the maximum, to a standstill
  const auto b = brakeFor(car(0.0, 20.0), car(8.0, 0.0), kSettings);
  ASSERT_TRUE(b.has_value());
  EXPECT_DOUBLE_EQ(b->deceleration, 9.0);
  EXPECT_DOUBLE_EQ(b->targetSpeed, 0.0);
  EXPECT_DOUBLE_EQ(b->duration, 20.0 / 9.0);
}

TEST(BrakePolicy, NoGapLeftBrakesAtTheMaximum) {
  // bumpers 0.5 m apart, inside the 1 m standstill gap
  const auto b = brakeFor(car(0.0, 10.0), car(5.5, 4.0), kSettings);
  ASSERT_TRUE(b.has_value());
  EXPECT_DOUBLE_EQ(b->deceleration, 9.0);
  EXPECT_DOUBLE_EQ(b->targetSpeed, 4.0);
}

TEST(BrakePolicy, AnOncomingFoeBrakesToAStandstillNotBelow) {
  // closing 20 + 10 = 30 m/s over gap 40 - 5 - 1 = 34 m: 900 / 68 m/s^2, capped; the target not negative
  const auto b = brakeFor(car(0.0, 20.0), car(40.0, 10.0, std::numbers::pi), kSettings);
  ASSERT_TRUE(b.has_value());
  EXPECT_DOUBLE_EQ(b->deceleration, 9.0);
  EXPECT_DOUBLE_EQ(b->targetSpeed, 0.0);
  EXPECT_DOUBLE_EQ(b->duration, 30.0 / 9.0);
}

TEST(BrakePolicy, AtTheThresholdBrakesBelowItNot) {
  // closing 6 m/s over gap 12 - 5 - 1 = 6 m needs exactly 36 / 12 = 3 m/s^2
  const auto at = brakeFor(car(0.0, 6.0), car(12.0, 0.0), kSettings);
  ASSERT_TRUE(at.has_value());
  EXPECT_DOUBLE_EQ(at->deceleration, 3.0);
  BrakeSettings firmer = kSettings;
  firmer.deceleration = 3.0001;
  EXPECT_FALSE(brakeFor(car(0.0, 6.0), car(12.0, 0.0), firmer).has_value());
  // gap 24 m, closing 10 m/s: 100 / 48 m/s^2, gentler than 3
  EXPECT_FALSE(brakeFor(car(0.0, 20.0), car(30.0, 10.0), kSettings).has_value());
}

TEST(BrakePolicy, NoneForAFoeBehind) {
  EXPECT_FALSE(brakeFor(car(0.0, 20.0), car(-20.0, 5.0), kSettings).has_value());
  EXPECT_FALSE(brakeFor(car(0.0, 20.0), car(0.0, 5.0), kSettings).has_value());  // level with us
}

TEST(BrakePolicy, NoneForAFoeBeside) {
  VehicleState foe = car(20.0, 5.0);
  foe.position.y() = 3.2;  // the next lane
  EXPECT_FALSE(brakeFor(car(0.0, 20.0), foe, kSettings).has_value());
  foe.position.y() = 1.8;  // bodies touching sideways, not overlapping
  EXPECT_FALSE(brakeFor(car(0.0, 20.0), foe, kSettings).has_value());
  foe.position.y() = -1.7;  // overlapping by 0.1 m: in our path
  EXPECT_TRUE(brakeFor(car(0.0, 20.0), foe, kSettings).has_value());
}

TEST(BrakePolicy, NoneForAFasterFoeOrOneAsFast) {
  EXPECT_FALSE(brakeFor(car(0.0, 20.0), car(20.0, 25.0), kSettings).has_value());
  EXPECT_FALSE(brakeFor(car(0.0, 20.0), car(20.0, 20.0), kSettings).has_value());
}

TEST(BrakePolicy, OnlyTheFoesSpeedAlongOurHeadingCounts) {
  // a foe crossing our path at right angles closes at our full speed: 400 / 28 m/s^2, capped, to 0
  const auto b = brakeFor(car(0.0, 20.0), car(20.0, 15.0, 0.5 * std::numbers::pi), kSettings);
  ASSERT_TRUE(b.has_value());
  EXPECT_DOUBLE_EQ(b->deceleration, 9.0);
  EXPECT_NEAR(b->targetSpeed, 0.0, 1e-12);
}

}  // namespace
}  // namespace st::highway
