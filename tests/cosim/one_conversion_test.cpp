// One conversion from SUMO's records to the highway model's states (sthighway/sumo_conversion.hpp),
// whatever the source. The same records (tests/data/highway/one_conversion.csv) go through the live
// path (the backend's SumoVehicle and the vTypes as SUMO itself reports them) and through an FCD
// trace read by FcdReader with the vType file: identical states, field by field and bit for bit,
// and identical warnings. Python's step_sumo takes the same records in
// tests/python/test_one_conversion.py.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "test_util.hpp"
#include <sthighway/monitor.hpp>
#include <sthighway/report.hpp>
#include <sthighway/sumo_files.hpp>
#include <stcosim/backend.hpp>
#include <stcosim/conversions.hpp>

namespace st::cosim {
namespace {

using namespace st::cosim::test;
namespace fs = std::filesystem;

const fs::path kData = sourceDir() / "tests/data/highway";

struct Record {
  double time = 0.0;
  std::string id, type, lane;
  SumoVehicle v;
  std::vector<std::string> fields;  // the CSV row as written: the FCD repeats its numbers exactly
};

std::vector<Record> readRecords() {
  std::ifstream in(kData / "one_conversion.csv");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "time,id,type,lane,x,y,angle,speed,lateral_speed,pos_lat,acceleration,signals");
  std::vector<Record> out;
  while (std::getline(in, line)) {
    const auto f = splitCsv(line);
    if (f.size() != 12) {
      ADD_FAILURE() << line;
      continue;
    }
    Record r;
    r.time = std::stod(f[0]);
    r.id = f[1];
    r.type = f[2];
    r.lane = f[3];
    r.v.id = f[1];
    r.v.x = std::stod(f[4]);
    r.v.y = std::stod(f[5]);
    r.v.angle = std::stod(f[6]);
    r.v.speed = std::stod(f[7]);
    r.v.lateralSpeed = std::stod(f[8]);
    r.fields = f;
    r.v.acceleration = std::stod(f[10]);
    r.v.signals = std::stoi(f[11]);
    out.push_back(r);
  }
  return out;
}

// The records as SUMO's FCD output writes them (the attributes sumo --fcd-output writes with
// --fcd-output.signals/.acceleration and the sublane model's posLat), numbers exactly as given.
fs::path writeFcd(const std::vector<Record>& records, const fs::path& dir) {
  const fs::path p = dir / "one_conversion.fcd.xml";
  std::ofstream out(p);
  out << "<fcd-export>\n";
  double time = -1.0;
  for (const Record& r : records) {
    const auto& f = r.fields;
    if (r.time != time) {
      if (time >= 0.0) out << "  </timestep>\n";
      out << "  <timestep time=\"" << f[0] << "\">\n";
      time = r.time;
    }
    out << "    <vehicle id=\"" << f[1] << "\" x=\"" << f[4] << "\" y=\"" << f[5] << "\" angle=\"" << f[6] << "\" type=\""
        << f[2] << "\" speed=\"" << f[7] << "\" posLat=\"" << f[9] << "\" lane=\"" << f[3] << "\" signals=\"" << f[11]
        << "\" acceleration=\"" << f[10] << "\"/>\n";
  }
  out << "  </timestep>\n</fcd-export>\n";
  return p;
}

// The vTypes as SUMO reports them live (libsumo here; the backends agree, backend_test.cpp).
std::map<std::string, SumoVehicleType> typesFromSumo() {
  SumoLaunch launch;
  launch.args = {"--net-file", (kData / "lanedrop.net.xml").string(), "--route-files",
                 (kData / "one_conversion.rou.xml").string(), "--end", "1", "--no-step-log", "true"};
  auto b = startLibsumo(launch);
  std::map<std::string, SumoVehicleType> out;
  for (const char* id : {"car", "anon", "trailer", "bike"}) out[id] = b->vehicleType(id);
  b->close();
  return out;
}

void expectSameState(const highway::VehicleState& a, const highway::VehicleState& b, const std::string& where) {
  EXPECT_EQ(a.id, b.id) << where;
  EXPECT_EQ(a.vehicleClass, b.vehicleClass) << where;
  EXPECT_EQ(a.length, b.length) << where;
  EXPECT_EQ(a.width, b.width) << where;
  EXPECT_EQ(a.mass, b.mass) << where;
  EXPECT_EQ(a.decel, b.decel) << where;
  EXPECT_EQ(a.position.x(), b.position.x()) << where;
  EXPECT_EQ(a.position.y(), b.position.y()) << where;
  EXPECT_EQ(a.heading, b.heading) << where;
  EXPECT_EQ(a.speed, b.speed) << where;
  EXPECT_EQ(a.lateralSpeed, b.lateralSpeed) << where;
  EXPECT_EQ(a.acceleration, b.acceleration) << where;
  EXPECT_EQ(a.signals, b.signals) << where;
  EXPECT_EQ(a.lane, b.lane) << where;
  EXPECT_EQ(a.handle, b.handle) << where;
}

TEST(OneConversion, AVTypeFileGivesTheTypesSumoReportsLive) {
  const auto live = typesFromSumo();
  const auto file = highway::readSumoVehicleTypes(kData / "one_conversion.rou.xml");
  ASSERT_EQ(file.size(), live.size());
  for (const auto& [id, sumo] : live) {
    const VehicleTypeInfo a = toVehicleTypeInfo(sumo);
    const VehicleTypeInfo& b = file.at(id);
    EXPECT_EQ(a.vehicleClass, b.vehicleClass) << id;
    EXPECT_EQ(a.length, b.length) << id;
    EXPECT_EQ(a.width, b.width) << id;
    EXPECT_EQ(a.mass, b.mass) << id;
    EXPECT_EQ(a.decel, b.decel) << id;
  }
  // the attributes the file leaves out are SUMO's own defaults for the class
  EXPECT_EQ(live.at("anon").vClass, "passenger");
  EXPECT_EQ(live.at("anon").length, 4.3);
  EXPECT_EQ(live.at("trailer").length, 16.5);
  EXPECT_EQ(live.at("bike").decel, 3.0);
  EXPECT_EQ(toVehicleTypeInfo(live.at("trailer")).mass, 30000.0);
}

TEST(OneConversion, LiveRecordsAndTheirFcdGiveIdenticalStatesAndWarnings) {
  const auto dir = freshDir("one_conversion");
  const auto records = readRecords();
  ASSERT_EQ(records.size(), 326u);
  const auto sumoTypes = typesFromSumo();
  const highway::RoadGeometry road = highway::readSumoNet(kData / "lanedrop.net.xml");
  std::map<std::string, int> laneIndex;
  for (std::size_t i = 0; i < road.lanes.size(); ++i) laneIndex[road.lanes[i].id] = static_cast<int>(i);

  // the live path: the backend's records (serial in order of first appearance, as the backends
  // number them), converted by the plugin's call
  std::vector<highway::FcdFrame> live;
  std::map<std::string, std::uint32_t> serial;
  for (const Record& r : records) {
    if (live.empty() || live.back().time != r.time) live.push_back({r.time, {}});
    SumoVehicle v = r.v;
    v.serial = serial.emplace(r.id, static_cast<std::uint32_t>(serial.size())).first->second;
    highway::VehicleState s;
    toVehicleState(v, toVehicleTypeInfo(sumoTypes.at(r.type)), s);
    s.lane = laneIndex.at(r.lane);
    live.back().vehicles.push_back(s);
  }
  // the trace path
  std::vector<highway::FcdFrame> trace;
  highway::FcdReader reader(writeFcd(records, dir), highway::readSumoVehicleTypes(kData / "one_conversion.rou.xml"), {},
                            &road);
  for (highway::FcdFrame f; reader.next(f);) trace.push_back(f);

  ASSERT_EQ(live.size(), trace.size());
  int lateral = 0, signalled = 0;
  for (std::size_t k = 0; k < live.size(); ++k) {
    ASSERT_EQ(live[k].time, trace[k].time);
    ASSERT_EQ(live[k].vehicles.size(), trace[k].vehicles.size()) << live[k].time;
    for (std::size_t i = 0; i < live[k].vehicles.size(); ++i) {
      const auto& a = live[k].vehicles[i];
      expectSameState(a, trace[k].vehicles[i], a.id + " at t = " + std::to_string(live[k].time));
      lateral += a.id == "drift" && a.speed > 25.0;
      signalled += a.signals != 0;
    }
  }
  EXPECT_EQ(lateral, 5);     // the drift's five steps: |v| = hypot(25, 0.5)
  EXPECT_GT(signalled, 10);  // blinkers (not the brake light, not the hazard lights)

  auto warnings = [&](const std::vector<highway::FcdFrame>& frames, highway::DetectorKind kind, highway::MotionModel motion) {
    highway::MonitorConfig cfg;
    cfg.detector.kind = kind;
    cfg.detector.motion = motion;
    highway::HighwayMonitor m(road, cfg);
    std::vector<std::string> rows;
    for (const auto& f : frames) {
      m.step(f.time, f.vehicles);
      for (const auto& w : m.takeFinished()) rows.push_back(highway::warningCsvRow(w));
    }
    m.finish(frames.back().time);
    for (const auto& w : m.takeFinished()) rows.push_back(highway::warningCsvRow(w));
    return rows;
  };
  using highway::DetectorKind, highway::MotionModel;
  // five circles at constant velocity: the closing follower, the drift beside the leader, the
  // trailer behind its three foes, the drift's lane marker
  const auto a = warnings(live, DetectorKind::FiveCircle, MotionModel::ConstantVelocity);
  EXPECT_GE(a.size(), 7u);
  EXPECT_EQ(a, warnings(trace, DetectorKind::FiveCircle, MotionModel::ConstantVelocity));
  // the box with each car's acceleration (the follower's braking keeps it clear of the leader)
  const auto b = warnings(live, DetectorKind::Box, MotionModel::ConstantAcceleration);
  EXPECT_GE(b.size(), 2u);
  EXPECT_EQ(b, warnings(trace, DetectorKind::Box, MotionModel::ConstantAcceleration));
}

}  // namespace
}  // namespace st::cosim
