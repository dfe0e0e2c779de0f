// The two backends against each other on the same scenario and seed: identical vehicle states every
// step and identical warnings; attaching to a running SUMO as the second of two TraCI clients.
#include <gtest/gtest.h>

#include <libsumo/libtraci.h>

#include <set>

#include <thread>

#include "sumo_process.hpp"
#include "test_util.hpp"
#include <sthighway/report.hpp>
#include <stcosim/backend.hpp>
#include <stcosim/plugin.hpp>
#include <stcosim/scenario.hpp>

namespace st::cosim {
namespace {

using namespace st::cosim::test;

struct Recorded {
  std::vector<std::vector<SumoVehicle>> steps;
  std::vector<std::string> warnings;  // CSV rows
  std::uint64_t departed = 0, arrived = 0;
};

Scenario shortMotorway(double end) {
  Scenario s = loadScenario(motorway());
  s.end = end;
  return s;
}

Recorded run(Backend& b, const Scenario& s) {
  Recorded r;
  HighwayPlugin plugin(b, s.plugin);
  while (b.running()) {
    b.step();
    plugin.update();
    r.steps.push_back(b.vehicles());
    for (const auto& w : plugin.takeFinished()) r.warnings.push_back(highway::warningCsvRow(w));
  }
  plugin.finish();
  for (const auto& w : plugin.takeFinished()) r.warnings.push_back(highway::warningCsvRow(w));
  r.departed = plugin.counters().departed;
  r.arrived = plugin.counters().arrived;
  b.close();
  return r;
}

void expectSameStates(const Recorded& a, const Recorded& b) {
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (std::size_t k = 0; k < a.steps.size(); ++k) {
    ASSERT_EQ(a.steps[k].size(), b.steps[k].size()) << "step " << k;
    for (std::size_t i = 0; i < a.steps[k].size(); ++i) {
      const SumoVehicle& x = a.steps[k][i];
      const SumoVehicle& y = b.steps[k][i];
      ASSERT_EQ(x.id, y.id) << "step " << k;
      // TraCI sends doubles as 8 bytes: bit-identical values
      EXPECT_EQ(x.x, y.x);
      EXPECT_EQ(x.y, y.y);
      EXPECT_EQ(x.angle, y.angle);
      EXPECT_EQ(x.speed, y.speed);
      EXPECT_EQ(x.lateralSpeed, y.lateralSpeed);
      EXPECT_EQ(x.acceleration, y.acceleration);
      EXPECT_EQ(x.signals, y.signals);
      EXPECT_EQ(x.type, y.type);
    }
  }
}

TEST(Backends, LibsumoAndLibtraciGiveIdenticalStatesAndWarnings) {
  const Scenario s = shortMotorway(90.0);
  const SumoLaunch launch{sumoArguments(s), false, "", ""};
  auto a = startLibsumo(launch);
  EXPECT_DOUBLE_EQ(a->deltaT(), 0.1);
  const Recorded viaLibsumo = run(*a, s);
  auto b = launchTraci(launch);
  const Recorded viaTraci = run(*b, s);

  // the run is not trivial: vehicles came and went, warnings were raised
  EXPECT_EQ(viaLibsumo.steps.size(), 900u);
  EXPECT_GT(viaLibsumo.departed, 100u);
  EXPECT_GT(viaLibsumo.arrived, 0u);  // 3 km at ~33 m/s: the first arrive after ~85 s
  EXPECT_GT(viaLibsumo.warnings.size(), 50u);
  expectSameStates(viaLibsumo, viaTraci);
  EXPECT_EQ(viaLibsumo.warnings, viaTraci.warnings);
}

// The sublane model: lateral speeds and blinkers are non-zero here, and must agree as well.
TEST(Backends, LibsumoAndLibtraciAgreeOnTheSublaneModel) {
  Scenario s = loadScenario(sourceDir() / "networks/sublane/scenario.yaml");
  s.end = 60.0;
  const SumoLaunch launch{sumoArguments(s), false, "", ""};
  auto a = startLibsumo(launch);
  const Recorded viaLibsumo = run(*a, s);
  auto b = launchTraci(launch);
  const Recorded viaTraci = run(*b, s);
  std::size_t lateral = 0, blinking = 0;
  for (const auto& step : viaLibsumo.steps)
    for (const auto& v : step) {
      lateral += v.lateralSpeed != 0.0;
      blinking += (v.signals & (kSumoBlinkerLeft | kSumoBlinkerRight)) != 0;
    }
  EXPECT_GT(lateral, 1000u);
  EXPECT_GT(blinking, 100u);
  expectSameStates(viaLibsumo, viaTraci);
  EXPECT_EQ(viaLibsumo.warnings, viaTraci.warnings);
}

TEST(Backends, VehicleTypesCarryMassParamAndClass) {
  const Scenario s = shortMotorway(5.0);
  auto b = startLibsumo(SumoLaunch{sumoArguments(s), false, "", ""});
  const SumoVehicleType& truck = b->vehicleType("truck");
  EXPECT_EQ(truck.vClass, "truck");
  EXPECT_DOUBLE_EQ(truck.length, 12.0);
  EXPECT_DOUBLE_EQ(truck.width, 2.55);
  ASSERT_TRUE(truck.mass.has_value());
  EXPECT_DOUBLE_EQ(*truck.mass, 20000.0);
  // lanes from the network: 3 + 1 + 4 + 3 normal lanes, widths 3.75 m
  int normal = 0;
  for (const auto& l : b->lanes())
    if (!l.internal) {
      ++normal;
      EXPECT_DOUBLE_EQ(l.width, 3.75) << l.id;
      EXPECT_GE(l.shape.size(), 2u);
    }
  EXPECT_EQ(normal, 11);
  b->close();
}

TEST(Backends, TraciLaunchOfBrokenConfigNamesTheProblem) {
  const auto dir = freshDir("broken_launch");
  std::ofstream(dir / "bad.sumocfg") << "<configuration><input><net-file value=\"nope.net.xml\"/></input></configuration>";
  try {
    launchTraci(SumoLaunch{{"-c", (dir / "bad.sumocfg").string()}, false, (dir / "sumo.log").string(), ""});
    FAIL() << "expected SumoError";
  } catch (const SumoError& e) {
    EXPECT_NE(std::string(e.what()).find("nope.net.xml"), std::string::npos) << e.what();
  }
}

// The C++ API for users who drive SUMO themselves: the caller steps libsumo, the plugin reads,
// warns and colours. Checked through SUMO itself: the colour SUMO reports for each alerted car.
TEST(Plugin, UserDrivenLibsumoGetsWarningsAndColours) {
  const Scenario s = shortMotorway(60.0);
  auto sumo = startLibsumo(SumoLaunch{sumoArguments(s), false, "", ""});  // stands in for the user's start()
  auto plugin = HighwayPlugin::forLibsumo(s.plugin);
  std::size_t warnings = 0, checked = 0;
  while (sumo->running()) {
    sumo->step();     // the user's Simulation::step()
    plugin->step();   // reads the state SUMO is in
    warnings += plugin->takeFinished().size();
    for (const auto& al : plugin->alerts()) {
      const std::string& id = plugin->states()[static_cast<std::size_t>(al.vehicle)].id;
      const Rgba c = plugin->backend().color(id);
      const bool red = al.ttc < 0.5 * al.safeTime;
      const Rgba want = red ? s.plugin.actions.dangerColor : s.plugin.actions.warningColor;
      EXPECT_EQ(c.r, want.r) << id;
      EXPECT_EQ(c.g, want.g) << id;
      EXPECT_EQ(c.b, want.b) << id;
      ++checked;
    }
  }
  // a car whose warnings are over has its own colour back (grey cars, blue trucks)
  std::set<std::string> alerted;
  for (const auto& al : plugin->alerts()) alerted.insert(plugin->states()[static_cast<std::size_t>(al.vehicle)].id);
  for (const auto& v : plugin->states()) {
    if (alerted.count(v.id)) continue;
    const Rgba c = plugin->backend().color(v.id);
    EXPECT_FALSE(c.r == 255 && c.b == 0) << v.id << " still coloured";
    EXPECT_EQ(c.r, c.g) << v.id;  // grey cars (179, 179, 179) and blue trucks (77, 77, 204)
  }
  plugin->finish();
  warnings += plugin->takeFinished().size();
  EXPECT_GT(warnings, 20u);
  EXPECT_GT(checked, 100u);
  EXPECT_GT(plugin->counters().colorChanges, 0u);
  sumo->close();
}

// --gui draws the cells as polygons; checked through libtraci on a launched SUMO: SUMO holds one
// polygon per cell with the cell's extent.
TEST(Plugin, DrawsCellBoundariesAsPolygonsInSumo) {
  const Scenario s = shortMotorway(1.0);
  auto b = launchTraci(SumoLaunch{sumoArguments(s), false, "", ""});
  HighwayPlugin plugin(*b, s.plugin);
  const int n = plugin.drawCells();
  const auto& cells = plugin.monitor().cells();
  EXPECT_EQ(n, cells.cellCount());
  EXPECT_GE(n, 15);  // 3 km of motorway + ramp at 200 m per cell
  const auto ids = libtraci::Polygon::getIDList();
  EXPECT_EQ(static_cast<int>(ids.size()), n);
  const auto shape = libtraci::Polygon::getShape("stsim_cell_3").value;
  const Aabb<2> box = cells.cellExtent(3);
  ASSERT_EQ(shape.size(), 5u);
  EXPECT_DOUBLE_EQ(shape[0].x, box.min.x());
  EXPECT_DOUBLE_EQ(shape[0].y, box.min.y());
  EXPECT_DOUBLE_EQ(shape[2].x, box.max.x());
  EXPECT_DOUBLE_EQ(shape[2].y, box.max.y());
  b->close();
}

// stsim attaches as client 2 of a SUMO serving two clients; this test is client 1 and drives the
// simulation. Since client 1 only steps, stsim's warnings equal those of an embedded libsumo run.
TEST(Backends, AttachesToRunningSumoAsSecondClient) {
  const auto dir = freshDir("second_client");
  const double end = 60.0;
  const auto reference = runStsim({"highway", motorway().string(), "--end", "60", "--out", (dir / "ref").string()},
                                  dir);
  ASSERT_EQ(reference.code, 0) << reference.err;

  Scenario s = shortMotorway(end);
  std::vector<std::string> args = sumoArguments(s);
  args.insert(args.end(), {"--num-clients", "2"});
  detail::SumoProcess sumo("sumo", args, (dir / "sumo.log").string());
  const std::string where = "localhost:" + std::to_string(sumo.port()) + ":2";
  StsimProcess attached({"highway", motorway().string(), "--end", "60", "--traci", where, "--out",
                         (dir / "attached").string()},
                        dir);

  libtraci::Simulation::init(sumo.port(), 30, "localhost", "test-client-1");
  libtraci::Simulation::setOrder(1);
  int steps = 0;
  while (libtraci::Simulation::getTime() < end - 0.05) {
    libtraci::Simulation::step();
    ++steps;
  }
  libtraci::Simulation::close();
  EXPECT_EQ(steps, 600);
  EXPECT_EQ(attached.wait(), 0) << attached.err();
  sumo.stop(10.0);

  const std::string summary = slurp(dir / "attached/summary.json");
  EXPECT_NE(jsonString(summary, "backend").find("client order 2"), std::string::npos) << summary;
  const std::string a = slurp(dir / "attached/warnings.csv");
  EXPECT_GT(lines(a).size(), 20u);
  EXPECT_EQ(a, slurp(dir / "ref/warnings.csv"));
}

// SUMO dies mid-run: stsim reports the lost connection in one line, exits non-zero and leaves a
// valid warnings.csv with the warnings up to that point and a summary saying why it stopped.
TEST(Backends, DroppedConnectionGivesClearErrorAndValidOutputs) {
  const auto dir = freshDir("dropped");
  Scenario s = shortMotorway(420.0);
  detail::SumoProcess sumo("sumo", sumoArguments(s), (dir / "sumo.log").string());
  StsimProcess attached({"highway", motorway().string(), "--traci", "localhost:" + std::to_string(sumo.port()),
                         "--out", (dir / "out").string()},
                        dir);
  // let it run until it has written some simulated time, then kill SUMO
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  ::kill(sumo.pid(), SIGKILL);
  const int code = attached.wait();
  sumo.stop(0.0);
  EXPECT_EQ(code, 1);
  const auto errLines = lines(attached.err());
  ASSERT_EQ(errLines.size(), 1u) << attached.err();
  EXPECT_NE(errLines[0].find("TraCI connection to localhost:"), std::string::npos) << errLines[0];
  EXPECT_NE(errLines[0].find("lost at t = "), std::string::npos) << errLines[0];
  std::size_t rows = 0;
  EXPECT_TRUE(validWarningsCsv(dir / "out/warnings.csv", &rows));
  EXPECT_GT(rows, 0u);
  const std::string summary = slurp(dir / "out/summary.json");
  EXPECT_EQ(jsonString(summary, "stop_reason"), "error");
  const double simulated = jsonNumber(summary, "simulated_s");
  EXPECT_GT(simulated, 0.0);
  EXPECT_LT(simulated, 420.0);
}

}  // namespace
}  // namespace st::cosim
