// What a warning records of its tick of minimum TTC, on constructed encounters: the type by
// SSAM's angles (a rear-end, a lane change, a 90-degree crossing at a junction netconvert builds
// here), the position and lane, the speeds, DRAC and MaxDeltaV against hand-computed values, a
// curb's lateral speed; and the conflict map drawn from a replay (one SVG marker per warning).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <sthighway/conflict_map.hpp>
#include <sthighway/monitor.hpp>
#include <sthighway/report.hpp>
#include <sthighway/sumo_files.hpp>

#include "files.hpp"
#include "roads.hpp"
#include "svg_markers.hpp"

namespace st::highway {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

VehicleState car(const std::string& id, Vec2 p, double headingDeg, double speed, double lateral = 0.0) {
  VehicleState v;
  v.id = id;
  v.position = p;
  v.heading = headingDeg * kPi / 180.0;
  v.speed = speed;
  v.lateralSpeed = lateral;
  return v;
}

MonitorConfig boxConfig(bool road) {
  MonitorConfig cfg;
  cfg.detector.kind = DetectorKind::Box;  // exact rectangles: TTCs by hand
  cfg.broadphase = Broadphase::AllPairs;
  cfg.checkRoad = road;
  return cfg;
}

// One tick, then finish: the minimum is that tick's.
std::vector<Warning> oneTick(const RoadGeometry& road, const MonitorConfig& cfg, std::vector<VehicleState> cars) {
  HighwayMonitor m(road, cfg);
  m.step(0.0, cars);
  m.finish(0.1);
  return m.takeFinished();
}

const Warning* find(const std::vector<Warning>& ws, const std::string& ego, WarningKind kind) {
  for (const auto& w : ws)
    if (w.ego == ego && w.kind == kind) return &w;
  return nullptr;
}

TEST(ConflictRecord, RearEndWithDracAndDeltaVByHand) {
  // follower 30 m/s at x = 0, a 15 t truck (12 m) at 20 m/s ahead, 15 m of gap bumper to bumper
  VehicleState f = car("follower", Vec2(0.0, 0.0), 0.0, 30.0);
  VehicleState l = car("truck", Vec2(2.5 + 15.0 + 6.0, 0.0), 0.0, 20.0);
  l.length = 12.0;
  l.width = 2.55;
  l.mass = 15000.0;
  l.vehicleClass = VehicleClass::Truck;
  l.equipped = false;
  const auto ws = oneTick(oneLaneRoad(), boxConfig(false), {f, l});
  const Warning* w = find(ws, "follower", WarningKind::Vehicle);
  ASSERT_NE(w, nullptr);
  EXPECT_NEAR(w->minTtc, 1.5, 1e-9);  // 15 m at 10 m/s
  EXPECT_EQ(w->type, ConflictType::RearEnd);
  EXPECT_NEAR(w->headingAngle, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(w->x, 0.0);
  EXPECT_DOUBLE_EQ(w->y, 0.0);
  EXPECT_DOUBLE_EQ(w->egoSpeed, 30.0);
  EXPECT_DOUBLE_EQ(w->foeSpeed, 20.0);
  // DRAC = 10^2 / (2 * 15) = 3.333 m/s^2
  EXPECT_NEAR(w->drac, 100.0 / 30.0, 1e-9);
  // inelastic impact: the car takes 15000/16500 of the 10 m/s difference
  EXPECT_NEAR(w->maxDeltaV, 10.0 * 15000.0 / 16500.0, 1e-9);
  EXPECT_EQ(w->lane, "e_0");  // no lane given: the one the road prediction matched
  EXPECT_TRUE(w->line.empty());
  EXPECT_TRUE(std::isnan(w->lateralSpeed));
}

TEST(ConflictRecord, LaneChangeBetweenTheThresholds) {
  // the ego cuts in at 40 degrees towards a car in the next lane; relative motion straight at it
  const VehicleState e = car("ego", Vec2(0.0, 0.0), 40.0, 20.0);
  const Vec2 rel = e.velocity() - Vec2(10.0, 0.0);
  VehicleState o = car("other", rel, 0.0, 10.0);
  o.equipped = false;
  const auto ws = oneTick(oneLaneRoad(), boxConfig(false), {e, o});
  const Warning* w = find(ws, "ego", WarningKind::Vehicle);
  ASSERT_NE(w, nullptr);
  EXPECT_NEAR(w->headingAngle, 40.0, 1e-9);
  EXPECT_EQ(w->type, ConflictType::LaneChange);
  // the same encounter with the lane-change band closed below 40 degrees is a crossing
  MonitorConfig narrow = boxConfig(false);
  narrow.conflict.crossingAboveDeg = 35.0;
  const auto ws2 = oneTick(oneLaneRoad(), narrow, {e, o});
  ASSERT_NE(find(ws2, "ego", WarningKind::Vehicle), nullptr);
  EXPECT_EQ(find(ws2, "ego", WarningKind::Vehicle)->type, ConflictType::Crossing);
  // and with the rear-end band opened above it, a rear-end
  MonitorConfig wide = boxConfig(false);
  wide.conflict.rearEndBelowDeg = 45.0;
  EXPECT_EQ(find(oneTick(oneLaneRoad(), wide, {e, o}), "ego", WarningKind::Vehicle)->type, ConflictType::RearEnd);
}

TEST(ConflictRecord, CurbWarningCarriesTheLineAndTheLateralSpeed) {
  // drifting right at 2 m/s, 0.7 m from the curb (lane 3.2 m, car 1.8 m): TTC 0.35 s
  const auto ws = oneTick(oneLaneRoad(), boxConfig(true), {car("drifter", Vec2(0.0, 0.0), 0.0, 25.0, -2.0)});
  const Warning* w = find(ws, "drifter", WarningKind::Curb);
  ASSERT_NE(w, nullptr);
  EXPECT_NEAR(w->minTtc, 0.35, 1e-9);
  EXPECT_EQ(w->type, ConflictType::Road);
  EXPECT_EQ(w->line, "e:right");
  EXPECT_NEAR(w->lateralSpeed, 2.0, 1e-12);
  EXPECT_NEAR(w->drac, 4.0 / (2.0 * 0.7), 1e-9);  // v^2 / (2 gap)
  EXPECT_NEAR(w->headingAngle, 0.0, 1e-12);        // parallel to the curb
  EXPECT_TRUE(std::isnan(w->maxDeltaV));
  EXPECT_TRUE(std::isnan(w->foeSpeed));
}

// three lanes of the given width, centre lines at y = -width, 0, width (indices 0, 1, 2)
RoadGeometry threeLaneRoad(double width) {
  RoadGeometry r;
  for (int i = 0; i < 3; ++i)
    r.lanes.push_back({"e_" + std::to_string(i), "e", i, {Vec2(-100.0, (i - 1) * width), Vec2(1000.0, (i - 1) * width)},
                       width, false});
  return r;
}
RoadGeometry twoLaneRoad() { return threeLaneRoad(3.2); }

MonitorConfig fiveConfig() {
  MonitorConfig cfg;
  cfg.detector.kind = DetectorKind::FiveCircle;  // Fig. 11(a), the main job's
  cfg.broadphase = Broadphase::AllPairs;
  cfg.checkRoad = false;
  return cfg;
}

VehicleState truck(const std::string& id, Vec2 p, double speed) {
  VehicleState v = car(id, p, 0.0, speed);
  v.length = 12.0;  // the motorway's trucks
  v.width = 2.55;
  v.mass = 20000.0;
  v.vehicleClass = VehicleClass::Truck;
  return v;
}

// Side by side in adjacent lanes, the five-circle detector's side circles reach into the other
// vehicle: a truck's (radius 2.1 m about a point 0.64 m off its axis) into a car's body circle
// (1.23 m) across the motorway's 3.75 m lanes, two cars' across 2.5 m lanes: TTC 0 in zone left
// or right, though the bodies run parallel and never meet. That is a proximity state, never a
// rear-end conflict, whatever the speeds (level, overtaken with the centres closing, pulling
// away), under either prediction; it has no DRAC. The box detector does not warn at all.
TEST(ConflictRecord, SideBySideInTheFiveCircleZonesIsProximityNeverRearEnd) {
  struct Case {
    const char* what;
    double laneWidth;
    VehicleState ego, other;
    Zone zone;
  };
  const double w = 3.75;
  const Case cases[] = {
      {"a car level on the truck's left", w, truck("ego", Vec2(0.0, 0.0), 25.0), car("other", Vec2(0.0, w), 0.0, 25.0), Zone::Left},
      {"a car overtaking on the left, centres closing", w, truck("ego", Vec2(0.0, 0.0), 25.0),
       car("other", Vec2(-2.0, w), 0.0, 27.0), Zone::Left},
      {"a car on the right pulling away", w, truck("ego", Vec2(0.0, 0.0), 25.0), car("other", Vec2(2.0, -w), 0.0, 26.0),
       Zone::Right},
      {"two cars in 2.5 m lanes", 2.5, car("ego", Vec2(0.0, 0.0), 0.0, 25.0), car("other", Vec2(0.5, 2.5), 0.0, 24.0),
       Zone::Left}};
  for (Case k : cases) {
    k.ego.lane = 1;
    k.other.lane = k.other.position.y() > 0.0 ? 2 : 0;
    k.other.equipped = false;
    for (Prediction pred : {Prediction::Road, Prediction::Straight}) {
      MonitorConfig cfg = fiveConfig();
      cfg.prediction = pred;
      const auto ws = oneTick(threeLaneRoad(k.laneWidth), cfg, {k.ego, k.other});
      const Warning* x = find(ws, "ego", WarningKind::Vehicle);
      ASSERT_NE(x, nullptr) << k.what;
      EXPECT_EQ(x->minTtc, 0.0) << k.what;  // the zone already overlaps the other vehicle
      EXPECT_EQ(x->zone, k.zone) << k.what;
      EXPECT_EQ(x->type, ConflictType::Proximity) << k.what;
      EXPECT_NE(x->type, ConflictType::RearEnd) << k.what;
      EXPECT_TRUE(std::isnan(x->drac)) << k.what;
      EXPECT_NEAR(x->headingAngle, 0.0, 1e-12);  // still recorded, and the impact's severity
      EXPECT_FALSE(std::isnan(x->maxDeltaV));
      MonitorConfig box = cfg;
      box.detector.kind = DetectorKind::Box;
      EXPECT_EQ(find(oneTick(threeLaneRoad(k.laneWidth), box, {k.ego, k.other}), "ego", WarningKind::Vehicle), nullptr)
          << k.what;
    }
  }
}

// The same zones occupied on a collision course are typed by SSAM's angles: a car cutting in
// (10 degrees towards the other, whose side it reaches within its safe time), and a follower
// whose front circle is already in the leader, closing fast enough to touch within the safe time.
TEST(ConflictRecord, ZonesOccupiedOnACollisionCourseKeepTheirSsamType) {
  // cutting in: heading 10 deg to the left at 25 m/s (4.3 m/s across the 0.7 m between the bodies)
  VehicleState in = car("in", Vec2(0.0, 0.0), 10.0, 25.0);
  VehicleState next = car("next", Vec2(0.0, 2.5), 0.0, 25.0);
  next.equipped = false;
  const auto ws = oneTick(threeLaneRoad(2.5), fiveConfig(), {in, next});
  const Warning* w = find(ws, "in", WarningKind::Vehicle);
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->minTtc, 0.0);
  EXPECT_NEAR(w->headingAngle, 10.0, 1e-9);
  EXPECT_EQ(w->type, ConflictType::RearEnd);  // SSAM: below 30 degrees
  EXPECT_TRUE(std::isinf(w->drac));           // closing at TTC 0
  // rear-end: 0.5 m bumper to bumper, closing at 5 m/s (touching in 0.1 s)
  VehicleState f = car("follower", Vec2(0.0, 0.0), 0.0, 30.0);
  VehicleState l = car("leader", Vec2(5.5, 0.0), 0.0, 25.0);
  l.equipped = false;
  const auto ws2 = oneTick(twoLaneRoad(), fiveConfig(), {f, l});
  const Warning* r = find(ws2, "follower", WarningKind::Vehicle);
  ASSERT_NE(r, nullptr);
  EXPECT_EQ(r->zone, Zone::Front);
  EXPECT_EQ(r->type, ConflictType::RearEnd);
  EXPECT_FALSE(std::isnan(r->drac));
  // the same follower at the leader's speed: its front circle in the leader, no collision course
  f.speed = 25.0;
  const auto ws3 = oneTick(twoLaneRoad(), fiveConfig(), {f, l});
  ASSERT_NE(find(ws3, "follower", WarningKind::Vehicle), nullptr);
  EXPECT_EQ(find(ws3, "follower", WarningKind::Vehicle)->type, ConflictType::Proximity);
}

// summary.json's conflicts.with_bicycle and the console's count: the counters as they are, and a
// run with no conflict with a bicycle reads as before (no "with a bicycle" on the console).
TEST(ConflictRecord, BicycleConflictsCountApartInSummaryAndConsole) {
  MonitorCounters c;
  c.conflictsByType[static_cast<int>(ConflictType::RearEnd)] = 5;
  c.conflictsByType[static_cast<int>(ConflictType::Crossing)] = 2;
  EXPECT_EQ(conflictCountText(c), "7 (rear_end 5, lane_change 0, crossing 2, pedestrian 0)");
  EXPECT_NE(conflictsJson(c, ConflictConfig{}).find("\"with_bicycle\": {\"count\": 0, \"between_bicycles\": 0, "
                                                    "\"by_type\": {\"rear_end\": 0, \"lane_change\": 0, \"crossing\": 0, "
                                                    "\"pedestrian\": 0}}"),
            std::string::npos);
  c.conflictsWithBicycle[static_cast<int>(ConflictType::RearEnd)] = 3;
  c.conflictsWithBicycle[static_cast<int>(ConflictType::Crossing)] = 1;
  c.conflictsBetweenBicycles = 2;
  EXPECT_EQ(conflictsWithBicycle(c), 4u);
  EXPECT_EQ(conflictCountText(c), "7 (rear_end 5, lane_change 0, crossing 2, pedestrian 0; with a bicycle 4: rear_end 3, "
                                  "lane_change 0, crossing 1, pedestrian 0, between two bicycles 2)");
  const std::string json = conflictsJson(c, ConflictConfig{});
  EXPECT_NE(json.find("\"with_bicycle\": {\"count\": 4, \"between_bicycles\": 2, \"by_type\": {\"rear_end\": 3, "
                      "\"lane_change\": 0, \"crossing\": 1, \"pedestrian\": 0}}"),
            std::string::npos)
      << json;
}

TEST(ConflictRecord, ProximityCountsApartFromTheSsamTypes) {
  HighwayMonitor m(threeLaneRoad(2.5), fiveConfig());
  VehicleState ego = car("ego", Vec2(0.0, 0.0), 0.0, 25.0), other = car("other", Vec2(0.0, 2.5), 0.0, 25.0);
  ego.lane = 1;
  other.lane = 2;
  m.step(0.0, std::vector<VehicleState>{ego, other});
  m.finish(0.1);
  const auto& c = m.counters();
  EXPECT_EQ(c.warningsByType[static_cast<int>(ConflictType::Proximity)], 2u);
  EXPECT_EQ(c.warningsByType[static_cast<int>(ConflictType::RearEnd)], 0u);
  EXPECT_EQ(conflictWarnings(c), 0u);
  RunInfo info;
  const std::string json = summaryJson(c, info);
  EXPECT_NE(json.find("\"conflicts\": 0,\n    \"by_type\": {\"rear_end\": 0, \"lane_change\": 0, \"crossing\": 0, "
                      "\"pedestrian\": 0, \"proximity\": 2, \"road\": 0}"),
            std::string::npos)
      << json;
  EXPECT_EQ(conflictTypeBreakdown(c),
            "rear_end 0, lane_change 0, crossing 0, pedestrian 0; proximity 2 (zone occupied, no collision course); road 0");
  // in warnings.csv: the type and an empty DRAC
  const std::string row = warningCsvRow(m.takeFinished().front());
  EXPECT_NE(row.find(",proximity,,"), std::string::npos) << row;
}

// a cross junction: four one-lane edges into and out of c
fs::path buildJunction(const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream(dir / "x.nod.xml") << R"(<nodes>
  <node id="c" x="0" y="0" type="priority"/>
  <node id="w" x="-100" y="0"/> <node id="e" x="100" y="0"/>
  <node id="s" x="0" y="-100"/> <node id="n" x="0" y="100"/>
</nodes>)";
  std::ofstream(dir / "x.edg.xml") << R"(<edges>
  <edge id="w2c" from="w" to="c" numLanes="1" speed="13.9"/> <edge id="c2e" from="c" to="e" numLanes="1" speed="13.9"/>
  <edge id="s2c" from="s" to="c" numLanes="1" speed="13.9"/> <edge id="c2n" from="c" to="n" numLanes="1" speed="13.9"/>
</edges>)";
  const fs::path net = dir / "x.net.xml";
  const std::string cmd = "netconvert --node-files " + (dir / "x.nod.xml").string() + " --edge-files " +
                          (dir / "x.edg.xml").string() + " --no-turnarounds -o " + net.string() + " > /dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return net;
}

TEST(ConflictRecord, RightAngleCrossingAtANetconvertJunction) {
  if (std::system("command -v netconvert > /dev/null 2>&1") != 0) GTEST_SKIP() << "netconvert not installed";
  const fs::path dir = fs::temp_directory_path() / ("sthighway_junction_" + std::to_string(::getpid()));
  const RoadGeometry road = readSumoNet(buildJunction(dir));
  int west = -1, south = -1;
  for (std::size_t i = 0; i < road.lanes.size(); ++i) {
    if (road.lanes[i].id == "w2c_0") west = static_cast<int>(i);
    if (road.lanes[i].id == "s2c_0") south = static_cast<int>(i);
  }
  ASSERT_GE(west, 0);
  ASSERT_GE(south, 0);
  // each lane's last segment, extended into the junction: the two centre lines meet at X
  auto lastSegment = [&](int i, Vec2& end, Vec2& along) {
    const auto& s = road.lanes[i].shape;
    end = s.back();
    along = (s.back() - s[s.size() - 2]).normalized();
  };
  Vec2 ew, dw, es, ds;
  lastSegment(west, ew, dw);
  lastSegment(south, es, ds);
  ASSERT_NEAR(std::abs(dw.dot(ds)), 0.0, 1e-6);  // the net is at right angles
  const double tw = cross(es - ew, ds) / cross(dw, ds);
  const Vec2 X = ew + tw * dw;
  // both 20 m before X at 10 m/s: they would meet at X at t = 2 s
  HighwayMonitor m(road, [] {
    MonitorConfig c = boxConfig(true);
    return c;
  }());
  double tLast = 0.0;
  for (int k = 0; k <= 8; ++k) {
    const double t = 0.1 * k;
    VehicleState a = car("east", X - (20.0 - 10.0 * t) * dw, std::atan2(dw.y(), dw.x()) * 180.0 / kPi, 10.0);
    VehicleState b = car("north", X - (20.0 - 10.0 * t) * ds, std::atan2(ds.y(), ds.x()) * 180.0 / kPi, 10.0);
    a.lane = west;
    b.lane = south;
    m.step(t, std::vector<VehicleState>{a, b});
    tLast = t;
  }
  m.finish(tLast + 0.1);
  const auto ws = m.takeFinished();
  for (const char* ego : {"east", "north"}) {
    const Warning* w = find(ws, ego, WarningKind::Vehicle);
    ASSERT_NE(w, nullptr) << ego;
    EXPECT_EQ(w->type, ConflictType::Crossing) << ego;
    EXPECT_NEAR(w->headingAngle, 90.0, 1e-4) << ego;
    EXPECT_EQ(w->lane, std::string(ego) == "east" ? "w2c_0" : "s2c_0");
    // the position at the tick of the minimum TTC (the TTC falls every tick: the last one)
    EXPECT_NEAR(w->minTtcTime, tLast, 1e-12);
    const Vec2 at = X - (20.0 - 10.0 * w->minTtcTime) * (std::string(ego) == "east" ? dw : ds);
    EXPECT_NEAR(w->x, at.x(), 1e-9);
    EXPECT_NEAR(w->y, at.y(), 1e-9);
    // equal masses at right angles, 10 m/s each: MaxDeltaV = |dv| / 2 = 5 sqrt 2
    EXPECT_NEAR(w->maxDeltaV, 5.0 * std::sqrt(2.0), 1e-6);
    // closing at 10 sqrt 2 along the line of centres (symmetric approach)
    EXPECT_NEAR(w->drac, 10.0 * std::sqrt(2.0) / (2.0 * w->minTtc), 1e-6);
  }
  fs::remove_all(dir);
}

TEST(ConflictRecord, CsvColumnsAppendedInAFixedOrder) {
  const std::string h = warningsCsvHeader();
  // the old columns keep their names and places (the episode's, then hindsight's)
  EXPECT_EQ(h.rfind("ego,foe,kind,zone,begin,end,min_ttc,min_ttc_time,safe_time,open,"
                    "verdict,clearance,clearance_time,deceleration,crossed,signalled,", 0), 0u) << h;
  const std::string tail = ",x,y,lane,ego_speed,foe_speed,heading_angle,type,drac,max_delta_v,line,lateral_speed";
  ASSERT_GE(h.size(), tail.size());
  EXPECT_EQ(h.substr(h.size() - tail.size()), tail) << h;
  const auto ws = oneTick(oneLaneRoad(), boxConfig(true), {car("drifter", Vec2(0.0, 0.0), 0.0, 25.0, -2.0)});
  ASSERT_FALSE(ws.empty());
  const std::string row = warningCsvRow(ws.front());
  EXPECT_EQ(std::count(row.begin(), row.end(), ','), std::count(h.begin(), h.end(), ',')) << row;
}

using st::test::slurp;

long csvRows(const fs::path& csv) {
  const std::string s = slurp(csv);
  return std::count(s.begin(), s.end(), '\n') - 1;
}

// One point per row of conflicts.csv (a conflict, at TTC*), none for the warnings beside it.
TEST(ConflictMap, OneMarkerPerConflictInAValidPngAndSvg) {
  if (std::system("/usr/bin/python3 -c 'import matplotlib' > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "python3-matplotlib not installed";
  const fs::path data = fs::path(STSIM_SOURCE_DIR) / "tests/data/highway";
  const fs::path out = fs::temp_directory_path() / ("sthighway_map_" + std::to_string(::getpid()));
  fs::create_directories(out);
  const RoadGeometry road = readSumoNet(data / "lanedrop.net.xml");
  HighwayMonitor m(road, MonitorConfig{});
  FcdReader r(data / "lanedrop.fcd.xml", readSumoVehicleTypes(data / "lanedrop.rou.xml"), {}, &road);
  WarningsCsvWriter csv(out / "warnings.csv");
  ConflictsCsvWriter conflictsCsv(out / "conflicts.csv");
  std::vector<Conflict> conflicts;
  FcdFrame f;
  double last = 0.0;
  bool laned = false;
  for (int k = 0; k < 600 && r.next(f); ++k) {
    m.step(f.time, f.vehicles);
    last = f.time;
    for (const auto& v : f.vehicles) laned = laned || v.lane >= 0;
    csv.write(m.takeFinished());
    m.takeConflicts(conflicts);
    conflictsCsv.write(conflicts);
  }
  m.finish(last);
  csv.write(m.takeFinished());
  csv.flush();
  m.takeConflicts(conflicts);
  conflictsCsv.write(conflicts);
  conflictsCsv.flush();
  EXPECT_TRUE(laned);  // the trace's lane attributes became lane indices
  const long rows = csvRows(out / "conflicts.csv");
  ASSERT_GT(rows, 0);
  std::string why;
  ASSERT_TRUE(writeConflictMap({out / "map", data / "lanedrop.net.xml", {out / "conflicts.csv"}, "lanedrop"}, why)) << why;
  const std::string png = slurp(out / "map.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  const std::string svg = slurp(out / "map.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_EQ(st::test::svgMarkers(svg), rows);
  // the lanes are drawn: the network's lanes are in the picture's line collection
  EXPECT_NE(svg.find("LineCollection"), std::string::npos);
  // a lane id in the csv (the trace has lane attributes and the net)
  EXPECT_NE(slurp(out / "warnings.csv").find(",main_"), std::string::npos);
  fs::remove_all(out);
}

}  // namespace
}  // namespace st::highway
