// SUMO's bodies along their paths (PathBodies): SUMO puts a vehicle's back `length` metres of
// path behind its front and points its angle from that back to the front. Fed a front driven
// along a known path with SUMO's angle worked out from the exact back, the fitted body's back must
// be that back; on straight road the body is exactly toVehicleState's.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <sthighway/sumo_conversion.hpp>

namespace st::highway {
namespace {

constexpr double kR = 5.6;  // the corner of networks/intersection's right and left turns (m)
constexpr double kTruck = 10.0;

// A lane along +x to the origin, a left quarter circle of radius kR, then along +y; `offset` to
// the left of it (a parallel lane). s: metres along the lane from the origin.
Vec2 lanePoint(double s, double offset = 0.0) {
  const double r = kR - offset, quarter = 0.5 * std::numbers::pi * r;
  if (s <= 0.0) return {s, offset};
  if (s <= quarter) return {r * std::sin(s / r), kR - r * std::cos(s / r)};
  return {r, kR + (s - quarter)};
}

// The record SUMO reports for a front at s with its back `length` behind on the same lane.
SumoVehicleRecord sumoAt(Vec2 front, Vec2 back) {
  SumoVehicleRecord r;
  r.x = front.x();
  r.y = front.y();
  const Vec2 d = front - back;
  r.angle = 90.0 - std::atan2(d.y(), d.x()) * 180.0 / std::numbers::pi;
  r.speed = 8.0;
  return r;
}

VehicleTypeInfo truck() {
  SumoTypeRecord t;
  t.vClass = "truck";
  t.length = kTruck;
  t.width = 2.5;
  return toVehicleTypeInfo(t);
}

Vec2 backOf(const VehicleState& s) { return s.position - 0.5 * s.length * s.direction(); }

// A truck at 8 m/s, 0.1 s steps, through the corner: its back is SUMO's to a few cm throughout
// (the trail's 0.8 m chords cut the corner by s^2 / 8R = 0.014 m), where laying the full 10 m along
// SUMO's angle puts it 1.2 m off.
TEST(PathBodies, TheBodyIsTheChordFromSumosBackToItsFront) {
  PathBodies bodies;
  double worstFitted = 0.0, worstFull = 0.0, shortest = kTruck;
  int straight = 0;
  for (int k = 0; k <= 60; ++k) {
    const double s = -20.0 + 0.8 * k;
    const Vec2 front = lanePoint(s), back = lanePoint(s - kTruck);
    VehicleState full;
    toVehicleState(sumoAt(front, back), truck(), full);
    VehicleState fitted = full;
    bodies.fit(7, 0.1 * k, fitted);
    worstFitted = std::max(worstFitted, (backOf(fitted) - back).norm());
    worstFull = std::max(worstFull, (backOf(full) - back).norm());
    shortest = std::min(shortest, fitted.length);
    // both ends on the straight: as toVehicleState laid it, to the bit
    if (s <= 0.0 || s - kTruck >= 0.5 * std::numbers::pi * kR) {
      EXPECT_EQ(fitted.length, kTruck) << s;
      EXPECT_EQ(fitted.position, full.position) << s;
      ++straight;
    }
    EXPECT_EQ(fitted.heading, full.heading);
  }
  EXPECT_LT(worstFitted, 0.03);
  EXPECT_GT(worstFull, 1.0);
  // the shortest chord: back and front on a circle's ends 10 m of path apart, or near it
  EXPECT_NEAR(shortest, 2.0 * kR * std::sin(kTruck / (2.0 * kR)), 0.4);
  EXPECT_GT(straight, 20);
}

// SUMO (without the sublane model) changes lanes in one step, back and all: the trail moves with
// the front, and the back on the corner after is the new lane's.
TEST(PathBodies, ALaneChangeInOneStepMovesTheTrailWithIt) {
  PathBodies bodies;
  const double width = 3.2;
  double worst = 0.0;
  for (int k = 0; k <= 50; ++k) {
    const double s = -12.0 + 0.8 * k;
    const double offset = s < -4.0 ? -width : 0.0;  // from the lane to the right, 4 m before the corner
    const Vec2 front = lanePoint(s, offset), back = lanePoint(s - kTruck, offset);
    VehicleState v;
    toVehicleState(sumoAt(front, back), truck(), v);
    bodies.fit(0, 0.1 * k, v);
    if (s > 0.0 && s < 8.0) worst = std::max(worst, (backOf(v) - back).norm());
  }
  EXPECT_LT(worst, 0.03);
}

// Where the trail cannot say: just inserted (no path behind it yet), an angle that does not
// point from the trail's back (SUMO's sublane model turns it with the lateral motion), a trace
// too coarse to follow the corner, a person: the full length along SUMO's angle.
TEST(PathBodies, FullLengthWhereTheTrailCannotSay) {
  const auto run = [](double step, double turn, const char* vClass) {
    PathBodies bodies;
    SumoTypeRecord t;
    t.vClass = vClass;
    t.length = kTruck;
    const VehicleTypeInfo type = toVehicleTypeInfo(t);
    double shortest = kTruck;
    for (int k = 0; k * step <= 20.0; ++k) {
      const double s = -2.0 + step * k;  // inserted 2 m before the corner
      SumoVehicleRecord r = sumoAt(lanePoint(s), lanePoint(s - kTruck));
      r.angle += turn;
      VehicleState v;
      toVehicleState(r, type, v);
      bodies.fit(3, 0.1 * k, v);
      shortest = std::min(shortest, v.length);
    }
    return shortest;
  };
  EXPECT_EQ(run(0.8, 5.0, "truck"), kTruck);        // the angle 5 degrees off the chord
  EXPECT_EQ(run(8.0, 0.0, "truck"), kTruck);        // one sample per 8 m
  EXPECT_EQ(run(0.8, 0.0, "pedestrian"), kTruck);   // a person
  EXPECT_LT(run(0.8, 0.0, "truck"), kTruck - 0.5);  // the same truck, followed from 2 m before the corner
}

// A new run (time going back) starts every trail again: its first step is the full length.
TEST(PathBodies, ANewRunStartsTheTrailAgain) {
  PathBodies bodies;
  VehicleState v;
  for (int k = 0; k <= 25; ++k) {
    const double s = -10.0 + 0.8 * k;  // to 10 m, the back at the corner's start
    toVehicleState(sumoAt(lanePoint(s), lanePoint(s - kTruck)), truck(), v);
    bodies.fit(0, 0.1 * k, v);
  }
  ASSERT_LT(v.length, kTruck - 0.5);
  toVehicleState(sumoAt(lanePoint(10.0), lanePoint(0.0)), truck(), v);
  bodies.fit(0, 0.0, v);
  EXPECT_EQ(v.length, kTruck);
}

}  // namespace
}  // namespace st::highway
