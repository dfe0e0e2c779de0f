#include <gtest/gtest.h>

#include <array>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <sthighway/monitor.hpp>
#include <sthighway/report.hpp>
#include <sthighway/sumo_files.hpp>

#include "files.hpp"

namespace st::highway {
namespace {

namespace fs = std::filesystem;
const fs::path kData = fs::path(STSIM_SOURCE_DIR) / "tests/data/highway";

fs::path writeTemp(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("sthighway_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

using st::test::slurp;

// A trace replayed through a monitor, finished at its last frame: the warnings in the order
// they finished, and the counters; onFrame sees every frame after its step.
struct Replay {
  std::vector<Warning> warnings;
  MonitorCounters counters;
};
Replay replay(const RoadGeometry& road, const VehicleTypes& types, const fs::path& fcd, const MonitorConfig& cfg,
              const std::function<void(const FcdFrame&)>& onFrame = {}) {
  HighwayMonitor m(road, cfg);
  FcdReader r(fcd, types);
  FcdFrame f;
  double last = 0.0;
  Replay out;
  while (r.next(f)) {
    m.step(f.time, f.vehicles);
    for (auto& w : m.takeFinished()) out.warnings.push_back(std::move(w));
    if (onFrame) onFrame(f);
    last = f.time;
  }
  m.finish(last);
  for (auto& w : m.takeFinished()) out.warnings.push_back(std::move(w));
  out.counters = m.counters();
  return out;
}

TEST(SumoFiles, FcdConventionsAreConverted) {
  const fs::path p = writeTemp("conv.fcd.xml",
                               "<fcd-export>\n"
                               "<timestep time=\"1.0\">\n"
                               "  <vehicle id=\"east\" x=\"10\" y=\"5\" angle=\"90\" type=\"car\" speed=\"20\" signals=\"2\"/>\n"
                               "  <vehicle id=\"north\" x=\"0\" y=\"0\" angle=\"0\" type=\"myTruck\" speed=\"3\" acceleration=\"-1.5\"/>\n"
                               "</timestep>\n"
                               "<timestep time=\"1.5\">\n"
                               "  <vehicle id=\"east\" x=\"20\" y=\"5.5\" angle=\"90\" type=\"car\" speed=\"20\" signals=\"1\"/>\n"
                               "</timestep>\n"
                               "</fcd-export>\n");
  VehicleTypes types;
  types["car"] = VehicleTypeInfo{VehicleClass::Passenger, 4.0, 1.8, 1400.0};
  FcdReader r(p, types);
  FcdFrame f;
  ASSERT_TRUE(r.next(f));
  EXPECT_EQ(f.time, 1.0);
  ASSERT_EQ(f.vehicles.size(), 2u);
  const VehicleState& e = f.vehicles[0];
  // navigational 90 deg (east) is math heading 0; the centre is half a length behind the bumper
  EXPECT_NEAR(e.heading, 0.0, 1e-15);
  EXPECT_NEAR(e.position.x(), 8.0, 1e-12);
  EXPECT_NEAR(e.position.y(), 5.0, 1e-12);
  EXPECT_EQ(e.mass, 1400.0);
  EXPECT_EQ(e.signals, kSignalLeft);  // SUMO bit 1 is the left blinker
  const VehicleState& n = f.vehicles[1];
  EXPECT_NEAR(n.heading, 3.14159265358979323846 / 2, 1e-15);
  EXPECT_EQ(n.vehicleClass, VehicleClass::Truck);  // guessed from the type name
  EXPECT_NEAR(n.position.y(), -6.0, 1e-12);        // 12 m truck facing north
  EXPECT_NEAR(n.position.x(), 0.0, 1e-12);
  EXPECT_EQ(n.acceleration, -1.5);
  ASSERT_TRUE(r.next(f));
  ASSERT_EQ(f.vehicles.size(), 1u);
  EXPECT_EQ(f.vehicles[0].signals, kSignalRight);
  // no posLat: SUMO reports no lateral speed (the centre's 0.5 m to the left is a lane change
  // SUMO made in one step), so none is taken from the motion; the speed is the record's
  EXPECT_EQ(f.vehicles[0].lateralSpeed, 0.0);
  EXPECT_EQ(f.vehicles[0].speed, 20.0);
  EXPECT_FALSE(r.next(f));
  fs::remove(p);
}

// The sublane model's lateral speed from posLat (FCD has no lateral speed): its change along one
// lane, or into the lane beside it on the same edge with the half widths between them, by hand
// on lanedrop.net.xml (main_1 and main_2 are 3.2 m wide, main_2 the left one).
TEST(SumoFiles, FcdLateralSpeedFromPosLat) {
  const RoadGeometry road = readSumoNet(kData / "lanedrop.net.xml");
  const fs::path p = writeTemp("poslat.fcd.xml",
                               "<fcd-export>\n"
                               "<timestep time=\"0\"><vehicle id=\"a\" x=\"100\" y=\"-0.35\" angle=\"90\" speed=\"20\" lane=\"main_2\" posLat=\"1.25\"/></timestep>\n"
                               "<timestep time=\"0.5\"><vehicle id=\"a\" x=\"110\" y=\"-3\" angle=\"91\" speed=\"20\" lane=\"main_2\" posLat=\"-1.4\"/></timestep>\n"
                               "<timestep time=\"1\"><vehicle id=\"a\" x=\"120\" y=\"-3.3\" angle=\"91\" speed=\"20\" lane=\"main_1\" posLat=\"1.5\"/></timestep>\n"
                               "<timestep time=\"1.5\"><vehicle id=\"a\" x=\"130\" y=\"-8\" angle=\"90\" speed=\"20\" lane=\"main_0\" posLat=\"0\"/></timestep>\n"
                               "<timestep time=\"2\"><vehicle id=\"a\" x=\"140\" y=\"-4.8\" angle=\"90\" speed=\"20\" lane=\"drop_0\" posLat=\"0\"/></timestep>\n"
                               "</fcd-export>\n");
  FcdReader r(p, {}, {}, &road);
  FcdFrame f;
  ASSERT_TRUE(r.next(f));
  EXPECT_EQ(f.vehicles[0].speed, 20.0);  // first frame: no lateral speed known
  ASSERT_TRUE(r.next(f));
  EXPECT_DOUBLE_EQ(f.vehicles[0].speed, std::hypot(20.0, 5.3));  // (-1.4 - 1.25) / 0.5 s
  EXPECT_EQ(f.vehicles[0].lateralSpeed, 0.0);  // folded into the speed along SUMO's angle
  ASSERT_TRUE(r.next(f));
  // from main_2 into main_1: posLat 1.5 there is 1.5 - 3.2 = -1.7 in main_2's frame, 0.3 m to
  // the right of -1.4 in 0.5 s
  EXPECT_DOUBLE_EQ(f.vehicles[0].speed, std::hypot(20.0, 0.6));
  ASSERT_TRUE(r.next(f));
  EXPECT_EQ(f.vehicles[0].speed, 20.0);  // a lane width in one step (1.5 to 0 - 3.2): a jump, none
  ASSERT_TRUE(r.next(f));
  EXPECT_EQ(f.vehicles[0].speed, 20.0);  // onto another edge: SUMO's offset is against another line
  EXPECT_FALSE(r.next(f));
  fs::remove(p);
}

TEST(SumoFiles, BadInputNamesFileAndLine) {
  FcdReader r(kData / "bad_angle.fcd.xml");
  FcdFrame f;
  try {
    r.next(f);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad_angle.fcd.xml:5:"), std::string::npos) << what;
    EXPECT_NE(what.find("angle"), std::string::npos) << what;
  }
  const fs::path trunc = writeTemp("trunc.fcd.xml", "<fcd-export>\n<timestep time=\"0\">\n<vehicle id=\"a\" x=\"1\"");
  FcdReader r2(trunc);
  EXPECT_THROW(r2.next(f), InputError);
  EXPECT_THROW(readSumoNet(kData / "missing.net.xml"), InputError);
  EXPECT_THROW(readSumoNet(kData / "lanedrop.rou.xml"), InputError);  // not a network
  fs::remove(trunc);
  // a vehicle twice in one timestep (the monitor would refuse the frame without naming the line);
  // the same id in the next timestep is fine
  const fs::path dup = writeTemp("dup.fcd.xml",
                                 "<fcd-export>\n<timestep time=\"0\">\n"
                                 "<vehicle id=\"a\" x=\"1\" y=\"0\" angle=\"90\" speed=\"1\"/>\n</timestep>\n"
                                 "<timestep time=\"1\">\n<vehicle id=\"a\" x=\"2\" y=\"0\" angle=\"90\" speed=\"1\"/>\n"
                                 "<vehicle id=\"a\" x=\"9\" y=\"0\" angle=\"90\" speed=\"1\"/>\n</timestep>\n</fcd-export>\n");
  FcdReader r3(dup);
  EXPECT_TRUE(r3.next(f));
  try {
    r3.next(f);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("dup.fcd.xml:7: vehicle 'a' appears twice"), std::string::npos) << what;
  }
  fs::remove(dup);
}

// The error a whole trace of `body` (inside <fcd-export>) gives, read to its end ("" if none).
std::string traceError(const std::string& name, const std::string& text, const FcdChecks& checks = {}) {
  const fs::path p = writeTemp(name + ".fcd.xml", text);
  std::string what;
  try {
    FcdReader r(p, {}, checks);
    FcdFrame f;
    while (r.next(f)) {
    }
  } catch (const InputError& e) {
    what = e.what();
  }
  fs::remove(p);
  const auto colon = what.find(".fcd.xml:");
  return colon == std::string::npos ? what : what.substr(colon + 9);  // "LINE: message"
}

std::string oneVehicle(const std::string& attrs, const std::string& time = "0") {
  return "<fcd-export>\n<timestep time=\"" + time + "\">\n<vehicle " + attrs + "/>\n</timestep>\n</fcd-export>\n";
}

// Trace values SUMO never writes (a time beyond any run's or not finite, a negative angle, an
// empty id, an attribute twice, a hex float, an unclosed trace) are refused naming the line
TEST(SumoFiles, TraceValuesSumoNeverWritesAreRefused) {
  const std::string rest = "x=\"1\" y=\"0\" angle=\"90\" speed=\"1\"";
  EXPECT_EQ(traceError("ok", oneVehicle("id=\"a\" " + rest)), "");
  EXPECT_EQ(traceError("ok360", oneVehicle("id=\"a\" x=\"1\" y=\"0\" angle=\"360.00\" speed=\"1\"")), "");
  for (const char* time : {"1e300", "-1e300", "1e10"})
    EXPECT_EQ(traceError("time", oneVehicle("id=\"a\" " + rest, time)),
              "2: <timestep> time " + std::string(time[0] == '-' ? "-1e+300" : time[2] == '3' ? "1e+300" : "1e+10") +
                  " s is beyond any run's (at most 1e+09 s either side of 0)");
  EXPECT_EQ(traceError("inf", oneVehicle("id=\"a\" " + rest, "inf")),
            "2: <timestep> attribute 'time' is not a finite number: 'inf'");
  EXPECT_EQ(traceError("angle", oneVehicle("id=\"a\" x=\"1\" y=\"0\" angle=\"-90\" speed=\"1\"")),
            "3: <vehicle id=\"a\"> angle -90 is not a heading (degrees, 0..360)");
  EXPECT_EQ(traceError("id", oneVehicle("id=\"\" " + rest)), "3: <vehicle> attribute 'id' is empty");
  EXPECT_EQ(traceError("twice", oneVehicle("id=\"a\" " + rest + " x=\"5\"")),
            "3: attribute 'x' of <vehicle> given twice");
  EXPECT_EQ(traceError("hex", oneVehicle("id=\"a\" x=\"0x1p3\" y=\"0\" angle=\"90\" speed=\"1\"")),
            "3: <vehicle> attribute 'x' is not a finite number: '0x1p3'");
  const std::string cut = oneVehicle("id=\"a\" " + rest);
  EXPECT_EQ(traceError("cut", cut.substr(0, cut.find("</fcd-export>"))),
            "1: <fcd-export> is not closed (no </fcd-export>: the trace is cut short)");
}

// The lanes a trace names are checked against its network even when the network has none left
TEST(SumoFiles, ATraceLaneMissingFromItsNetworkIsRefused) {
  const FcdChecks none = fcdChecksFor(RoadGeometry{}, {}, "empty.net.xml");
  EXPECT_EQ(traceError("lane", oneVehicle("id=\"a\" x=\"1\" y=\"0\" angle=\"90\" speed=\"1\" lane=\"e_0\""), none),
            "3: <vehicle id=\"a\"> lane 'e_0' is not in empty.net.xml");
}

// A network's lane at 1e300, given twice or 1e9 m wide is refused naming the line
TEST(SumoFiles, NetworkValuesNoNetworkHasAreRefused) {
  auto netError = [](const std::string& name, const std::string& lanes) {
    const fs::path p = writeTemp(name + ".net.xml", "<net>\n<edge id=\"e\">\n" + lanes + "</edge>\n</net>\n");
    std::string what;
    try {
      readSumoNet(p);
    } catch (const InputError& e) {
      what = e.what();
    }
    fs::remove(p);
    const auto colon = what.find(".net.xml:");
    return colon == std::string::npos ? what : what.substr(colon + 9);
  };
  const std::string lane0 = "<lane id=\"e_0\" index=\"0\" length=\"100\" shape=\"0,0 100,0\"/>\n";
  EXPECT_EQ(netError("ok", lane0), "");
  EXPECT_EQ(netError("far", "<lane id=\"e_0\" index=\"0\" length=\"100\" shape=\"0,0 1e300,0\"/>\n"),
            "3: <lane id=\"e_0\"> shape point (1e+300, 0) is farther than 1e+07 m from the network's origin");
  EXPECT_EQ(netError("dup", lane0 + lane0), "4: <lane id=\"e_0\"> given twice (first at line 3)");
  EXPECT_EQ(netError("wide", "<lane id=\"e_0\" index=\"0\" width=\"1e9\" length=\"100\" shape=\"0,0 100,0\"/>\n"),
            "3: <lane id=\"e_0\"> width 1e+09 m is beyond any lane's (at most 100)");
}

TEST(SumoFiles, NetworkLanes) {
  const RoadGeometry road = readSumoNet(kData / "lanedrop.net.xml");
  std::map<std::string, int> lanesOf;
  for (const Lane& l : road.lanes)
    if (!l.internal) ++lanesOf[l.edge];
  EXPECT_EQ(lanesOf["main"], 3);
  EXPECT_EQ(lanesOf["drop"], 2);
  const RoadFeatures f = deriveFeatures(road);
  ASSERT_EQ(f.sections.size(), 2u);
  int curbs = 0, markers = 0;
  for (const RoadFeature& x : f.features) (x.kind == FeatureKind::Curb ? curbs : markers)++;
  EXPECT_EQ(curbs, 4);    // both sides of both edges (straight: one segment each)
  EXPECT_EQ(markers, 3);  // 2 on main, 1 on drop
}

TEST(Trace, ShippedTraceCellsEqualAllPairsAndDistanceAdds) {
  const RoadGeometry road = readSumoNet(kData / "lanedrop.net.xml");
  const VehicleTypes types = readSumoVehicleTypes(kData / "lanedrop.rou.xml");
  ASSERT_EQ(types.size(), 2u);
  EXPECT_EQ(types.at("truck").mass, 15000.0);
  for (DetectorKind k : {DetectorKind::Concentric, DetectorKind::FiveCircle, DetectorKind::Box}) {
    std::vector<Warning> out[2];
    MonitorCounters counters[2];
    double speedTimesDt = 0.0;
    std::set<std::string> ids;
    for (int b = 0; b < 2; ++b) {
      MonitorConfig cfg;
      cfg.detector.kind = k;
      cfg.broadphase = b == 0 ? Broadphase::Cells : Broadphase::AllPairs;
      Replay run = replay(road, types, kData / "lanedrop.fcd.xml", cfg, [&](const FcdFrame& f) {
        if (b == 0)
          for (const auto& v : f.vehicles) {
            speedTimesDt += v.speed * 0.5;
            ids.insert(v.id);
          }
      });
      out[b] = std::move(run.warnings);
      counters[b] = run.counters;
    }
    ASSERT_EQ(out[0].size(), out[1].size()) << toString(k);
    for (std::size_t i = 0; i < out[0].size(); ++i) {
      EXPECT_EQ(warningCsvRow(out[0][i]), warningCsvRow(out[1][i])) << toString(k);
    }
    EXPECT_GT(out[0].size(), 10u) << toString(k);
    EXPECT_EQ(counters[0].vehiclesSeen, ids.size());
    EXPECT_GT(counters[0].handoffs, 0u);
    EXPECT_LT(counters[0].candidatePairs, counters[1].candidatePairs);
    // distance between consecutive centres against speed x step (SUMO's Euler update moves a
    // car by its new speed x step, counted here one step later: within 2%)
    EXPECT_NEAR(counters[0].vehicleMeters, speedTimesDt, 0.02 * speedTimesDt) << toString(k);
  }
}

// The front end on the shipped trace and on bad input.
int runStsim(const std::string& args, std::string* err = nullptr) {
  const fs::path errFile = fs::temp_directory_path() / ("sthighway_err_" + std::to_string(::getpid()));
  const std::string cmd = std::string(STSIM_BINARY) + " " + args + " > /dev/null 2> " + errFile.string();
  const int rc = std::system(cmd.c_str());
  if (err) *err = slurp(errFile);
  fs::remove(errFile);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// The trace generated from networks/motorway (15 s around its first rear-end collision at the
// ramp merge, t = 210-225 s, 0.5 s frames; command in tests/data/highway/README.md), replayed on
// the shipped network with the route file's vTypes: cells == all pairs (brute force), every
// detector and both motion models, with car-car, curb and lane-marker warnings present.
TEST(Trace, MotorwayTraceFromTheShippedNetworkCellsEqualAllPairs) {
  const fs::path net = fs::path(STSIM_SOURCE_DIR) / "networks/motorway";
  const RoadGeometry road = readSumoNet(net / "motorway.net.xml");
  const VehicleTypes types = readSumoVehicleTypes(net / "motorway.rou.xml");
  EXPECT_EQ(types.at("truck").mass, 20000.0);  // the vType's mass param
  for (Prediction prediction : {Prediction::Straight, Prediction::Road})
  for (MotionModel motion : {MotionModel::ConstantVelocity, MotionModel::ConstantAcceleration})
    for (DetectorKind k : {DetectorKind::Concentric, DetectorKind::FiveCircle, DetectorKind::Box}) {
      std::vector<std::string> rows[2];
      std::array<std::uint64_t, kWarningKindCount> byKind{};
      for (int b = 0; b < 2; ++b) {
        MonitorConfig cfg;
        cfg.prediction = prediction;
        cfg.detector.kind = k;
        cfg.detector.motion = motion;
        cfg.broadphase = b == 0 ? Broadphase::Cells : Broadphase::AllPairs;
        const Replay run = replay(road, types, kData / "motorway_merge.fcd.xml", cfg);
        for (const auto& w : run.warnings) rows[b].push_back(warningCsvRow(w));
        if (b == 0) byKind = run.counters.warningsByKind;
        EXPECT_EQ(run.counters.ticks, 30u);
      }
      EXPECT_EQ(rows[0], rows[1]) << toString(k) << " " << toString(prediction);
      // along the lanes the box still warns the merge's rear-end conflicts; SUMO's one-step lane
      // changes are no lateral motion there, so the markers stay quiet
      EXPECT_GT(byKind[static_cast<int>(WarningKind::Vehicle)], prediction == Prediction::Road ? 5u : 10u) << toString(k);
      if (prediction == Prediction::Road) continue;
      EXPECT_GT(byKind[static_cast<int>(WarningKind::Curb)], 0u) << toString(k);
      // straight on too: a trace without posLat has no lateral speed, as SUMO reports none for
      // its one-step lane changes (the live run's reading); the markers once warned of those
      // jumps taken as 7-20 m/s of lateral motion
      EXPECT_EQ(byKind[static_cast<int>(WarningKind::LaneMarker)], 0u) << toString(k);
    }
}

TEST(Cli, TraceModeWritesWarningsAndSummary) {
  const fs::path out = fs::temp_directory_path() / ("sthighway_cli_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string base = "highway --fcd " + (kData / "lanedrop.fcd.xml").string() + " --net " +
                           (kData / "lanedrop.net.xml").string() + " --vtypes " + (kData / "lanedrop.rou.xml").string();
  ASSERT_EQ(runStsim(base + " --detector box --out " + out.string()), 0);
  const std::string csv = slurp(out / "warnings.csv");
  const std::string json = slurp(out / "summary.json");
  const long rows = std::count(csv.begin(), csv.end(), '\n') - 1;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(json, m, std::regex("\"total\": ([0-9]+)")));
  EXPECT_EQ(std::stol(m[1]), rows);
  EXPECT_GT(rows, 0);
  EXPECT_NE(json.find("\"detector\": \"box\""), std::string::npos);
  EXPECT_NE(json.find("\"vehicle_km\""), std::string::npos);
  EXPECT_NE(json.find("\"handoffs\""), std::string::npos);
  // usage errors exit 2, bad input exits 1 with one line naming file and line, results flushed
  std::string err;
  EXPECT_EQ(runStsim(base + " --detector circle", &err), 2);
  EXPECT_EQ(runStsim("highway --fcd x.xml", &err), 2);
  fs::remove_all(out);
  EXPECT_EQ(runStsim("highway --fcd " + (kData / "bad_angle.fcd.xml").string() + " --net " +
                         (kData / "lanedrop.net.xml").string() + " --out " + out.string(),
                     &err),
            1);
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("bad_angle.fcd.xml:5:"), std::string::npos) << err;
  EXPECT_TRUE(fs::exists(out / "warnings.csv"));
  EXPECT_NE(slurp(out / "summary.json").find("\"error\""), std::string::npos);
  EXPECT_EQ(runStsim("highway --fcd " + (kData / "nope.fcd.xml").string() + " --net " + (kData / "lanedrop.net.xml").string() +
                         " --out " + out.string(),
                     &err),
            1);
  EXPECT_NE(err.find("nope.fcd.xml"), std::string::npos) << err;
  fs::remove_all(out);
}

// The conflict columns and map from the front end: summary.json's by_type adds up to the total,
// the map is drawn (or skipped with --no-map), and the trace's lanes reach warnings.csv.
TEST(Cli, TraceModeCountsTypesAndDrawsTheMap) {
  const fs::path out = fs::temp_directory_path() / ("sthighway_cli_map_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string base = "highway --fcd " + (kData / "motorway_merge.fcd.xml").string() + " --net " +
                           (fs::path(STSIM_SOURCE_DIR) / "networks/motorway/motorway.net.xml").string() + " --vtypes " +
                           (fs::path(STSIM_SOURCE_DIR) / "networks/motorway/motorway.rou.xml").string() +
                           " --prediction straight";  // road warnings of the straight line (this trace has none along its lanes)
  ASSERT_EQ(runStsim(base + " --no-map --out " + out.string()), 0);
  EXPECT_FALSE(fs::exists(out / "conflict_map.png"));
  const std::string json = slurp(out / "summary.json");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(json, m, std::regex("\"total\": ([0-9]+)")));
  const long total = std::stol(m[1]);
  // SSAM's three types and the pedestrian's (none on a motorway trace), then apart proximity (zones
  // only, no collision course) and road
  ASSERT_TRUE(std::regex_search(json, m, std::regex("\"conflicts\": ([0-9]+),\\s*\"by_type\": \\{\"rear_end\": ([0-9]+), "
                                                    "\"lane_change\": ([0-9]+), \"crossing\": ([0-9]+), "
                                                    "\"pedestrian\": ([0-9]+), \"proximity\": ([0-9]+), \"road\": ([0-9]+)\\}")))
      << json;
  EXPECT_EQ(std::stol(m[2]) + std::stol(m[3]) + std::stol(m[4]) + std::stol(m[5]) + std::stol(m[6]) + std::stol(m[7]), total);
  EXPECT_EQ(std::stol(m[1]), std::stol(m[2]) + std::stol(m[3]) + std::stol(m[4]) + std::stol(m[5]));
  EXPECT_EQ(std::stol(m[5]), 0);
  EXPECT_GT(std::stol(m[2]), 0);
  EXPECT_GT(std::stol(m[7]), 0);
  // every row names the ego's lane (the trace has lane attributes, the net those lanes)
  std::istringstream csv(slurp(out / "warnings.csv"));
  std::string line;
  std::getline(csv, line);
  long rows = 0, laned = 0;
  while (std::getline(csv, line)) {
    ++rows;
    laned += std::regex_search(line, std::regex(",[a-zA-Z:][A-Za-z_0-9]*_[0-9]+,"));
  }
  EXPECT_EQ(rows, total);
  EXPECT_GT(laned, rows / 2);
  if (std::system("/usr/bin/python3 -c 'import matplotlib' > /dev/null 2>&1") == 0) {
    ASSERT_EQ(runStsim(base + " --out " + out.string()), 0);
    EXPECT_TRUE(fs::exists(out / "conflict_map.png"));
    EXPECT_TRUE(fs::exists(out / "conflict_map.svg"));
  }
  std::string err;
  EXPECT_EQ(runStsim(base + " --rear-end-below 50 --crossing-above 40 --out " + out.string(), &err), 2);
  fs::remove_all(out);
}

}  // namespace
}  // namespace st::highway
