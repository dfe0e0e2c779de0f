#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <tuple>

#include <stcore/toi.hpp>
#include <sthighway/monitor.hpp>
#include <sthighway/report.hpp>

#include "roads.hpp"
#include "test_scale.hpp"
#include "scenes.hpp"

namespace st::highway {
namespace {

constexpr double kPi = 3.14159265358979323846;

RoadGeometry straightRoad(double length = 2000.0, int lanes = 3) {
  RoadGeometry r;
  for (int i = 0; i < lanes; ++i) r.lanes.push_back(laneOf("a", i, {Vec2(0, 3.2 * i), Vec2(length, 3.2 * i)}));
  return r;
}

VehicleState vehicle(const std::string& id, Vec2 p, double heading, double speed) {
  VehicleState v;
  v.id = id;
  v.position = p;
  v.heading = heading;
  v.speed = speed;
  return v;
}

bool sameWarning(const Warning& a, const Warning& b) {
  return a.ego == b.ego && a.foe == b.foe && a.kind == b.kind && a.zone == b.zone && a.begin == b.begin &&
         a.end == b.end && a.minTtc == b.minTtc && a.minTtcTime == b.minTtcTime && a.safeTimeAtMin == b.safeTimeAtMin &&
         a.open == b.open;
}

std::vector<Warning> runAll(HighwayMonitor& m, const std::vector<std::vector<VehicleState>>& ticks, double dt) {
  std::vector<Warning> out;
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    m.step(dt * static_cast<double>(i), ticks[i]);
    for (auto& w : m.takeFinished()) out.push_back(std::move(w));
  }
  m.finish(dt * static_cast<double>(ticks.size() - 1));
  for (auto& w : m.takeFinished()) out.push_back(std::move(w));
  return out;
}

TEST(Monitor, CellsEqualAllPairsOnRandomScenes) {
  std::mt19937_64 rng(424242);
  const RoadGeometry road = testRoad();
  std::uint64_t total = 0, cellPairs = 0, allPairs = 0, handoffs = 0, subdivisions = 0;
  std::array<std::uint64_t, kWarningKindCount> byKind{};
  const int scenes = test::scaledCount(1000);  // fewer under the sanitizers (test_scale.hpp)
  for (int scene = 0; scene < scenes; ++scene) {
    MonitorConfig cfg;
    cfg.prediction = Prediction::Straight;  // the brute force predicts in straight lines
    cfg.detector.kind = static_cast<DetectorKind>(scene % 3);
    cfg.detector.motion = (scene / 3) % 2 ? MotionModel::ConstantAcceleration : MotionModel::ConstantVelocity;
    cfg.cells.cellLength = 60.0 + 10.0 * (scene % 7);
    // some scenes with small cells' spaces subdivided: pairs walked once (undivided cells) next
    // to pairs searched per ego (a subdivided cell on either side)
    cfg.cells.decompositionFactor = scene % 5 == 4 ? 4 : 32;
    const auto ticks = randomScene(rng, cfg.cells.cellLength);
    cfg.broadphase = Broadphase::Cells;
    HighwayMonitor cells(road, cfg);
    cfg.broadphase = Broadphase::AllPairs;
    HighwayMonitor all(road, cfg);
    const auto a = runAll(cells, ticks, 0.2);
    const auto b = runAll(all, ticks, 0.2);
    ASSERT_EQ(a.size(), b.size()) << "scene " << scene;
    for (std::size_t i = 0; i < a.size(); ++i)
      ASSERT_TRUE(sameWarning(a[i], b[i])) << "scene " << scene << " warning " << i << ": " << a[i].ego << "/"
                                           << a[i].foe << " vs " << b[i].ego << "/" << b[i].foe;
    total += a.size();
    for (const auto& w : a) ++byKind[static_cast<int>(w.kind)];
    cellPairs += cells.counters().candidatePairs;
    allPairs += all.counters().candidatePairs;
    handoffs += cells.counters().handoffs;
    subdivisions += cells.counters().subdivisions;
  }
  // the scenes exercise every kind of warning, and the cells do prune
  // (floors per 1000 scenes, scaled with them)
  for (int k = 0; k < kWarningKindCount; ++k)
    EXPECT_GT(byKind[k], 20u * scenes / 1000) << toString(static_cast<WarningKind>(k));
  EXPECT_LT(cellPairs * 2, allPairs);
  EXPECT_GT(handoffs, 0u);
  EXPECT_GT(subdivisions, 50u * scenes / 1000);
  RecordProperty("warnings", static_cast<int>(total));
  RecordProperty("subdivisions", static_cast<int>(subdivisions));
}

// Brute force without any pruning: every equipped ego against every other car and every road
// feature, safe times from the documented rule, the signal rule, the worst TTC per feature polyline.
struct Threat {
  std::string ego, foe;
  WarningKind kind;
  double ttc, safe;
  bool operator<(const Threat& o) const {
    return std::tie(ego, foe, kind) < std::tie(o.ego, o.foe, o.kind);
  }
};

std::vector<Threat> bruteForce(const RoadGeometry& road, const MonitorConfig& cfg, const std::vector<VehicleState>& vs) {
  const RoadFeatures rf = deriveFeatures(road);
  std::map<std::tuple<std::string, std::string, int>, Threat> best;
  auto keep = [&](const Threat& t) {
    auto key = std::make_tuple(t.ego, t.foe, static_cast<int>(t.kind));
    auto it = best.find(key);
    // the worst per key: the smallest TTC, on a tie the longer safe time (the monitor's rule)
    if (it == best.end() || t.ttc < it->second.ttc || (t.ttc == it->second.ttc && t.safe > it->second.safe)) best[key] = t;
  };
  for (const VehicleState& e : vs) {
    if (!e.equipped) continue;
    const Body a = bodyOf(e);
    for (const VehicleState& f : vs) {
      if (f.id == e.id) continue;
      const Body b = bodyOf(f);
      const Vec2 p = b.position - a.position, v = b.velocity - a.velocity;
      const double closing = p.norm() > 0 ? -p.dot(v) / p.norm() : v.norm();
      const double safe = cfg.safeTime.vehicleReactionTime +
                          e.mass * std::max(0.0, closing) / (2 * cfg.safeTime.brakeForce[static_cast<int>(e.vehicleClass)]);
      const Ttc t = vehicleTtc(cfg.detector, a, b, safe);
      if (t.found() && t.t() <= safe) keep({e.id, f.id, WarningKind::Vehicle, t.t(), safe});
    }
    for (const RoadFeature& f : rf.features) {
      const Vec2 c = f.kind == FeatureKind::Hazard ? f.segment.a : closestPointOnSegment(f.segment, a.position);
      const Vec2 d = c - a.position;
      const double closing = d.norm() > 0 ? a.velocity.dot(d) / d.norm() : a.velocity.norm();
      const double safe = cfg.safeTime.roadReactionTime +
                          e.mass * std::max(0.0, closing) / (2 * cfg.safeTime.brakeForce[static_cast<int>(e.vehicleClass)]);
      const Ttc t = featureTtc(cfg.detector, a, f, safe);
      if (!t.found() || t.t() > safe) continue;
      if (f.kind == FeatureKind::LaneMarker) {
        double side = cross(a.axis, d);
        if (std::abs(side) < 1e-9) side = cross(a.axis, a.velocity);
        if (e.signals & (side > 0 ? kSignalLeft : kSignalRight)) continue;
      }
      const WarningKind k = f.kind == FeatureKind::Curb ? WarningKind::Curb
                            : f.kind == FeatureKind::LaneMarker ? WarningKind::LaneMarker : WarningKind::Hazard;
      keep({e.id, f.name, k, t.t(), safe});
    }
  }
  std::vector<Threat> out;
  for (auto& [k, t] : best) out.push_back(t);
  return out;
}

// One tick of the monitor with the given broad phase against the unpruned brute force, threat by
// threat (ego, foe, TTC and safe time exactly); adds the monitor's threats to `found`.
void expectBruteForceThreats(const RoadGeometry& road, MonitorConfig cfg, Broadphase bp, const std::vector<VehicleState>& vs,
                             int scene, std::vector<Threat>& found) {
  cfg.broadphase = bp;
  HighwayMonitor m(road, cfg);
  m.step(0.0, vs);
  std::vector<Threat> got;
  for (const Warning& w : m.openWarnings()) got.push_back({w.ego, w.foe, w.kind, w.minTtc, w.safeTimeAtMin});
  std::sort(got.begin(), got.end());
  const std::vector<Threat> want = bruteForce(road, cfg, vs);
  ASSERT_EQ(got.size(), want.size()) << "scene " << scene << " " << toString(bp);
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].ego + "/" + got[i].foe, want[i].ego + "/" + want[i].foe) << "scene " << scene;
    ASSERT_EQ(got[i].ttc, want[i].ttc) << "scene " << scene << " " << got[i].ego << "/" << got[i].foe;
    ASSERT_EQ(got[i].safe, want[i].safe);
  }
  found.insert(found.end(), got.begin(), got.end());
}

TEST(Monitor, PruningNeverChangesTheAnswer) {
  // single ticks against the unpruned brute force, including cars riding exactly on a lane
  // marker or a curb with a vanishing sideways speed (contact within the kernels' slop)
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const RoadGeometry road = testRoad();
  std::size_t threats = 0;
  const int scenes = test::scaledCount(300);  // fewer under the sanitizers (test_scale.hpp)
  for (int scene = 0; scene < scenes; ++scene) {
    MonitorConfig cfg;
    cfg.prediction = Prediction::Straight;  // the brute force predicts in straight lines
    cfg.detector.kind = static_cast<DetectorKind>(scene % 3);
    cfg.detector.motion = (scene / 3) % 2 ? MotionModel::ConstantAcceleration : MotionModel::ConstantVelocity;
    auto vs = randomScene(rng, 80.0)[1];
    for (std::size_t i = 0; i < vs.size(); i += 4) {
      // on a boundary: the side exactly on a marker (y = 1.6) or the right curb (y = -1.6)
      VehicleState& v = vs[i];
      if (v.heading > 0.1) continue;
      v.heading = 0.0;
      // the side 0.5 nm from the line (within the kernels' 1 nm contact slop), drifting towards
      // it at 1e-12 m/s or a little faster, or away
      const double line = U(rng) < 0.5 ? 1.6 : -1.6;
      const double below = U(rng) < 0.5 ? 1.0 : -1.0;  // centre below (right of) the line or above
      v.position.y() = line - below * (0.5 * v.width + 5e-10);
      const double r = U(rng);
      v.lateralSpeed = below * (r < 0.4 ? 1e-12 : r < 0.7 ? 1e-6 : -1e-6);
    }
    std::vector<Threat> found;
    for (Broadphase bp : {Broadphase::Cells, Broadphase::AllPairs})
      ASSERT_NO_FATAL_FAILURE(expectBruteForceThreats(road, cfg, bp, vs, scene, found));
    threats += found.size();
  }
  EXPECT_GT(threats, 1000u * scenes / 300);
}

TEST(Monitor, RoadPruneNeverChangesTheAnswerNearSegmentEnds) {
  // the road prune tightens its horizon to the approach speed while an ego's centre projects
  // inside a segment; near and beyond its ends the closest point is the end, and the closing
  // speed may be the full speed. A wiggling road of short segments (many ends and normals), a
  // lane that ends, hazards; cars near the vertices at any heading and speed, against the
  // unpruned brute force
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::size_t roadThreats = 0;
  for (int scene = 0; scene < 200; ++scene) {
    RoadGeometry road;
    std::vector<std::vector<Vec2>> lanes(2);
    double heading = 0.0;
    for (int k = 0; k <= 30; ++k) {
      const Vec2 at = k == 0 ? Vec2(0.0, 0.0) : lanes[0].back() + 6.0 * Vec2(std::cos(heading), std::sin(heading));
      for (int lane = 0; lane < 2; ++lane) lanes[lane].push_back(at + 3.2 * lane * Vec2(-std::sin(heading), std::cos(heading)));
      heading += 0.3 * (U(rng) - 0.5);
    }
    lanes[1].resize(12);  // the left lane ends: its marker and curb have ends mid-road
    for (int lane = 0; lane < 2; ++lane) road.lanes.push_back(laneOf("w", lane, lanes[lane]));
    road.hazards.push_back(Hazard{"pothole", lanes[0][15], 0.3});
    MonitorConfig cfg;
    cfg.prediction = Prediction::Straight;  // the brute force predicts in straight lines
    cfg.detector.kind = static_cast<DetectorKind>(scene % 3);
    cfg.detector.motion = (scene / 3) % 2 ? MotionModel::ConstantAcceleration : MotionModel::ConstantVelocity;
    std::vector<VehicleState> vs;
    for (int i = 0; i < 25; ++i) {
      VehicleState v;
      v.id = "c";  // appended: GCC 12 flags `"c" + std::string&&` with a false -Wrestrict (PR 105329)
      v.id += std::to_string(i);
      const Vec2 corner = lanes[static_cast<std::size_t>(U(rng) * 2)][static_cast<std::size_t>(U(rng) * 12)];
      v.position = corner + Vec2(6.0 * (U(rng) - 0.5), 6.0 * (U(rng) - 0.5));
      v.heading = U(rng) < 0.5 ? 0.4 * (U(rng) - 0.5) : 2.0 * kPi * U(rng);
      v.speed = U(rng) < 0.1 ? 0.0 : 35.0 * U(rng);
      v.lateralSpeed = U(rng) < 0.3 ? 0.0 : 2.0 * (U(rng) - 0.5);
      v.acceleration = 6.0 * (U(rng) - 0.5);
      if (U(rng) < 0.2) makeTruck(v);
      vs.push_back(v);
    }
    std::vector<Threat> found;
    for (Broadphase bp : {Broadphase::Cells, Broadphase::AllPairs})
      ASSERT_NO_FATAL_FAILURE(expectBruteForceThreats(road, cfg, bp, vs, scene, found));
    for (const Threat& t : found) roadThreats += t.kind != WarningKind::Vehicle;
  }
  EXPECT_GT(roadThreats, 500u);
}

TEST(Monitor, CarClosingOnStoppedCarEpisode) {
  // ego at 20 m/s, stopped car with a 60 m bumper gap, box detector, ticks of 0.1 s:
  // TTC(t) = 3 - t, safe time 1 + 1500 * 20 / (2 * 12000) = 2.25 s, so the warning begins at the
  // first tick with 3 - t <= 2.25, t = 0.8, and lasts until the stopped car leaves after t = 1.2
  MonitorConfig cfg;
  cfg.detector.kind = DetectorKind::Box;
  cfg.checkRoad = false;
  HighwayMonitor m(straightRoad(), cfg);
  std::vector<Warning> got;
  for (int k = 0; k <= 15; ++k) {
    const double t = 0.1 * k;
    std::vector<VehicleState> vs{vehicle("ego", {100 + 20 * t, 3.2}, 0, 20)};
    if (k <= 12) vs.push_back(vehicle("stopped", {165, 3.2}, 0, 0));
    m.step(t, vs);
    for (auto& w : m.takeFinished()) got.push_back(w);
    if (k == 10) {
      // both are equipped: the ego (index 0) and the stopped car see each other
      ASSERT_EQ(m.alerts().size(), 2u);
      const Alert& a = m.alerts()[0].vehicle == 0 ? m.alerts()[0] : m.alerts()[1];
      EXPECT_EQ(a.vehicle, 0);
      EXPECT_NEAR(a.ttc, 2.0, 1e-9);
      EXPECT_NEAR(a.safeTime, 2.25, 1e-12);
      EXPECT_EQ(m.openWarnings().size(), 2u);
    }
  }
  ASSERT_EQ(got.size(), 2u);
  const Warning& w = got[0].ego == "ego" ? got[0] : got[1];
  EXPECT_EQ(w.ego, "ego");
  EXPECT_EQ(w.foe, "stopped");
  EXPECT_EQ(w.kind, WarningKind::Vehicle);
  EXPECT_EQ(w.zone, Zone::Body);
  EXPECT_NEAR(w.begin, 0.8, 1e-12);
  EXPECT_NEAR(w.end, 1.3, 1e-12);  // the first tick without the threat (the stopped car is gone)
  EXPECT_NEAR(w.minTtc, 3.0 - 1.2, 1e-9);
  EXPECT_NEAR(w.minTtcTime, 1.2, 1e-12);
  EXPECT_NEAR(w.safeTimeAtMin, 2.25, 1e-12);
  // the stopped car (equipped too) saw the ego coming from behind, with its own (car) safe time
  const Warning& back = got[0].ego == "ego" ? got[1] : got[0];
  EXPECT_EQ(back.foe, "ego");
  EXPECT_NEAR(back.begin, 0.8, 1e-12);
  EXPECT_NEAR(back.end, 1.2, 1e-12);  // its own last tick
  EXPECT_EQ(m.counters().warningsBegun, 2u);
  EXPECT_NEAR(m.counters().tet[0], 0.5 + 0.5, 1e-9);  // both cars, 0.8 .. 1.3
}

TEST(Monitor, TruckHasLongerSafeTimeThanCarAtSameSpeed) {
  // both approach a stopped car at 20 m/s with a 52 m bumper gap: TTC 2.6 s for both.
  // Car: 1 + 1500 * 20 / 24000 = 2.25 s -> no warning. Truck: 1 + 15000 * 20 / 150000 = 3 s -> warning.
  MonitorConfig cfg;
  cfg.detector.kind = DetectorKind::Box;
  cfg.checkRoad = false;
  for (bool truck : {false, true}) {
    HighwayMonitor m(straightRoad(), cfg);
    VehicleState ego = vehicle("ego", {100, 3.2}, 0, 20);
    if (truck) makeTruck(ego);
    VehicleState lead = vehicle("lead", {100 + ego.length / 2 + 52 + 2.5, 3.2}, 0, 0);
    lead.equipped = false;
    const std::vector<VehicleState> vs{ego, lead};
    m.step(0.0, vs);
    if (truck) {
      ASSERT_EQ(m.alerts().size(), 1u);
      EXPECT_NEAR(m.alerts()[0].ttc, 2.6, 1e-9);
      EXPECT_NEAR(m.alerts()[0].safeTime, 3.0, 1e-12);
    } else {
      EXPECT_TRUE(m.alerts().empty());
    }
  }
  SafeTimeConfig st;
  EXPECT_GT(st.vehicleSafeTime(15000, 20, VehicleClass::Truck), st.vehicleSafeTime(1500, 20, VehicleClass::Passenger));
}

TEST(Monitor, LaneChangeWithSignalIsNotAWarning) {
  // a car in lane 0 (y = 0) drifting left at 1 m/s towards the marker at y = 1.6: its side
  // reaches it after (1.6 - 0.9) / 1 = 0.7 s, below the road safe time 0.5 + 1500 * 1 / 24000
  MonitorConfig cfg;
  cfg.detector.kind = DetectorKind::FiveCircle;
  for (std::uint8_t signal : {kSignalNone, kSignalLeft, kSignalRight}) {
    HighwayMonitor m(straightRoad(), cfg);
    VehicleState v = vehicle("c", {500, 0.6}, 0, 25);
    v.lateralSpeed = 1.0;
    v.signals = signal;
    const std::vector<VehicleState> vs{v};
    m.step(0.0, vs);
    const auto open = m.openWarnings();
    if (signal == kSignalLeft) {
      EXPECT_TRUE(open.empty());
    } else {
      ASSERT_EQ(open.size(), 1u) << int(signal);
      EXPECT_EQ(open[0].kind, WarningKind::LaneMarker);
      EXPECT_EQ(open[0].foe, "a_0|a_1");
      EXPECT_EQ(open[0].zone, Zone::Center);
      EXPECT_NEAR(open[0].minTtc, 0.1, 1e-9);  // side at 1.5, marker at 1.6
    }
  }
  // drifting right towards the curb at y = -1.6 with the right signal on: the curb still warns
  HighwayMonitor m(straightRoad(), cfg);
  VehicleState v = vehicle("c", {500, -0.6}, 0, 25);
  v.lateralSpeed = -1.0;
  v.signals = kSignalRight;
  const std::vector<VehicleState> vs{v};
  m.step(0.0, vs);
  const auto open = m.openWarnings();
  ASSERT_EQ(open.size(), 1u);
  EXPECT_EQ(open[0].kind, WarningKind::Curb);
  EXPECT_EQ(open[0].foe, "a:right");
}

TEST(Monitor, CutInFromTheRightFiresTheRightZone) {
  MonitorConfig cfg;
  cfg.detector.kind = DetectorKind::FiveCircle;
  cfg.checkRoad = false;
  HighwayMonitor m(straightRoad(), cfg);
  VehicleState ego = vehicle("ego", {500, 3.2}, 0, 25);
  VehicleState cutter = vehicle("cutter", {500, 0.2}, 0, 25);
  cutter.lateralSpeed = 1.5;
  cutter.equipped = false;
  const std::vector<VehicleState> vs{ego, cutter};
  m.step(0.0, vs);
  const auto open = m.openWarnings();
  ASSERT_EQ(open.size(), 1u);
  EXPECT_EQ(open[0].zone, Zone::Right);
  EXPECT_EQ(open[0].foe, "cutter");
}

// The monitor maps ids to its slots by position when the input keeps its order (no lookup) and
// by id otherwise: the same traffic given in a fixed order and reshuffled every tick gives the
// same warnings, and the same cars are alerted.
TEST(Monitor, InputOrderDoesNotChangeWarnings) {
  std::mt19937_64 rng(777);
  const RoadGeometry road = testRoad();
  std::size_t total = 0;
  for (int scene = 0; scene < 60; ++scene) {
    MonitorConfig cfg;
    cfg.detector.kind = static_cast<DetectorKind>(scene % 3);
    cfg.broadphase = scene % 2 ? Broadphase::AllPairs : Broadphase::Cells;
    cfg.cells.cellLength = 60.0;
    auto ticks = randomScene(rng, cfg.cells.cellLength);
    // a longer run: the scene's last tick moved on a few more ticks
    for (int k = 0; k < 6; ++k) {
      auto next = ticks.back();
      for (VehicleState& v : next) v.position += 0.2 * v.velocity();
      ticks.push_back(next);
    }
    auto shuffled = ticks;
    for (auto& t : shuffled) std::shuffle(t.begin(), t.end(), rng);
    HighwayMonitor fixed(road, cfg), moving(road, cfg);
    std::vector<std::string> a, b;
    for (std::size_t i = 0; i < ticks.size(); ++i) {
      fixed.step(0.2 * static_cast<double>(i), ticks[i]);
      moving.step(0.2 * static_cast<double>(i), shuffled[i]);
      // the alerted cars (which foe is named among exact ties follows the order of arrival)
      std::vector<std::string> alertsA, alertsB;
      for (const Alert& x : fixed.alerts()) alertsA.push_back(ticks[i][x.vehicle].id);
      for (const Alert& x : moving.alerts()) alertsB.push_back(shuffled[i][x.vehicle].id);
      std::sort(alertsA.begin(), alertsA.end());
      std::sort(alertsB.begin(), alertsB.end());
      ASSERT_EQ(alertsA, alertsB) << "scene " << scene << " tick " << i;
      for (const auto& w : fixed.takeFinished()) a.push_back(warningCsvRow(w));
      for (const auto& w : moving.takeFinished()) b.push_back(warningCsvRow(w));
    }
    for (const auto& w : fixed.openWarnings()) a.push_back(warningCsvRow(w));
    for (const auto& w : moving.openWarnings()) b.push_back(warningCsvRow(w));
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    ASSERT_EQ(a, b) << "scene " << scene;
    total += a.size();
  }
  EXPECT_GT(total, 500u);
}

// takeFinished into a caller's buffer: the same episodes, tick by tick, as the vector it returns;
// the buffer's old contents are replaced, not appended to.
TEST(Monitor, TakeFinishedIntoABufferReplacesItsContents) {
  std::mt19937_64 rng(77);
  const RoadGeometry road = testRoad();
  std::size_t total = 0;
  for (int scene = 0; scene < 40; ++scene) {
    MonitorConfig cfg;
    cfg.detector.kind = static_cast<DetectorKind>(scene % 3);
    const auto ticks = randomScene(rng, cfg.cells.cellLength);
    HighwayMonitor byValue(road, cfg), intoBuffer(road, cfg);
    std::vector<Warning> buffer(3);  // stale contents that must not survive
    auto compare = [&](const std::vector<Warning>& want) {
      ASSERT_EQ(buffer.size(), want.size()) << "scene " << scene;
      for (std::size_t k = 0; k < want.size(); ++k) ASSERT_TRUE(sameWarning(buffer[k], want[k])) << "scene " << scene;
      total += want.size();
    };
    std::uint64_t delivered = 0;
    for (std::size_t i = 0; i < ticks.size(); ++i) {
      byValue.step(0.2 * static_cast<double>(i), ticks[i]);
      intoBuffer.step(0.2 * static_cast<double>(i), ticks[i]);
      intoBuffer.takeFinished(buffer);
      compare(byValue.takeFinished());
      delivered += buffer.size();
    }
    byValue.finish(0.2 * static_cast<double>(ticks.size() - 1));
    intoBuffer.finish(0.2 * static_cast<double>(ticks.size() - 1));
    intoBuffer.takeFinished(buffer);
    compare(byValue.takeFinished());
    // and every episode that began was handed over once (byValue now shares the overload's code,
    // so this is the independent count)
    EXPECT_EQ(delivered + buffer.size(), intoBuffer.counters().warningsBegun) << "scene " << scene;
  }
  EXPECT_GT(total, 20u);
}

// The cells broad phase keeps each cell's compact cars apart from its trucks: a divided road
// with trucks in the outer lanes only (their outer circles, 12.3 m across, cannot reach the other
// carriageway from there) gives no candidate pair across the median, so the two carriageways
// together cost what each costs alone. A truck in an inner lane does reach across (its circle
// and a car's, 8.8 m, against 8 m between the inner lanes): the control that the count sees such
// pairs. The warnings equal those of all pairs throughout.
TEST(Monitor, CompactTrafficMakesNoCandidatePairsAcrossTheMedian) {
  RoadGeometry road = straightRoad(2000.0);
  for (int i = 0; i < 3; ++i)
    road.lanes.push_back(laneOf("back", i, {Vec2(2000.0, 20.8 - 3.2 * i), Vec2(0.0, 20.8 - 3.2 * i)}));
  // lanes 0 (outer) to 2 (inner) of each carriageway; every fifth car in an outer lane a truck
  auto carriageway = [](bool west, bool truckInside) {
    std::vector<VehicleState> cars;
    for (int lane = 0; lane < 3; ++lane)
      for (int k = 0; k < 70; ++k) {
        const double y = west ? 20.8 - 3.2 * lane : 3.2 * lane;
        const double x = 20.0 + 25.0 * k + 7.0 * lane;
        VehicleState v = vehicle(std::string(west ? "w" : "e") + std::to_string(lane) + "_" + std::to_string(k),
                                 Vec2(west ? 2000.0 - x : x, y), west ? std::numbers::pi : 0.0, 24.0 + 3.0 * lane);
        const bool truck = k % 5 == 0 && (lane == 0 || (truckInside && lane == 2));
        if (truck) makeTruck(v);
        cars.push_back(v);
      }
    return cars;
  };
  for (DetectorKind kind : {DetectorKind::Concentric, DetectorKind::FiveCircle, DetectorKind::Box}) {
    auto pairsOf = [&](const std::vector<VehicleState>& cars, Broadphase bp, std::vector<Warning>* out) {
      MonitorConfig cfg;
      cfg.detector.kind = kind;
      cfg.broadphase = bp;
      HighwayMonitor m(road, cfg);
      std::vector<std::vector<VehicleState>> ticks;
      for (int t = 0; t < 4; ++t) {
        ticks.push_back(cars);
        for (VehicleState& v : ticks.back()) v.position += 0.1 * t * v.velocity();
      }
      const auto w = runAll(m, ticks, 0.1);
      if (out) *out = w;
      return m.counters().candidatePairs;
    };
    for (bool truckInside : {false, true}) {
      const auto east = carriageway(false, truckInside), west = carriageway(true, truckInside);
      std::vector<VehicleState> both = east;
      both.insert(both.end(), west.begin(), west.end());
      std::vector<Warning> cells, all;
      const std::uint64_t together = pairsOf(both, Broadphase::Cells, &cells);
      const std::uint64_t apart = pairsOf(east, Broadphase::Cells, nullptr) + pairsOf(west, Broadphase::Cells, nullptr);
      pairsOf(both, Broadphase::AllPairs, &all);
      ASSERT_EQ(cells.size(), all.size()) << toString(kind);
      for (std::size_t i = 0; i < cells.size(); ++i) ASSERT_TRUE(sameWarning(cells[i], all[i])) << toString(kind);
      // (the box detector's tight reach finds no candidate at all in this steady traffic)
      if (kind != DetectorKind::Box) {
        EXPECT_GT(apart, 0u) << toString(kind);
      }
      if (!truckInside) {
        EXPECT_EQ(together, apart) << toString(kind);
      } else if (kind == DetectorKind::Concentric) {
        EXPECT_GT(together, apart);
      }
    }
  }
}

TEST(Monitor, RejectsBadInput) {
  HighwayMonitor m(straightRoad(), MonitorConfig{});
  std::vector<VehicleState> dup{vehicle("x", {1, 0}, 0, 1), vehicle("x", {50, 0}, 0, 1)};
  EXPECT_THROW(m.step(0.0, dup), std::invalid_argument);
  {
    // a duplicate where the last tick had another vehicle, or the same one (the by-position map)
    HighwayMonitor m2(straightRoad(), MonitorConfig{});
    m2.step(0.0, std::vector<VehicleState>{vehicle("a", {1, 0}, 0, 1), vehicle("b", {50, 0}, 0, 1)});
    EXPECT_THROW(m2.step(1.0, std::vector<VehicleState>{vehicle("a", {2, 0}, 0, 1), vehicle("a", {51, 0}, 0, 1)}),
                 std::invalid_argument);
    HighwayMonitor m3(straightRoad(), MonitorConfig{});
    m3.step(0.0, std::vector<VehicleState>{vehicle("a", {1, 0}, 0, 1), vehicle("b", {50, 0}, 0, 1)});
    EXPECT_THROW(m3.step(1.0, std::vector<VehicleState>{vehicle("b", {2, 0}, 0, 1), vehicle("b", {51, 0}, 0, 1)}),
                 std::invalid_argument);
  }
  std::vector<VehicleState> nan{vehicle("y", {std::nan(""), 0}, 0, 1)};
  EXPECT_THROW(m.step(1.0, nan), std::invalid_argument);
  std::vector<VehicleState> ok{vehicle("z", {1, 0}, 0, 1)};
  m.step(2.0, ok);
  EXPECT_THROW(m.step(2.0, ok), std::invalid_argument);  // time must increase
  MonitorConfig bad;
  bad.detector.five.zones[FiveCircleLayout::kFront].rx = 0.05;
  EXPECT_THROW(HighwayMonitor(straightRoad(), bad), std::invalid_argument);
}

TEST(Road, FeaturesOfAThreeLaneEdge) {
  const RoadFeatures f = deriveFeatures(straightRoad(1000.0));
  ASSERT_EQ(f.features.size(), 4u);  // right curb, two markers, left curb
  EXPECT_EQ(f.features[0].kind, FeatureKind::Curb);
  EXPECT_NEAR(f.features[0].segment.a.y(), -1.6, 1e-12);
  EXPECT_EQ(f.features[1].kind, FeatureKind::LaneMarker);
  EXPECT_NEAR(f.features[1].segment.a.y(), 1.6, 1e-12);
  EXPECT_NEAR(f.features[2].segment.b.y(), 4.8, 1e-12);
  EXPECT_EQ(f.features[3].kind, FeatureKind::Curb);
  EXPECT_NEAR(f.features[3].segment.b.y(), 8.0, 1e-12);
  // mitred offset keeps the distance on both legs of a right-angle bend
  const auto off = offsetPolyline({Vec2(0, 0), Vec2(10, 0), Vec2(10, 10)}, 1.0);
  ASSERT_EQ(off.size(), 3u);
  EXPECT_NEAR(off[1].x(), 9.0, 1e-12);
  EXPECT_NEAR(off[1].y(), 1.0, 1e-12);
}

}  // namespace
}  // namespace st::highway
