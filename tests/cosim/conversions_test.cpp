// SUMO's conventions to ours, against hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>

#include <stcosim/conversions.hpp>

namespace st::cosim {
namespace {

constexpr double kPi = 3.14159265358979323846;

SumoVehicleType car() { return {"car", "passenger", 4.0, 2.0, std::nullopt}; }

TEST(Conversions, FrontBumperToCentreAndNavigationalToMathAngle) {
  // heading north (SUMO 0 deg): centre is half a length south of the front bumper
  SumoVehicle v;
  v.id = "a";
  v.x = 10.0;
  v.y = 20.0;
  v.angle = 0.0;
  v.speed = 5.0;
  auto s = toVehicleState(v, car());
  EXPECT_NEAR(s.heading, kPi / 2, 1e-12);
  EXPECT_NEAR(s.position.x(), 10.0, 1e-12);
  EXPECT_NEAR(s.position.y(), 18.0, 1e-12);
  EXPECT_NEAR(s.velocity().y(), 5.0, 1e-12);
  // east (90 deg): heading 0, centre 2 m west
  v.angle = 90.0;
  s = toVehicleState(v, car());
  EXPECT_NEAR(s.heading, 0.0, 1e-12);
  EXPECT_NEAR(s.position.x(), 8.0, 1e-12);
  EXPECT_NEAR(s.position.y(), 20.0, 1e-12);
  // south-west (225 deg, clockwise from north): heading -135 deg
  v.angle = 225.0;
  s = toVehicleState(v, car());
  EXPECT_NEAR(std::cos(s.heading), -std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(std::sin(s.heading), -std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(s.position.x(), 10.0 + 2.0 * std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(s.position.y(), 20.0 + 2.0 * std::sqrt(0.5), 1e-12);
}

TEST(Conversions, SublaneSpeedIsAlongTheHeading) {
  // SUMO's angle already includes the lateral motion; the speed magnitude combines both parts
  SumoVehicle v;
  v.angle = 90.0;
  v.speed = 3.0;
  v.lateralSpeed = 4.0;
  const auto s = toVehicleState(v, car());
  EXPECT_DOUBLE_EQ(s.speed, 5.0);
  EXPECT_DOUBLE_EQ(s.lateralSpeed, 0.0);
}

TEST(Conversions, MassFromParamElseClassDefault) {
  SumoVehicle v;
  SumoVehicleType truck{"t", "truck", 12.0, 2.5, std::nullopt};
  EXPECT_DOUBLE_EQ(toVehicleState(v, truck).mass, highway::classDefaults(highway::VehicleClass::Truck).mass);
  EXPECT_EQ(toVehicleState(v, truck).vehicleClass, highway::VehicleClass::Truck);
  truck.mass = 31000.0;
  EXPECT_DOUBLE_EQ(toVehicleState(v, truck).mass, 31000.0);
  EXPECT_DOUBLE_EQ(toVehicleState(v, car()).mass, highway::classDefaults(highway::VehicleClass::Passenger).mass);
}

TEST(Conversions, BlinkerBits) {
  SumoVehicle v;
  v.signals = kSumoBlinkerLeft | 8;  // left blinker + brake light
  EXPECT_EQ(toVehicleState(v, car()).signals, highway::kSignalLeft);
  v.signals = kSumoBlinkerRight;
  EXPECT_EQ(toVehicleState(v, car()).signals, highway::kSignalRight);
  // hazard lights (bit 2) announce no lane change: not a blinker, on every path alike
  v.signals = highway::kSumoHazardLights;
  EXPECT_EQ(toVehicleState(v, car()).signals, highway::kSignalNone);
}

}  // namespace
}  // namespace st::cosim
