// Road-aware prediction (Prediction::Road) against independent truth: circular lanes driven at
// constant speed, cars side by side through a curve, a drift across a marker with its analytic
// time to line crossing, a rear-end pair on a curve against the straight road of the same arc
// length; and its prunes against an unpruned brute force along the same paths.
#include <gtest/gtest.h>
#include "test_scale.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <sthighway/monitor.hpp>

#include "lane_prediction.hpp"
#include "pair_search.hpp"
#include "roads.hpp"
#include "scenes.hpp"
#include "vehicle_table.hpp"

namespace st::highway {
namespace {

constexpr double kPi = 3.14159265358979323846;

// An arc edge of `lanes` lanes (3.2 m), centre (0, 0), lane 0 (the rightmost) on radius r0,
// counter-clockwise from angle 0 to `sweep`, a vertex every `step` rad.
RoadGeometry arcRoad(double r0, int lanes, double sweep, double step) {
  RoadGeometry road;
  for (int i = 0; i < lanes; ++i) {
    std::vector<Vec2> shape;
    const double r = r0 - 3.2 * i;  // counter-clockwise: the left lanes are inside
    for (double th = 0.0; th <= sweep + 1e-12; th += step) shape.emplace_back(r * std::cos(th), r * std::sin(th));
    road.lanes.push_back(laneOf("arc", i, std::move(shape)));
  }
  return road;
}

// A car on the true circle of radius r at angle th, heading along it, at speed u.
VehicleState onCircle(const std::string& id, int handle, double r, double th, double u) {
  VehicleState v;
  v.id = id;
  v.handle = handle;
  v.position = Vec2(r * std::cos(th), r * std::sin(th));
  v.heading = th + 0.5 * kPi;
  v.speed = u;
  return v;
}

struct Drive {
  std::vector<Warning> warnings;
  MonitorCounters counters;
};

template <class Tick>
Drive drive(const RoadGeometry& road, const MonitorConfig& cfg, int ticks, double dt, Tick tick) {
  HighwayMonitor m(road, cfg);
  Drive out;
  for (int k = 0; k < ticks; ++k) {
    m.step(k * dt, tick(k * dt));
    for (auto& w : m.takeFinished()) out.warnings.push_back(std::move(w));
  }
  m.finish((ticks - 1) * dt);
  for (auto& w : m.takeFinished()) out.warnings.push_back(std::move(w));
  out.counters = m.counters();
  return out;
}

std::size_t countKind(const Drive& r, WarningKind k) {
  std::size_t n = 0;
  for (const Warning& w : r.warnings) n += w.kind == k;
  return n;
}

MonitorConfig config(DetectorKind kind, Prediction p) {
  MonitorConfig cfg;
  cfg.detector.kind = kind;
  cfg.prediction = p;
  return cfg;
}

TEST(RoadPrediction, CircularLaneAtConstantSpeedNeverWarnsAboutCurbsOrMarkers) {
  // radius 150 m, a vertex every 2 degrees (SUMO-like polyline): the car drives the true circle
  // (off the polyline by up to 2.3 cm between vertices) at 30 m/s, 0.1 s ticks, in the outer and
  // the inner lane of two
  const RoadGeometry road = arcRoad(150.0, 2, 1.8 * kPi, 2.0 * kPi / 180.0);
  for (DetectorKind kind : {DetectorKind::Concentric, DetectorKind::FiveCircle, DetectorKind::Box}) {
    std::size_t straightRoadWarnings = 0;
    for (Prediction p : {Prediction::Road, Prediction::Straight}) {
      const Drive r = drive(road, config(kind, p), 200, 0.1, [](double t) {
        return std::vector<VehicleState>{onCircle("outer", 0, 150.0, 0.1 + 30.0 * t / 150.0, 30.0),
                                         onCircle("inner", 1, 146.8, 0.6 + 30.0 * t / 146.8, 30.0)};
      });
      const std::size_t roadWarnings = countKind(r, WarningKind::Curb) + countKind(r, WarningKind::LaneMarker);
      if (p == Prediction::Road) {
        EXPECT_EQ(roadWarnings, 0u) << toString(kind);
        EXPECT_EQ(r.counters.straightFallbacks, 0u);
        EXPECT_EQ(r.counters.roadPredicted, 400u);
      } else {
        straightRoadWarnings = roadWarnings;
      }
    }
    // the straight line leaves the circle tangentially: 30^2 / (2 150) = 3 m per s^2
    EXPECT_GT(straightRoadWarnings, 0u) << toString(kind);
  }
}

TEST(RoadPrediction, CarsSideBySideThroughACurveNeverWarnEachOther) {
  // two cars in adjacent lanes of a 40 m curve at 14 m/s (an exit loop), the outer one 3 m of arc
  // ahead, at the same angular speed: each keeps its lane and the pair its spacing; their bodies
  // stay 1.4 m apart. In straight lines the one behind heads 0.075 rad further out than the one
  // ahead and closes on it sideways at 1 m/s.
  const double r = 40.0, u = 14.0;
  const RoadGeometry road = arcRoad(r, 2, 1.5 * kPi, 1.5 * kPi / 180.0);
  for (DetectorKind kind : {DetectorKind::FiveCircle, DetectorKind::Box}) {
    std::size_t straight = 0;
    for (Prediction p : {Prediction::Road, Prediction::Straight}) {
      const Drive d = drive(road, config(kind, p), 100, 0.1, [&](double t) {
        const double th = 0.2 + u * t / r;
        return std::vector<VehicleState>{onCircle("a", 0, r, th + 3.0 / r, u), onCircle("b", 1, r - 3.2, th, u * (r - 3.2) / r)};
      });
      if (p == Prediction::Road) {
        EXPECT_EQ(countKind(d, WarningKind::Vehicle), 0u) << toString(kind);
      } else {
        straight = countKind(d, WarningKind::Vehicle);
      }
    }
    // the five-circle zones reach far enough for that to warn (the box's 1.4 m gap at 1 m/s stays
    // beyond its safe time)
    if (kind == DetectorKind::FiveCircle) {
      EXPECT_GT(straight, 0u);
    }
  }
}

TEST(RoadPrediction, DriftAcrossAMarkerWarnsWithTheAnalyticTimeToCrossing) {
  // a straight two-lane road; the car leaves its lane's centre at 0.8 m/s sideways (positions
  // only, as an FCD trace gives them: no lateral speed reported), 25 m/s along. Its side (the
  // box's half width 0.9 m) reaches the marker at y = 1.6 when y = 0.7: at t = 0.875 s. The
  // lateral speed is known from the second tick on; from then on TTC + t = 0.875 at every tick.
  RoadGeometry road;
  for (int i = 0; i < 2; ++i) road.lanes.push_back(laneOf("s", i, {Vec2(0.0, 3.2 * i), Vec2(2000.0, 3.2 * i)}));
  for (bool signal : {false, true}) {
    HighwayMonitor m(road, config(DetectorKind::Box, Prediction::Road));
    std::vector<Warning> ws;
    int alerted = 0;
    for (int k = 0; k < 12; ++k) {
      const double t = 0.1 * k;
      VehicleState v;
      v.id = "drifter";
      v.handle = 0;
      v.position = Vec2(100.0 + 25.0 * t, 0.8 * t);
      v.speed = 25.0;
      v.signals = signal ? kSignalLeft : kSignalNone;
      m.step(t, std::vector<VehicleState>{v});
      for (const Alert& a : m.alerts()) {
        if (a.kind != WarningKind::LaneMarker) continue;
        ++alerted;
        // the time to crossing at every tick before it, within rounding
        if (t < 0.875) {
          EXPECT_NEAR(t + a.ttc, 0.875, 1e-9) << t;
        } else {
          EXPECT_EQ(a.ttc, 0.0) << t;  // across and still moving towards it
        }
      }
      for (auto& w : m.takeFinished()) ws.push_back(std::move(w));
    }
    m.finish(1.1);
    for (auto& w : m.takeFinished()) ws.push_back(std::move(w));
    const Warning* marker = nullptr;
    for (const Warning& w : ws)
      if (w.kind == WarningKind::LaneMarker) marker = &w;
    if (signal) {
      EXPECT_EQ(marker, nullptr);  // a signalled lane change
      EXPECT_EQ(alerted, 0);
      continue;
    }
    ASSERT_NE(marker, nullptr);
    EXPECT_EQ(marker->foe, "s_0|s_1");
    // safe time 0.5 + 1500 * 0.8 / 24000 = 0.55 s: TLC = 0.875 - t <= 0.55 from t = 0.325, the first tick 0.4
    EXPECT_NEAR(marker->safeTimeAtMin, 0.55, 1e-9);
    EXPECT_NEAR(marker->begin, 0.4, 1e-9);
    EXPECT_EQ(alerted, 8);  // 0.4 .. 1.1
    // hindsight saw the body reach across the line, unsignalled, at the first tick after 0.875
    EXPECT_TRUE(marker->crossed);
    EXPECT_FALSE(marker->signalled);
    EXPECT_NEAR(marker->clearanceTime, 0.9, 1e-9);
    EXPECT_EQ(marker->verdict, Verdict::Confirmed);
    for (const Warning& w : ws) EXPECT_NE(w.kind, WarningKind::Curb);
  }
}

TEST(RoadPrediction, RearEndOnACurveHasTheTtcOfAStraightRoadOfTheSameArcLength) {
  // follower at 30 m/s, leader 20 m of arc ahead at 20 m/s on a 300 m curve (a vertex every
  // degree): on a straight road the box TTC is (20 - 5) / 10 = 1.5 s. Along the curve the two
  // bodies are turned against each other by 20/300 rad at most: their inner corners come closer
  // by up to W/2 of that (6 cm), 6 ms at 10 m/s.
  const double r = 300.0;
  const RoadGeometry road = arcRoad(r, 1, 0.5 * kPi, kPi / 180.0);
  for (DetectorKind kind : {DetectorKind::Box, DetectorKind::FiveCircle, DetectorKind::Concentric}) {
    MonitorConfig cfg = config(kind, Prediction::Road);
    cfg.checkRoad = false;
    HighwayMonitor m(road, cfg);
    std::vector<VehicleState> cars = {onCircle("follower", 0, r, 0.2, 30.0), onCircle("leader", 1, r, 0.2 + 20.0 / r, 20.0)};
    cars[1].equipped = false;
    // on the polyline, not the true circle: the arc length is the polyline's
    for (VehicleState& v : cars) {
      const double th = std::atan2(v.position.y(), v.position.x());
      const double k = std::floor(th / (kPi / 180.0));
      const Vec2 a(r * std::cos(k * kPi / 180.0), r * std::sin(k * kPi / 180.0));
      const Vec2 b(r * std::cos((k + 1) * kPi / 180.0), r * std::sin((k + 1) * kPi / 180.0));
      const Vec2 u = (b - a).normalized();
      v.position = a + (v.position - a).dot(u) * u;
      v.heading = std::atan2(u.y(), u.x());
    }
    m.step(0.0, cars);
    const auto open = m.openWarnings();
    ASSERT_EQ(open.size(), 1u) << toString(kind);
    const Warning& w = open[0];
    if (kind == DetectorKind::Box) {
      EXPECT_NEAR(w.minTtc, 1.5, 0.01);
      EXPECT_LE(w.minTtc, 1.5 + 1e-9);  // chords are never longer than arcs
    }
    // the circle models lead the box by their documented reach along the axis over 10 m/s
    if (kind == DetectorKind::FiveCircle) {
      EXPECT_NEAR(w.minTtc, 1.5 - 0.79 / 10.0, 0.015);
    }
    if (kind == DetectorKind::Concentric) {
      EXPECT_NEAR(w.minTtc, 1.5 - (std::hypot(5.0, 1.8) - 5.0) / 10.0, 0.015);
    }
  }
}

}  // namespace

namespace detail {
namespace {

// A straight three-lane stretch, then a tight two-lane curve (radius 60 m, 3 degree vertices)
// and a lane that continues into it, two lanes longer or shorter than SUMO would measure them:
// cars anywhere on them, at any speed, some drifting.
RoadGeometry tightRoad() {
  RoadGeometry r;
  for (int i = 0; i < 3; ++i) r.lanes.push_back(laneOf("a", i, {Vec2(0.0, 3.2 * i), Vec2(300.0, 3.2 * i)}));
  for (int i = 0; i < 2; ++i) {
    std::vector<Vec2> shape;
    const double radius = 60.0 - 3.2 * i;
    for (int k = 0; k <= 60; ++k) {
      const double th = 3.0 * k * kPi / 180.0;
      shape.emplace_back(300.0 + radius * std::sin(th), 60.0 - radius * std::cos(th));
    }
    shape.front() = Vec2(300.0, 3.2 * i);
    r.lanes.push_back(laneOf("b", i, std::move(shape)));
  }
  // lanes whose source length is not their shape's (SUMO's `length`): a car moves 1/0.6 times
  // its speed along the inner curve, 2/3 of it on the left straight lane
  double arc = 0.0;
  for (std::size_t k = 0; k + 1 < r.lanes[3].shape.size(); ++k) arc += (r.lanes[3].shape[k + 1] - r.lanes[3].shape[k]).norm();
  r.lanes[3].length = 0.6 * arc;
  r.lanes[2].length = 450.0;
  return r;
}

std::vector<VehicleState> tightScene(std::mt19937_64& rng, const RoadGeometry& road, int ticks, int k,
                                     std::vector<VehicleState>& base) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  if (k == 0) {
    base.clear();
    const int n = 20 + static_cast<int>(40 * U(rng));
    for (int i = 0; i < n; ++i) {
      const Lane& l = road.lanes[static_cast<std::size_t>(U(rng) * static_cast<double>(road.lanes.size()))];
      const std::size_t seg = static_cast<std::size_t>(U(rng) * static_cast<double>(l.shape.size() - 1));
      const Vec2 a = l.shape[seg], b = l.shape[seg + 1];
      const Vec2 u = (b - a).normalized();
      VehicleState v;
      v.id = "c" + std::to_string(i);
      v.handle = i;
      v.position = a + U(rng) * (b - a) + (U(rng) - 0.5) * 2.0 * Vec2(-u.y(), u.x());
      v.heading = std::atan2(u.y(), u.x()) + 0.1 * (U(rng) - 0.5);
      v.speed = U(rng) < 0.1 ? 0.0 : 40.0 * U(rng);
      v.lateralSpeed = U(rng) < 0.5 ? 0.0 : 2.0 * (U(rng) - 0.5);
      v.acceleration = 8.0 * (U(rng) - 0.6);
      if (U(rng) < 0.15) makeTruck(v);
      v.equipped = U(rng) < 0.9;
      base.push_back(v);
    }
  }
  (void)ticks;
  std::vector<VehicleState> out = base;
  for (VehicleState& v : out) v.position += 0.1 * k * v.velocity();
  return out;
}

TEST(RoadPrediction, PrunesKeepEveryThreatOfTheUnprunedPathsAndPathsStayWithinTheirDeviation) {
  // the pair searches prune with straight motion and envelopes grown by each car's deviation from
  // it; against every pair along the paths without any prune, threat by threat, cells and all
  // pairs, every detector, both motion models, on a tight curve
  std::mt19937_64 rng(4242);
  const RoadGeometry road = tightRoad();
  std::uint64_t threats = 0, curved = 0;
  const int scenes = test::scaledCount(240);
  for (int scene = 0; scene < scenes; ++scene) {
    MonitorConfig cfg;
    cfg.detector.kind = static_cast<DetectorKind>(scene % 3);
    cfg.detector.motion = (scene / 3) % 2 ? MotionModel::ConstantAcceleration : MotionModel::ConstantVelocity;
    cfg.cells.cellLength = 40.0 + 10.0 * (scene % 5);
    MonitorCounters counters, countersAll;
    VehicleTable cars(cfg, counters);
    LanePrediction paths(road, cfg, cars, counters);
    CellNetwork network(road, deriveFeatures(road), cfg.cells);
    const auto cells = makeCellPairSearch(PairTest{&cfg, &cars, &counters, &paths}, network);
    const auto all = makeAllPairsSearch(PairTest{&cfg, &cars, &countersAll, &paths});
    std::vector<VehicleState> base;
    const bool accel = cfg.detector.motion == MotionModel::ConstantAcceleration;
    for (int k = 0; k < 3; ++k) {
      const auto tick = tightScene(rng, road, 3, k, base);
      cars.update(0.1 * k, tick);
      paths.update(0.1 * k);
      cells->prepare();
      all->prepare();
      cars.release();
      for (int e : cars.active) {
        // the path within its deviation of the straight line (less what acceleration may add)
        const auto path = paths.path(e);
        curved += path.size() > 1;
        const Body& b = cars.body[e];
        const double dev = cars.env[e] - cars.ownEnv[e];
        for (double t = 0.0; t <= paths.horizon(e); t += 0.01) {
          const Body at = LanePrediction::bodyAt(path, b, cfg.detector.motion, t);
          const double allowed = dev + (accel ? 0.5 * std::abs(b.acceleration) * t * t : 0.0) + 1e-9;
          ASSERT_LE((at.position - b.position - b.velocity * t).norm(), allowed) << "scene " << scene << " t " << t;
          // and its shapes within the extents the prunes read, at every heading on the path
          const Vec2 ext = envelopeExtent(cfg.detector, at);
          ASSERT_LE(ext.x(), cars.ext[e].x() - dev + 1e-9) << "scene " << scene << " t " << t;
          ASSERT_LE(ext.y(), cars.ext[e].y() - dev + 1e-9) << "scene " << scene << " t " << t;
        }
        if (!cars.equipped[e]) continue;
        std::vector<Threat> want;
        for (int f : cars.active) {
          if (f == e) continue;
          const Vec2 p = cars.centre[f] - cars.centre[e], v = cars.vel[f] - cars.vel[e];
          const double dist = p.norm();
          const double closing = dist > 0.0 ? -p.dot(v) / dist : v.norm();
          const double safe = SafeTimeConfig::safeTimeOf(cfg.safeTime.vehicleReactionTime, cars.mass[e], closing,
                                                         cars.pairState[e].twiceBrakeForce);
          const Ttc ttc = paths.vehicleTtc(e, f, safe);
          if (ttc.found() && ttc.t() <= safe) want.push_back({cars.pairState[f].serial, WarningKind::Vehicle, ttc.zone, ttc.t(), safe, f});
        }
        for (const auto& search : {&cells, &all}) {
          std::vector<Threat> got;
          (*search)->threatsOf(e, got);
          auto key = [](const Threat& t) { return std::make_tuple(t.key, t.ttc, t.safe); };
          std::sort(got.begin(), got.end(), [&](const Threat& x, const Threat& y) { return key(x) < key(y); });
          std::sort(want.begin(), want.end(), [&](const Threat& x, const Threat& y) { return key(x) < key(y); });
          ASSERT_EQ(got.size(), want.size()) << "scene " << scene << " tick " << k << " ego " << cars.slots[e].id;
          for (std::size_t i = 0; i < got.size(); ++i) {
            EXPECT_EQ(got[i].key, want[i].key);
            EXPECT_NEAR(got[i].ttc, want[i].ttc, 1e-12) << "scene " << scene;
            EXPECT_EQ(got[i].safe, want[i].safe);
          }
        }
        threats += want.size();
      }
    }
  }
  EXPECT_GT(threats, 1000u * scenes / 240);
  EXPECT_GT(curved, 1000u * scenes / 240);
}

// A lane "in" ends at a junction with two junction lanes: straight on (to "east"), and a left
// turn (a quarter circle of 8 m, to "north").
RoadGeometry turnJunction() {
  RoadGeometry road;
  road.lanes.push_back(laneOf("in", 0, {Vec2(-100.0, 0.0), Vec2(0.0, 0.0)}));
  Lane straight = laneOf(":j_0", 0, {Vec2(0.0, 0.0), Vec2(16.0, 0.0)});
  straight.internal = true;
  Lane left = laneOf(":j_1", 0, {});
  left.internal = true;
  for (int k = 0; k <= 9; ++k) {
    const double th = 0.5 * kPi * k / 9.0;
    left.shape.emplace_back(8.0 * std::sin(th), 8.0 - 8.0 * std::cos(th));
  }
  road.lanes.push_back(straight);
  road.lanes.push_back(left);
  road.lanes.push_back(laneOf("north", 0, {Vec2(8.0, 8.0), Vec2(8.0, 100.0)}));
  road.lanes.push_back(laneOf("east", 0, {Vec2(16.0, 0.0), Vec2(100.0, 0.0)}));
  return road;
}

// turnJunction with a car 10 m before the junction at 10 m/s (its body and signal as given, its
// route as edge ids from its own edge on) and a faster car behind, which sets a longer horizon for
// both: the car's predicted path.
struct TurnScene {
  RoadGeometry road = turnJunction();
  MonitorConfig cfg;
  MonitorCounters counters;
  VehicleTable cars{cfg, counters};
  LanePrediction paths{road, cfg, cars, counters};
  int e = -1;  // the car's slot

  TurnScene(VehicleState v, const std::vector<std::string>& route) {
    const std::vector<std::string> edges = edgeIds(road);
    v.position = Vec2(-10.0, 0.0);
    v.speed = 10.0;
    for (std::size_t k = 0; k < route.size(); ++k)
      v.route[k] = static_cast<int>(std::find(edges.begin(), edges.end(), route[k]) - edges.begin());
    VehicleState fast = v;  // of the same kind
    fast.id = "fast";
    fast.signals = kSignalNone;
    fast.route.fill(-1);
    fast.position = Vec2(-80.0, 0.0);
    fast.speed = 40.0;
    const std::vector<VehicleState> tick = {v, fast};
    cars.update(0.0, tick);
    paths.update(0.0);
    e = cars.active[0];
  }
  Body at(double t) const { return LanePrediction::bodyAt(paths.path(e), cars.body[e], MotionModel::ConstantVelocity, t); }
};

// Where a car 10 m before turnJunction's junction at 10 m/s is 3 s on, given its signal and route
// (edge ids, from its own edge on).
Body turnedAfter3s(std::uint8_t signal, const std::vector<std::string>& route, std::uint64_t* routePredicted = nullptr) {
  VehicleState v;
  v.id = "car";
  v.signals = signal;
  const TurnScene scene(v, route);
  if (routePredicted) *routePredicted = scene.counters.routePredicted;
  return scene.at(3.0);  // 30 m on
}

bool onNorthLane(const Body& at) {
  // 30 - 10 - 4 pi = 7.4 m up it (the polyline's arc is a little shorter than the circle's)
  return std::abs(at.position.x() - 8.0) < 1e-6 && std::abs(at.position.y() - (8.0 + 20.0 - 4.0 * kPi)) < 0.05 &&
         std::abs(at.axis.y() - 1.0) < 1e-9;
}
bool onEastLane(const Body& at) { return std::abs(at.position.x() - 20.0) < 1e-9 && std::abs(at.position.y()) < 1e-12; }

TEST(RoadPrediction, ASignalledTurnIsPredictedOntoItsTurningLane) {
  // straight on without a signal, round the left turn with its left signal on
  EXPECT_TRUE(onEastLane(turnedAfter3s(kSignalNone, {})));
  EXPECT_TRUE(onNorthLane(turnedAfter3s(kSignalLeft, {})));
}

TEST(RoadPrediction, TheRouteIsFollowedThroughTheJunctionOverTheSignal) {
  // SUMO's route says where the car goes: round the turn unsignalled, straight on though it
  // signals left; a route that does not hold the car's edge is ignored (signal, then straight)
  std::uint64_t followed = 0;
  EXPECT_TRUE(onNorthLane(turnedAfter3s(kSignalNone, {"in", "north"}, &followed)));
  EXPECT_EQ(followed, 1u);
  EXPECT_TRUE(onEastLane(turnedAfter3s(kSignalLeft, {"in", "east"})));
  EXPECT_TRUE(onEastLane(turnedAfter3s(kSignalNone, {"in"})));  // the route ends: straight on
  EXPECT_TRUE(onNorthLane(turnedAfter3s(kSignalLeft, {"north"}, &followed)));
  EXPECT_EQ(followed, 0u);
  EXPECT_TRUE(onEastLane(turnedAfter3s(kSignalNone, {"elsewhere"})));
}

// A 10 m truck predicted round turnJunction's 8 m left turn is laid as SUMO lays it: the chord
// from its back to its front, both on the lanes' centre lines. Turned about its centre square to
// each segment, its back would swing 1.4 m off them.
TEST(RoadPrediction, ATruckRoundATurnHasItsBackAndFrontOnTheLanes) {
  VehicleState v;
  v.id = "truck";
  v.vehicleClass = VehicleClass::Truck;
  v.length = 10.0;
  v.width = 2.5;
  const TurnScene scene(v, {"in", "north"});
  const RoadGeometry& road = scene.road;
  // the distance from the lanes it drives: in, the turn's polyline, north
  auto offLanes = [&](const Vec2& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const char* edge : {"in", ":j_1", "north"})
      for (const Lane& l : road.lanes)
        if (l.edge == edge)
          for (std::size_t k = 1; k < l.shape.size(); ++k) {
            const Vec2 a = l.shape[k - 1], ab = l.shape[k] - a;
            const double f = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
            best = std::min(best, (p - a - f * ab).norm());
          }
    return best;
  };
  // over its horizon (1.5 s: from 10 m before the turn to 5 m into it), every 0.02 s. A heading is
  // held for a piece (a quarter of its length, or a polyline segment: 1.4 m here), so an end strays
  // up to 0.85 m; turned square to each segment about its centre, 1.79 m.
  ASSERT_GT(scene.paths.horizon(scene.e), 1.4);
  double worst = 0.0;
  for (double t = 0.0; t <= scene.paths.horizon(scene.e); t += 0.02) {
    const Body at = scene.at(t);
    worst = std::max({worst, offLanes(at.position + 5.0 * at.axis), offLanes(at.position - 5.0 * at.axis)});
  }
  EXPECT_LT(worst, 1.0);
}

TEST(RoadPrediction, WithoutANetworkEveryCarGoesStraight) {
  // no lanes: the road prediction is the straight line, every update a fallback; the same TTC
  std::vector<VehicleState> cars(2);
  cars[0].id = "follower";
  cars[0].speed = 30.0;
  cars[1].id = "leader";
  cars[1].position = Vec2(20.0, 0.0);
  cars[1].speed = 20.0;
  double ttc[2];
  for (Prediction p : {Prediction::Road, Prediction::Straight}) {
    MonitorConfig cfg;
    cfg.prediction = p;
    cfg.detector.kind = DetectorKind::Box;
    HighwayMonitor m(RoadGeometry{}, cfg);
    m.step(0.0, cars);
    const auto open = m.openWarnings();
    ASSERT_FALSE(open.empty());
    ttc[static_cast<int>(p)] = open[0].minTtc;
    if (p == Prediction::Road) {
      EXPECT_EQ(m.counters().straightFallbacks, 2u);
    }
  }
  EXPECT_EQ(ttc[0], ttc[1]);
  EXPECT_NEAR(ttc[0], 1.5, 1e-9);
}


TEST(RoadPrediction, ALaneLongerThanItsLengthCarriesTheCarFasterAlongIt) {
  // SUMO moves a car along a lane at shape / length times its speed (a netedit lane of 80 m drawn
  // 111 m long): a follower reporting 20 m/s on a 200 m shape of length 100 closes at 40 m/s on a
  // stopped car 35 m ahead, box TTC 35 / 40 = 0.875 s; the straight line takes its 20 m/s
  RoadGeometry road;
  road.lanes.push_back(laneOf("long", 0, {Vec2(0.0, 0.0), Vec2(200.0, 0.0)}));
  road.lanes[0].length = 100.0;
  std::vector<VehicleState> cars(2);
  cars[0].id = "follower";
  cars[0].position = Vec2(20.0, 0.0);
  cars[0].speed = 20.0;
  cars[1].id = "stopped";
  cars[1].position = Vec2(60.0, 0.0);
  cars[1].equipped = false;
  for (Prediction p : {Prediction::Road, Prediction::Straight}) {
    MonitorConfig cfg = config(DetectorKind::Box, p);
    cfg.checkRoad = false;
    HighwayMonitor m(road, cfg);
    m.step(0.0, cars);
    const auto open = m.openWarnings();
    ASSERT_EQ(open.size(), 1u);
    EXPECT_NEAR(open[0].minTtc, p == Prediction::Road ? 0.875 : 1.75, 1e-9) << toString(p);
  }
}

// The point at arc s along a polyline (beyond its end: on its last segment's extension) and the
// direction of the segment it is on.
std::pair<Vec2, Vec2> along(const std::vector<Vec2>& line, double s) {
  for (std::size_t k = 0; k + 1 < line.size(); ++k) {
    const double len = (line[k + 1] - line[k]).norm();
    const Vec2 u = (line[k + 1] - line[k]) / len;
    if (s <= len || k + 2 == line.size()) return {line[k] + s * u, u};
    s -= len;
  }
  return {line.front(), Vec2(1.0, 0.0)};
}

TEST(RoadPrediction, LeavingAJunctionLaneSidewaysIsNoLateralMotion) {
  // a two-way street: a car comes out of a junction lane that shifts it 3.2 m to the left onto the
  // northbound lane, placed as SUMO places it (its front and rear on the lanes, its heading from
  // its rear to its front, its centre half a length behind), while a car drives south on the
  // other lane, 3.2 m to its left: they pass 1.4 m apart and neither ever warns. (SUMO heads a car
  // from its rear to its front, so the centre sits off its new lane until the rear leaves the
  // junction; that offset shrinking, read as lateral motion, drove the car into the oncoming one.)
  RoadGeometry road;
  road.lanes.push_back(laneOf("in", 0, {Vec2(3.2, -200.0), Vec2(3.2, 0.0)}));
  Lane shift = laneOf(":j_0", 0, {Vec2(3.2, 0.0), Vec2(2.7, 3.0), Vec2(1.6, 5.0), Vec2(0.5, 7.0), Vec2(0.0, 10.0)});
  shift.internal = true;
  road.lanes.push_back(shift);
  road.lanes.push_back(laneOf("north", 0, {Vec2(0.0, 10.0), Vec2(0.0, 300.0)}));
  road.lanes.push_back(laneOf("south", 0, {Vec2(-3.2, 300.0), Vec2(-3.2, 12.0)}));
  std::vector<Vec2> route;
  for (int k : {0, 1, 2})
    for (const Vec2& q : road.lanes[k].shape)
      if (route.empty() || (q - route.back()).norm() > 1e-9) route.push_back(q);
  const double speed = 15.0, dt = 0.1;
  // (the concentric detector's outer circles overlap across adjacent lanes by design)
  for (DetectorKind kind : {DetectorKind::Box, DetectorKind::FiveCircle}) {
    MonitorConfig cfg = config(kind, Prediction::Road);
    cfg.checkRoad = false;
    const Drive r = drive(road, cfg, 100, dt, [&](double t) {
      std::vector<VehicleState> cars(2);
      cars[0].id = "out";
      // its front reaches the junction at 0.8 s and the north lane at 1.5 s
      const double s = 200.0 - 12.5 + speed * t;
      const Vec2 front = along(route, s).first, rear = along(route, s - 5.0).first;
      const Vec2 dir = (front - rear).normalized();
      cars[0].heading = std::atan2(dir.y(), dir.x());
      cars[0].position = front - 2.5 * dir;
      cars[0].speed = speed;
      cars[1].id = "oncoming";  // level with the first at 3.6 s, 1.7 s after its rear left the junction
      cars[1].position = Vec2(-3.2, 92.35 - speed * t);
      cars[1].heading = -0.5 * kPi;
      cars[1].speed = speed;
      return cars;
    });
    EXPECT_EQ(countKind(r, WarningKind::Vehicle), 0u) << toString(kind);
  }
}


TEST(RoadPrediction, ATruckFollowingAKinkedLaneStaysInIt) {
  // a 3.75 m lane whose centre line turns 14 degrees at one vertex (SUMO's polylines); a 12 m,
  // 2.55 m truck drives it placed as SUMO places it (front and rear on the line, heading from rear
  // to front): its centre cuts 0.7 m inside the bend, its side 0.1 m over the curb line, yet it
  // follows its lane: no curb warning and no crossing (measured from the line, it is one)
  const double turn = 14.0 * kPi / 180.0;
  RoadGeometry road;
  road.lanes.push_back(laneOf("ramp", 0, {Vec2(0.0, 0.0), Vec2(300.0, 0.0), Vec2(300.0 + 300.0 * std::cos(turn), -300.0 * std::sin(turn))}));
  road.lanes[0].width = 3.75;
  for (DetectorKind kind : {DetectorKind::Box, DetectorKind::FiveCircle}) {
    MonitorConfig cfg = config(kind, Prediction::Road);
    double worst = 0.0;  // the centre's largest distance from the line
    const Drive r = drive(road, cfg, 200, 0.1, [&](double t) {
      const double s = 250.0 + 20.0 * t;  // the front
      const Vec2 front = along(road.lanes[0].shape, s).first, rear = along(road.lanes[0].shape, s - 12.0).first;
      const Vec2 dir = (front - rear).normalized();
      VehicleState v;
      v.id = "truck";
      makeTruck(v);
      v.width = 2.55;
      v.heading = std::atan2(dir.y(), dir.x());
      v.position = front - 6.0 * dir;
      v.speed = 20.0;
      const Vec2 c = v.position;
      worst = std::max(worst, c.x() <= 300.0 ? std::abs(c.y()) : std::abs(std::sin(turn) * (c.x() - 300.0) + std::cos(turn) * c.y()));
      return std::vector<VehicleState>{v};
    });
    EXPECT_GT(worst, 0.6);  // so the side reached over the line (1.875 - 1.275 = 0.6 m of room)
    EXPECT_EQ(countKind(r, WarningKind::Curb), 0u) << toString(kind);
    EXPECT_EQ(r.counters.crossings, 0u) << toString(kind);
  }
}

TEST(RoadPrediction, ABusTurningTightlyInAJunctionStaysOnItsLanes) {
  // a right turn on a junction lane of radius 10 m, as SUMO's cross network has them; a 12.5 m
  // bus driven through it placed as SUMO places it (front and rear on the lanes, heading from rear
  // to front): mid-turn its centre lies 2.2 m inside the bend, beyond the lane's side, yet it is
  // on its lane every tick (predicted straight it crossed the other arm of the junction: SUMO's
  // cross had warnings against the cars waiting there) and never warns about a curb
  RoadGeometry road;
  road.lanes.push_back(laneOf("in", 0, {Vec2(0.0, -200.0), Vec2(0.0, 0.0)}));
  std::vector<Vec2> arc;
  for (int k = 0; k <= 9; ++k) {
    const double th = k * kPi / 18.0;
    arc.emplace_back(10.0 - 10.0 * std::cos(th), 10.0 * std::sin(th));
  }
  Lane turn = laneOf(":j_0", 0, arc);
  turn.internal = true;
  road.lanes.push_back(turn);
  road.lanes.push_back(laneOf("out", 0, {Vec2(10.0, 10.0), Vec2(300.0, 10.0)}));
  std::vector<Vec2> route;
  for (int k : {0, 1, 2})
    for (const Vec2& q : road.lanes[k].shape)
      if (route.empty() || (q - route.back()).norm() > 1e-9) route.push_back(q);
  for (DetectorKind kind : {DetectorKind::Box, DetectorKind::FiveCircle}) {
    MonitorConfig cfg = config(kind, Prediction::Road);
    double worst = 0.0;  // the centre's largest distance inside the arc
    const Drive r = drive(road, cfg, 40, 0.1, [&](double t) {
      const double s = 195.0 + 8.0 * t;  // the front: into the turn at 0.6 s, out of it at 2.6 s
      const Vec2 front = along(route, s).first, rear = along(route, s - 12.5).first;
      const Vec2 dir = (front - rear).normalized();
      VehicleState v;
      v.id = "bus";
      makeTruck(v);
      v.length = 12.5;
      v.width = 2.4;
      v.heading = std::atan2(dir.y(), dir.x());
      v.position = front - 6.25 * dir;
      v.speed = 8.0;
      const Vec2 c = v.position - Vec2(10.0, 0.0);
      if (c.x() < 0.0 && c.y() > 0.0) worst = std::max(worst, 10.0 - c.norm());
      return std::vector<VehicleState>{v};
    });
    EXPECT_GT(worst, 1.6 + 0.25);  // beyond the lane's side and the slack a kept lane has
    EXPECT_EQ(r.counters.straightFallbacks, 0u) << toString(kind);
    EXPECT_EQ(countKind(r, WarningKind::Curb), 0u) << toString(kind);
  }
}

}  // namespace
}  // namespace detail
}  // namespace st::highway
