// SSAM's measures of a warning (FHWA's Surrogate Safety Assessment Model) against analytic
// encounters: the contact point of two rectangles on a known collision course, DeltaS, the
// conflict and clock angle, the post-crash velocity by conservation of momentum, MaxS, DR and MaxD
// from a speed profile given tick by tick, the start and end points.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <sthighway/conflict.hpp>
#include <sthighway/monitor.hpp>
#include <sthighway/report.hpp>
#include <sthighway/sumo_files.hpp>

#include "conflict_capture.hpp"
#include "files.hpp"
#include "roads.hpp"

namespace st::highway {
namespace {

constexpr double kPi = 3.14159265358979323846;
namespace fs = std::filesystem;
constexpr double kInf = std::numeric_limits<double>::infinity();

VehicleState car(const std::string& id, Vec2 p, double headingDeg, double speed) {
  VehicleState v;
  v.id = id;
  v.position = p;
  v.heading = headingDeg * kPi / 180.0;
  v.speed = speed;
  return v;
}

MonitorConfig boxStraight() {
  MonitorConfig cfg;
  cfg.detector.kind = DetectorKind::Box;  // the rectangles' own TTC
  cfg.prediction = Prediction::Straight;  // straight lines: the analytic motion
  cfg.broadphase = Broadphase::AllPairs;
  cfg.checkRoad = false;
  return cfg;
}

const Warning* find(const std::vector<Warning>& ws, const std::string& ego) {
  for (const auto& w : ws)
    if (w.ego == ego && w.kind == WarningKind::Vehicle) return &w;
  return nullptr;
}
// the warnings must outlive the pointer: a temporary would be gone before the pointer is read
const Warning* find(std::vector<Warning>&& ws, const std::string& ego) = delete;

TEST(SsamKernels, ContactPointOfTwoRectangles) {
  const Vec2 x(1.0, 0.0);
  // flat rear-end, equal widths: the middle of the common edge
  Vec2 p = contactPoint({Vec2(0.0, 0.0), x, Vec2(2.5, 0.9)}, {Vec2(5.0, 0.0), x, Vec2(2.5, 0.9)}, 1e-3);
  EXPECT_NEAR(p.x(), 2.5, 1e-12);
  EXPECT_NEAR(p.y(), 0.0, 1e-12);
  // a car (1.8 m) into a truck (2.55 m), offset 0.3 m sideways: the middle of the car's front
  p = contactPoint({Vec2(0.0, 0.3), x, Vec2(2.5, 0.9)}, {Vec2(8.5, 0.0), x, Vec2(6.0, 1.275)}, 1e-3);
  EXPECT_NEAR(p.x(), 2.5, 1e-12);
  EXPECT_NEAR(p.y(), 0.3, 1e-12);
  // a corner into a side: the corner; rotated 45 degrees, the corner at (0, 0) meets the edge y = 0
  const Vec2 d = Vec2(1.0, 1.0).normalized();
  p = contactPoint({Vec2(0.0, -1.0), x, Vec2(2.0, 1.0)}, {Vec2(0.0, std::sqrt(2.0)), d, Vec2(1.0, 1.0)}, 1e-3);
  EXPECT_NEAR(p.x(), 0.0, 1e-12);
  EXPECT_NEAR(p.y(), 0.0, 1e-12);
  // symmetric in its two boxes
  const Box2 a{Vec2(0.3, 0.1), Vec2(0.8, 0.6), Vec2(2.5, 0.9)}, b{Vec2(4.0, 1.7), Vec2(0.0, 1.0), Vec2(2.0, 0.8)};
  EXPECT_NEAR((contactPoint(a, b, 1e-3) - contactPoint(b, a, 1e-3)).norm(), 0.0, 1e-12);
}

TEST(SsamKernels, ConflictAngleAndClock) {
  const Vec2 east(1.0, 0.0), north(0.0, 1.0), west(-1.0, 0.0), south(0.0, -1.0);
  EXPECT_NEAR(conflictAngleDeg(east, east), 0.0, 1e-12);
  EXPECT_NEAR(conflictAngleDeg(east, north), 90.0, 1e-12);   // the foe heads to the ego's left: from its right
  EXPECT_NEAR(conflictAngleDeg(east, south), -90.0, 1e-12);  // from its left
  EXPECT_NEAR(conflictAngleDeg(east, west), 180.0, 1e-12);   // head-on, never -180
  EXPECT_NEAR(conflictAngleDeg(north, east), -90.0, 1e-12);
  EXPECT_EQ(clockPosition(0.0), 12);
  EXPECT_EQ(clockPosition(14.9), 12);
  EXPECT_EQ(clockPosition(-14.9), 12);
  EXPECT_EQ(clockPosition(15.1), 1);
  EXPECT_EQ(clockPosition(90.0), 3);
  EXPECT_EQ(clockPosition(180.0), 6);
  EXPECT_EQ(clockPosition(-90.0), 9);
  EXPECT_EQ(clockPosition(-30.0), 11);
}

TEST(SsamKernels, PostCrashVelocityConservesMomentum) {
  const Vec2 va(30.0, 0.0), vb(0.0, -12.0);
  const Vec2 v = postCrashVelocity(1500.0, va, 15000.0, vb);
  EXPECT_NEAR((16500.0 * v - (1500.0 * va + 15000.0 * vb)).norm(), 0.0, 1e-9);
  // each vehicle's change of velocity is its deltaV (SSAM's MaxDeltaV the larger)
  EXPECT_NEAR((v - va).norm(), deltaV(1500.0, va, 15000.0, vb), 1e-12);
  EXPECT_NEAR((v - vb).norm(), deltaV(15000.0, vb, 1500.0, va), 1e-12);
}

// Two cars at right angles, each 10 m/s: "east" (5 x 1.8 m, 1500 kg) with its front 5 m short of
// the other's left side, "north" (3000 kg) whose rear reaches east's path as east arrives. They
// touch at t = 0.5 s along x = -0.9 over y in [0, 0.9]: the conflict point is its middle.
TEST(SsamMeasures, RightAngleCollisionCourseByHand) {
  VehicleState a = car("east", Vec2(-8.4, 0.0), 0.0, 10.0);
  VehicleState b = car("north", Vec2(0.0, -2.5), 90.0, 10.0);
  a.mass = 1500.0;
  b.mass = 3000.0;
  HighwayMonitor m(oneLaneRoad(), boxStraight());
  m.step(0.0, std::vector<VehicleState>{a, b});
  m.finish(0.1);
  const auto ws = m.takeFinished();
  const Vec2 va(10.0, 0.0), vb(0.0, 10.0);
  const Vec2 vc = (1500.0 * va + 3000.0 * vb) / 4500.0;  // momentum conserved
  for (const char* ego : {"east", "north"}) {
    const Warning* w = find(ws, ego);
    ASSERT_NE(w, nullptr) << ego;
    const bool east = std::string(ego) == "east";
    EXPECT_NEAR(w->minTtc, 0.5, 1e-9) << ego;
    EXPECT_EQ(w->type, ConflictType::Crossing) << ego;
    EXPECT_NEAR(w->conflictX, -0.9, 1e-9) << ego;
    EXPECT_NEAR(w->conflictY, 0.45, 1e-9) << ego;
    // both vehicles at the tick of the minimum TTC
    EXPECT_NEAR(w->x, east ? -8.4 : 0.0, 1e-12);
    EXPECT_NEAR(w->foeX, east ? 0.0 : -8.4, 1e-12);
    EXPECT_NEAR(w->foeY, east ? -2.5 : 0.0, 1e-12);
    EXPECT_NEAR(w->deltaSpeed, 10.0 * std::sqrt(2.0), 1e-9);
    EXPECT_NEAR(w->conflictAngle, east ? 90.0 : -90.0, 1e-9);  // north comes from east's right
    EXPECT_EQ(w->clockAngle, east ? 3.0 : 9.0);
    EXPECT_NEAR(w->postCrashSpeed, vc.norm(), 1e-9);
    EXPECT_NEAR(w->postCrashHeading, std::atan2(vc.y(), vc.x()) * 180.0 / kPi, 1e-9);
    EXPECT_NEAR(w->maxSpeed, 10.0, 1e-12);
    // one tick: no acceleration seen after begin
    EXPECT_TRUE(std::isnan(w->dr));
    EXPECT_TRUE(std::isnan(w->maxDecel));
    EXPECT_NEAR(w->startX, east ? -8.4 : 0.0, 1e-12);
    EXPECT_NEAR(w->endX, w->startX, 1e-12);
  }
}

// A rear-end: the conflict point is where the follower's front meets the truck's rear.
TEST(SsamMeasures, RearEndConflictPointIsTheLeadersRearThen) {
  // follower at 30 m/s, a 12 m truck at 20 m/s, 15 m bumper to bumper: contact after 1.5 s at the
  // truck's rear, 23.5 + 20 * 1.5 - 6 = 47.5
  VehicleState f = car("follower", Vec2(0.0, 0.0), 0.0, 30.0);
  VehicleState l = car("truck", Vec2(23.5, 0.0), 0.0, 20.0);
  l.length = 12.0;
  l.width = 2.55;
  l.mass = 15000.0;
  l.equipped = false;
  HighwayMonitor m(oneLaneRoad(), boxStraight());
  m.step(0.0, std::vector<VehicleState>{f, l});
  m.finish(0.1);
  const std::vector<Warning> finished = m.takeFinished();
  const Warning* w = find(finished, "follower");
  ASSERT_NE(w, nullptr);
  EXPECT_NEAR(w->minTtc, 1.5, 1e-9);
  EXPECT_NEAR(w->conflictX, 47.5, 1e-9);
  EXPECT_NEAR(w->conflictY, 0.0, 1e-9);
  EXPECT_NEAR(w->deltaSpeed, 10.0, 1e-12);
  EXPECT_EQ(w->clockAngle, 12.0);
  EXPECT_NEAR(w->postCrashSpeed, (1500.0 * 30.0 + 15000.0 * 20.0) / 16500.0, 1e-9);
  EXPECT_NEAR(w->postCrashHeading, 0.0, 1e-12);
}

// MaxS, DR and MaxD from a speed profile given tick by tick (0.1 s): the follower speeds up, then
// brakes at 5, 7 and 2 m/s^2, closing on a leader at 20 m/s throughout the episode.
TEST(SsamMeasures, MaxSDrAndMaxDFromTheSpeedProfile) {
  struct Profile {
    std::vector<double> speeds;
    double maxS, dr, maxD;
  };
  const Profile cases[] = {
      // SSAM's DR: the first negative acceleration after begin (-5), MaxD the lowest (-7)
      {{30.0, 30.2, 29.7, 29.0, 28.8}, 30.2, -5.0, -7.0},
      // no braking: DR is the lowest acceleration, MaxD positive
      {{30.0, 30.5, 30.7, 30.8}, 30.8, 1.0, 1.0}};
  for (const Profile& pr : cases) {
    HighwayMonitor m(oneLaneRoad(), boxStraight());
    double xf = 0.0, t = 0.0;
    std::vector<Vec2> centres;
    for (std::size_t k = 0; k < pr.speeds.size(); ++k) {
      t = 0.1 * static_cast<double>(k);
      if (k > 0) xf += 0.1 * pr.speeds[k];
      VehicleState f = car("follower", Vec2(xf, 0.0), 0.0, pr.speeds[k]);
      VehicleState l = car("leader", Vec2(13.0 + 20.0 * t, 0.0), 0.0, 20.0);  // 8 m ahead at first
      l.equipped = false;
      centres.push_back(f.position);
      m.step(t, std::vector<VehicleState>{f, l});
    }
    m.finish(t + 0.1);
    const auto ws = m.takeFinished();
    ASSERT_EQ(ws.size(), 1u);
    const Warning& w = ws.front();
    EXPECT_NEAR(w.begin, 0.0, 1e-12);
    EXPECT_NEAR(w.maxSpeed, pr.maxS, 1e-12);
    EXPECT_NEAR(w.dr, pr.dr, 1e-9);
    EXPECT_NEAR(w.maxDecel, pr.maxD, 1e-9);
    EXPECT_NEAR(w.startX, centres.front().x(), 1e-12);
    EXPECT_NEAR(w.endX, centres.back().x(), 1e-12);  // closed by finish: its last tick
    EXPECT_NEAR(w.endY, 0.0, 1e-12);
  }
}

// An episode that ends at a tick without the threat: its end point is the ego there.
TEST(SsamMeasures, EndPointIsTheEgoAtTheFirstTickWithout) {
  HighwayMonitor m(oneLaneRoad(), boxStraight());
  VehicleState f = car("follower", Vec2(0.0, 0.0), 0.0, 30.0);
  VehicleState l = car("leader", Vec2(13.0, 0.0), 0.0, 20.0);
  l.equipped = false;
  m.step(0.0, std::vector<VehicleState>{f, l});
  // the follower slowed to the leader's speed: no collision course
  f.position = Vec2(2.5, 0.0);
  f.speed = 20.0;
  l.position = Vec2(15.0, 0.0);
  m.step(0.1, std::vector<VehicleState>{f, l});
  m.finish(0.2);
  const std::vector<Warning> finished = m.takeFinished();
  const Warning* w = find(finished, "follower");
  ASSERT_NE(w, nullptr);
  EXPECT_NEAR(w->end, 0.1, 1e-12);
  EXPECT_NEAR(w->startX, 0.0, 1e-12);
  EXPECT_NEAR(w->endX, 2.5, 1e-12);
  EXPECT_NEAR(w->dr, -100.0, 1e-9);  // 30 -> 20 m/s in 0.1 s
  EXPECT_NEAR(w->maxSpeed, 30.0, 1e-12);
}

// Road warnings leave SSAM's columns empty.
TEST(SsamMeasures, RoadWarningsLeaveTheColumnsEmpty) {
  MonitorConfig cfg = boxStraight();
  cfg.checkRoad = true;
  cfg.prediction = Prediction::Road;
  VehicleState d = car("drifter", Vec2(0.0, 0.0), 0.0, 25.0);
  d.lateralSpeed = -2.0;
  HighwayMonitor m(oneLaneRoad(), cfg);
  m.step(0.0, std::vector<VehicleState>{d});
  m.finish(0.1);
  const auto ws = m.takeFinished();
  ASSERT_FALSE(ws.empty());
  const std::string row = warningCsvRow(ws.front());
  EXPECT_NE(row.find(std::string(",") + std::string(17, ',')), std::string::npos) << row;  // 17 empty cells in a row
  const std::string h = warningsCsvHeader();
  EXPECT_NE(h.find(",signalled,conflict_x,conflict_y,foe_x,foe_y,max_s,delta_s,dr,max_d,conflict_angle,clock_angle,"
                   "start_x,start_y,end_x,end_y,post_crash_speed,post_crash_heading,pet,x,y,"),
            std::string::npos)
      << h;
}


// The PET watch's conflict area where two paths cross at 40 degrees, worked out by hand from
// SUMO's junction model (MSLink: a conflict W (2 / sin a - 1) long on a lane crossing one of width
// W, centred on the crossing) and SSM's area (from (W - w) / 2 into it, w + L long): with W 3.2 m,
// w 1.8 m, L 4.6 m the area runs from 2.6783 m before the crossing to 3.7217 m past it. "a" drives
// east at 10 m/s, its front 20 m before the crossing; "b" at 5 m/s along 40 degrees, 30 m before.
// a: in at 1.73217 s, out at 2.37217 s; b: in at 5.46434 s. PET 3.09217 s.
TEST(SsamKernels, PetAreaIsSsmsWhereLanesCrossAtAnAngle) {
  const double th = 40.0 * kPi / 180.0;
  const Vec2 ua(1.0, 0.0), ub(std::cos(th), std::sin(th));
  Body a, b;
  a.axis = ua;
  b.axis = ub;
  a.length = b.length = 4.6;
  a.width = b.width = 1.8;
  auto frontA = [&](double t) { return Vec2((-20.0 + 10.0 * t) * ua); };
  auto frontB = [&](double t) { return Vec2((-30.0 + 5.0 * t) * ub); };
  a.position = frontA(0.0) - 0.5 * a.length * ua;
  b.position = frontB(0.0) - 0.5 * b.length * ub;
  detail::PetWatch w;
  detail::startPet(a, b, 3.2, 3.2, 0.0, detail::PetAngles::of(30.0), w);
  ASSERT_TRUE(w.active);
  double pet = std::numeric_limits<double>::quiet_NaN();
  for (int k = 1; k <= 80 && std::isnan(pet); ++k) {
    const double t = 0.1 * k;
    detail::observePet(frontA(t), frontB(t), t, w);
    pet = w.pet();
  }
  const double conflict = 3.2 * (2.0 / std::sin(th) - 1.0), before = 0.5 * conflict - 0.5 * (3.2 - 1.8);
  EXPECT_NEAR(before, 2.6783, 1e-4);
  EXPECT_NEAR(w.x.norm(), 0.0, 1e-9);
  EXPECT_NEAR(w.enter[0], (20.0 - before) / 10.0, 1e-9);
  EXPECT_NEAR(w.exit[0], (20.0 - before + 1.8 + 4.6) / 10.0, 1e-9);
  EXPECT_NEAR(w.enter[1], (30.0 - before) / 5.0, 1e-9);
  EXPECT_NEAR(pet, (30.0 - before) / 5.0 - (20.0 - before + 6.4) / 10.0, 1e-9);

  // paths starting nearly parallel (a rear-end by SSAM's angle) have no crossing to time
  Body c, d;
  d.axis = Vec2(std::cos(0.2), std::sin(0.2));
  detail::PetWatch n;
  detail::startPet(c, d, 0.0, 30.0, n);
  EXPECT_FALSE(n.active);
}

// A car turning left across another's path, timed on the path it takes. The front of "turner"
// (4 m by 2 m) drives east along y = 0 at 5 m/s from x = 0 at t = 0, turns north at (10, 0) at t =
// 2 s and goes on up x = 10; the front of "cross" (4 m by 2 m) drives west along y = 5 at 10 m/s from
// x = 60. Their paths cross at (10, 5) at a right angle: each is in the area from its front 1 m
// before the crossing until its back is 1 m past it. turner: arc 15 to the crossing, in from arc 14
// to 20, t = 2.8 to 4.0 s; cross: arc 50, in at arc 49, t = 4.9 s. PET 4.9 - 4.0 = 0.9 s, known when
// cross's front reaches turner's path (5.0 s). Straight lines from the start would be parallel
// (y = 0 and y = 5): no PET at all.
TEST(SsamKernels, PetOfATurnIsTimedOnThePathTaken) {
  auto turner = [](double t) { return t <= 2.0 ? Vec2(5.0 * t, 0.0) : Vec2(10.0, 5.0 * (t - 2.0)); };
  auto crosser = [](double t) { return Vec2(60.0 - 10.0 * t, 5.0); };
  Body a, b;
  a.axis = Vec2(1.0, 0.0);
  b.axis = Vec2(-1.0, 0.0);
  a.position = turner(0.0) - 2.0 * a.axis;
  b.position = crosser(0.0) - 2.0 * b.axis;
  a.length = b.length = 4.0;
  a.width = b.width = 2.0;
  detail::PetWatch w;
  detail::startPet(a, b, 0.0, 30.0, w);  // head-on at the start: still watched
  ASSERT_TRUE(w.active);
  double pet = std::numeric_limits<double>::quiet_NaN();
  for (int k = 1; k <= 60 && std::isnan(pet); ++k) {
    const double t = 0.1 * k;
    detail::observePet(turner(t), crosser(t), t, w);
    pet = w.pet();
    if (std::isnan(pet)) {
      EXPECT_LT(t, 5.1 - 1e-9);  // known once cross's front is on turner's path (5.0 s; rounding: the tick after)
    }
  }
  EXPECT_NEAR(w.x.x(), 10.0, 1e-9);
  EXPECT_NEAR(w.x.y(), 5.0, 1e-9);
  EXPECT_NEAR(w.enter[0], 2.8, 1e-9);
  EXPECT_NEAR(w.exit[0], 4.0, 1e-9);
  EXPECT_NEAR(w.enter[1], 4.9, 1e-9);
  EXPECT_NEAR(pet, 0.9, 1e-9);

  // the same two head-on on one line (the crosser along y = 0) never cross at an angle: no PET
  detail::PetWatch h;
  b.position = Vec2(62.0, 0.0);
  detail::startPet(a, b, 0.0, 30.0, h);
  for (int k = 1; k <= 20; ++k)
    detail::observePet(Vec2(5.0 * 0.1 * k, 0.0), Vec2(60.0 - 10.0 * 0.1 * k, 0.0), 0.1 * k, h);
  EXPECT_TRUE(std::isnan(h.pet()));
}

// Two cars at right angles on a collision course until t = 0.3 s, when "east" speeds up to 20 m/s
// and "north" slows to 5 m/s: east leaves the crossing square (its half length 2.5 m plus north's
// half width 0.9 m past the crossing) at 0.3 + 15.4 / 20 = 1.07 s, north enters it (3.4 m before)
// at 0.3 + 8.6 / 5 = 2.02 s: PET 0.95 s, for the episode of either.
TEST(SsamMeasures, PetOfAnAnalyticCrossing) {
  auto xEast = [](double t) { return t <= 0.3 ? -15.0 + 10.0 * t : -12.0 + 20.0 * (t - 0.3); };
  auto yNorth = [](double t) { return t <= 0.3 ? -15.0 + 10.0 * t : -12.0 + 5.0 * (t - 0.3); };
  HighwayMonitor m(oneLaneRoad(), boxStraight());
  std::vector<Warning> ws;
  double t = 0.0;
  for (int k = 0; k <= 30; ++k) {
    t = 0.1 * k;
    const bool late = t > 0.3 + 1e-9;
    VehicleState a = car("east", Vec2(xEast(t), 0.0), 0.0, late ? 20.0 : 10.0);
    VehicleState b = car("north", Vec2(0.0, yNorth(t)), 90.0, late ? 5.0 : 10.0);
    m.step(t, std::vector<VehicleState>{a, b});
    for (auto& w : m.takeFinished()) ws.push_back(w);
  }
  m.finish(t + 0.1);
  for (auto& w : m.takeFinished()) ws.push_back(w);
  for (const char* ego : {"east", "north"}) {
    const Warning* w = find(ws, ego);
    ASSERT_NE(w, nullptr) << ego;
    EXPECT_EQ(w->type, ConflictType::Crossing) << ego;
    EXPECT_NEAR(w->end, 0.4, 1e-9) << ego;  // no collision course once the speeds changed
    EXPECT_NEAR(w->pet, 2.02 - 1.07, 1e-9) << ego;
  }
  // a rear-end has none
  VehicleState f = car("follower", Vec2(0.0, 0.0), 0.0, 30.0), l = car("leader", Vec2(13.0, 0.0), 0.0, 20.0);
  HighwayMonitor r(oneLaneRoad(), boxStraight());
  r.step(0.0, std::vector<VehicleState>{f, l});
  r.finish(0.1);
  const std::vector<Warning> finished = r.takeFinished();
  const Warning* re = find(finished, "follower");
  ASSERT_NE(re, nullptr);
  EXPECT_TRUE(std::isnan(re->pet));
}


// --trajectories: each episode's TTC and DRAC at every tick it holds. On the shipped motorway
// trace, every detector: an episode's series runs from its begin to its last tick before end, one
// point a frame, and its smallest TTC is the episode's min_ttc, at min_ttc_time.
TEST(Trajectories, SeriesMinimumIsTheEpisodesMinTtc) {
  const fs::path data = fs::path(STSIM_SOURCE_DIR) / "tests/data/highway";
  const fs::path net = fs::path(STSIM_SOURCE_DIR) / "networks/motorway";
  const RoadGeometry road = readSumoNet(net / "motorway.net.xml");
  const VehicleTypes types = readSumoVehicleTypes(net / "motorway.rou.xml");
  for (DetectorKind kind : {DetectorKind::FiveCircle, DetectorKind::Box}) {
    MonitorConfig cfg;
    cfg.detector.kind = kind;
    HighwayMonitor m(road, cfg);
    m.recordTrajectories(true);
    FcdReader r(data / "motorway_merge.fcd.xml", types, {}, &road);
    FcdFrame f;
    std::vector<double> frames;
    std::vector<Warning> ws;
    std::vector<TrajectoryPoint> pts, tick;
    while (r.next(f)) {
      m.step(f.time, f.vehicles);
      frames.push_back(f.time);
      for (auto& w : m.takeFinished()) ws.push_back(w);
      m.takeTrajectories(tick);
      pts.insert(pts.end(), tick.begin(), tick.end());
    }
    m.finish(frames.back());
    for (auto& w : m.takeFinished()) ws.push_back(w);
    m.takeTrajectories(tick);
    EXPECT_TRUE(tick.empty());  // finish() records no tick
    ASSERT_GT(ws.size(), 5u);
    // an episode: its ego, foe, kind and begin
    using Key = std::tuple<std::string, std::string, WarningKind, double>;
    std::map<Key, std::vector<TrajectoryPoint>> by;
    for (const auto& p : pts) by[Key{p.ego, p.foe, p.kind, p.begin}].push_back(p);
    EXPECT_EQ(by.size(), ws.size());  // every episode has its series, and only those
    for (const Warning& w : ws) {
      const Key key{w.ego, w.foe, w.kind, w.begin};
      ASSERT_TRUE(by.count(key)) << w.ego << " " << w.foe;
      const auto& series = by[key];
      const auto lowest = std::min_element(series.begin(), series.end(),
                                           [](const TrajectoryPoint& a, const TrajectoryPoint& b) { return a.ttc < b.ttc; });
      EXPECT_EQ(lowest->ttc, w.minTtc) << w.ego << " " << w.foe;
      EXPECT_EQ(lowest->time, w.minTtcTime);
      EXPECT_EQ(series.front().time, w.begin);
      // one point a frame from begin on, through the frame before end (or end itself: the episode
      // closed at its vehicle's last tick, or at the end of the run)
      const auto first = std::find(frames.begin(), frames.end(), w.begin);
      ASSERT_NE(first, frames.end());
      ASSERT_LE(series.size(), static_cast<std::size_t>(frames.end() - first));
      for (std::size_t k = 0; k < series.size(); ++k) EXPECT_EQ(series[k].time, first[static_cast<long>(k)]);
      const double after = series.size() < static_cast<std::size_t>(frames.end() - first) ? first[static_cast<long>(series.size())] : kInf;
      EXPECT_TRUE(after == w.end || series.back().time == w.end) << w.ego << " " << w.foe << " " << w.end;
      // the DRAC at the minimum is the warning's (where it has one)
      if (w.kind == WarningKind::Vehicle && w.type != ConflictType::Proximity) {
        if (std::isinf(w.drac)) EXPECT_TRUE(std::isinf(lowest->drac));
        else EXPECT_NEAR(lowest->drac, w.drac, 1e-9 * std::max(1.0, w.drac));
      }
    }
  }
}

using st::test::slurp;

std::vector<std::vector<std::string>> readCsv(const fs::path& p) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(slurp(p));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::istringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) row.push_back(cell);
    if (!line.empty() && line.back() == ',') row.emplace_back();
    rows.push_back(row);
  }
  return rows;
}

// The front end: trajectories.csv only with --trajectories; its episodes join warnings.csv's.
TEST(Trajectories, FrontEndWritesTheFileOnlyWhenAsked) {
  const fs::path out = fs::temp_directory_path() / ("sthighway_traj_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string input = "highway --fcd " + (fs::path(STSIM_SOURCE_DIR) / "tests/data/highway/motorway_merge.fcd.xml").string() +
                            " --net " + (fs::path(STSIM_SOURCE_DIR) / "networks/motorway/motorway.net.xml").string() +
                            " --detector box --no-map --out " + out.string();
  ASSERT_EQ(std::system((std::string(STSIM_BINARY) + " " + input + " > /dev/null").c_str()), 0);
  EXPECT_FALSE(fs::exists(out / "trajectories.csv"));  // the default run writes no new file
  ASSERT_EQ(std::system((std::string(STSIM_BINARY) + " " + input + " --trajectories > /dev/null").c_str()), 0);
  ASSERT_TRUE(fs::exists(out / "trajectories.csv"));
  const auto series = readCsv(out / "trajectories.csv");
  const auto warnings = readCsv(out / "warnings.csv");
  ASSERT_FALSE(series.empty());
  EXPECT_EQ(series[0], (std::vector<std::string>{"ego", "foe", "kind", "begin", "time", "ttc", "drac"}));
  const auto& h = warnings[0];
  const auto col = [&](const char* name) { return static_cast<std::size_t>(std::find(h.begin(), h.end(), name) - h.begin()); };
  const std::size_t ego = col("ego"), foe = col("foe"), kind = col("kind"), begin = col("begin"), minTtc = col("min_ttc");
  ASSERT_LT(minTtc, h.size());
  auto key = [](const std::vector<std::string>& r, std::size_t a, std::size_t b, std::size_t c, std::size_t d) {
    return r[a] + "|" + r[b] + "|" + r[c] + "|" + r[d];
  };
  std::map<std::string, double> lowest;
  for (std::size_t i = 1; i < series.size(); ++i) {
    const double ttc = std::stod(series[i][5]);
    auto [it, fresh] = lowest.try_emplace(key(series[i], 0, 1, 2, 3), ttc);
    if (!fresh) it->second = std::min(it->second, ttc);
  }
  ASSERT_EQ(lowest.size(), warnings.size() - 1);
  for (std::size_t i = 1; i < warnings.size(); ++i) {
    const std::string k = key(warnings[i], ego, foe, kind, begin);
    ASSERT_TRUE(lowest.count(k)) << k;
    EXPECT_EQ(lowest[k], std::stod(warnings[i][minTtc]));  // both printed the same way
  }
  fs::remove_all(out);
}

}  // namespace
}  // namespace st::highway
