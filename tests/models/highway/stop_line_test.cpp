// A car that must stop at a red light's stop line (VehicleState::stopDistance): predicted braking
// evenly to stand there, under either motion model and every detector; worked by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <sthighway/detector.hpp>
#include <sthighway/monitor.hpp>
#include <sthighway/sumo_conversion.hpp>

namespace st::highway {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A 4 m car at x = 0 (front at 2) heading east at 10 m/s; a stopped 4 m car ahead whose rear is
// `gap` m beyond the first one's front.
VehicleState mover(double stopDistance, std::string id = "a") {
  VehicleState v;
  v.id = std::move(id);
  v.length = 4.0;
  v.width = 1.8;
  v.speed = 10.0;
  v.stopDistance = stopDistance;
  return v;
}
VehicleState standing(double gap) {
  VehicleState v;
  v.id = "b";
  v.length = 4.0;
  v.width = 1.8;
  v.position = Vec2(2.0 + gap + 2.0, 0.0);
  return v;
}

TEST(StopLine, BrakesEvenlyToStandAtTheLine) {
  for (DetectorKind kind : {DetectorKind::Box, DetectorKind::FiveCircle, DetectorKind::Concentric})
    for (MotionModel motion : {MotionModel::ConstantVelocity, MotionModel::ConstantAcceleration}) {
      DetectorConfig cfg;
      cfg.kind = kind;
      cfg.motion = motion;
      const char* what = toString(kind);
      // no light: the front covers the 15 m gap at 10 m/s
      if (kind == DetectorKind::Box) {
        EXPECT_NEAR(vehicleTtc(cfg, bodyOf(mover(kInf)), bodyOf(standing(15.0)), 10.0).t(), 1.5, 1e-6) << what;
        // red 20 m ahead: a = -u^2 / (2 d) = -2.5 m/s^2, 10 t - 1.25 t^2 = 15 at t = 2 s
        EXPECT_NEAR(vehicleTtc(cfg, bodyOf(mover(20.0)), bodyOf(standing(15.0)), 10.0).t(), 2.0, 1e-6) << what;
      }
      // a car standing beyond the line is never reached: it stops 5 m short, at the line
      EXPECT_FALSE(vehicleTtc(cfg, bodyOf(mover(20.0)), bodyOf(standing(25.0)), 30.0).found()) << what;
      EXPECT_TRUE(vehicleTtc(cfg, bodyOf(mover(kInf)), bodyOf(standing(25.0)), 30.0).found()) << what;
      // a foe crossing the lane 30 m ahead (beyond the line) as the car would get there: no conflict
      VehicleState cross;
      cross.id = "c";
      cross.heading = M_PI / 2;
      cross.speed = 10.0;
      cross.position = Vec2(2.0 + 30.0 + 1.0, -30.0);
      EXPECT_TRUE(vehicleTtc(cfg, bodyOf(mover(kInf)), bodyOf(cross), 10.0).found()) << what;
      EXPECT_FALSE(vehicleTtc(cfg, bodyOf(mover(20.0)), bodyOf(cross), 10.0).found()) << what;
    }
}

TEST(StopLine, TheMonitorWarnsOfTheCarBehindNotOfTheCrossTraffic) {
  // the follower closes on a leader slowing to its red: warned earlier than at constant speeds
  MonitorConfig cfg;
  cfg.detector.kind = DetectorKind::Box;
  cfg.checkRoad = false;
  for (double stop : {kInf, 20.0}) {
    HighwayMonitor m(RoadGeometry{}, cfg);
    VehicleState lead = mover(stop);
    // 1 m ahead: 1.25 t^2 = 1 at t = 0.894 s, within the safe time (1 s reaction at no closing speed)
    lead.position = Vec2(5.0, 0.0);
    const VehicleState follow = mover(kInf, "f");
    std::vector<VehicleState> tick{lead, follow};
    m.step(0.0, tick);
    bool warned = false;
    for (const auto& a : m.alerts()) {
      warned = warned || (a.vehicle == 1 && a.foe == 0);
      if (a.vehicle == 1 && a.foe == 0) {
        EXPECT_NEAR(a.ttc, std::sqrt(1.0 / 1.25), 1e-6);
      }
    }
    EXPECT_EQ(warned, stop < kInf) << stop;  // same speeds: only the braking leader is a threat
  }
}

TEST(StopLine, SumoLightStatesToStopDistances) {
  SumoVehicleRecord v;
  v.speed = 10.0;
  v.nextSignalDistance = 30.0;
  for (char red : {'r', 'u', 's', 'w'}) {
    v.nextSignal = red;
    EXPECT_EQ(stopDistanceOf(v, 4.5), 30.0) << red;
  }
  for (char go : {'G', 'M', 'o', 'O', '\0'}) {
    v.nextSignal = go;
    EXPECT_EQ(stopDistanceOf(v, 4.5), kInf) << go;
  }
  // yellow: stops if u^2 / (2 d) is within its decel (10^2 / 60 = 1.67 m/s^2), else goes on
  v.nextSignal = 'y';
  EXPECT_EQ(stopDistanceOf(v, 4.5), 30.0);
  EXPECT_EQ(stopDistanceOf(v, 1.5), kInf);
  v.nextSignalDistance = 11.0;  // 4.55 m/s^2 needed
  EXPECT_EQ(stopDistanceOf(v, 4.5), kInf);
  EXPECT_EQ(stopDistanceOf(v, std::numeric_limits<double>::quiet_NaN()), kInf);  // SUMO's 4.5 assumed
  v.nextSignalDistance = 11.2;  // 4.46 m/s^2
  EXPECT_EQ(stopDistanceOf(v, std::numeric_limits<double>::quiet_NaN()), 11.2);
}

// Where it gives way (a light's minor green g, a junction's minor link m, equal priority =): it
// stands there if it can stop at its own decel from one step of SUMO's travel further back
// (u^2 <= 2 b (d + u 0.1 s), tol::kYieldStepSlack); one that cannot has taken its gap
TEST(StopLine, SumoYieldStatesToStopDistances) {
  SumoVehicleRecord v;
  v.speed = 10.0;
  for (char yield : {'g', 'm', '='}) {
    v.nextSignal = yield;
    v.nextSignalDistance = 30.0;  // 10^2 / (2 x 31) = 1.61 m/s^2
    EXPECT_EQ(stopDistanceOf(v, 4.5), 30.0) << yield;
    EXPECT_EQ(stopDistanceOf(v, 1.5), kInf) << yield;
    v.nextSignalDistance = 10.0;  // 10^2 / (2 x 11) = 4.55 m/s^2: past the point where it could
    EXPECT_EQ(stopDistanceOf(v, 4.5), kInf) << yield;
    v.nextSignalDistance = 10.2;  // 10^2 / (2 x 11.2) = 4.46 m/s^2
    EXPECT_EQ(stopDistanceOf(v, 4.5), 10.2) << yield;
  }
  // standing at its line, it waits there
  v.speed = 0.0;
  v.nextSignal = 'm';
  v.nextSignalDistance = 0.0;
  EXPECT_EQ(stopDistanceOf(v, 4.5), 0.0);
}

}  // namespace
}  // namespace st::highway

// SUMO's internal lanes, crossings and walking areas name their junction; a junction id may hold
// '_' itself; a lane between junctions (or an unknown one) lies in none
TEST(JunctionOfLane, SumosInternalLaneNames) {
  EXPECT_EQ(st::highway::junctionOfLane(":C_12_0"), "C");
  EXPECT_EQ(st::highway::junctionOfLane(":C_c0_0"), "C");
  EXPECT_EQ(st::highway::junctionOfLane(":C_w1_0"), "C");
  EXPECT_EQ(st::highway::junctionOfLane(":cluster_1_2_5_0"), "cluster_1_2");
  EXPECT_EQ(st::highway::junctionOfLane(":J10_3_1"), "J10");
  EXPECT_EQ(st::highway::junctionOfLane("s_in_1"), "");
  EXPECT_EQ(st::highway::junctionOfLane(":C_0"), "");
  EXPECT_EQ(st::highway::junctionOfLane(""), "");
  EXPECT_EQ(st::highway::junctionOfLane(":"), "");
}
