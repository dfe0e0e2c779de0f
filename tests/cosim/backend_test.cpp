// The two backends against each other on the same scenario and seed: identical vehicle states every
// step and identical warnings; attaching to a running SUMO as the second of two TraCI clients.
#include <gtest/gtest.h>

#include <libsumo/libtraci.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <atomic>
#include <random>
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
  std::vector<std::vector<SumoVehicle>> personSteps;
  std::vector<std::string> warnings;  // CSV rows
  std::uint64_t departed = 0, arrived = 0, teleports = 0;
};

Scenario shortMotorway(double end) {
  Scenario s = loadScenario(motorway());
  s.end = end;
  return s;
}

// The plugin reads only what its configuration needs; allReads = true reads every variable anyway,
// so the backends are compared on all of them.
Recorded run(Backend& b, const Scenario& s, bool allReads = true) {
  Recorded r;
  HighwayPlugin plugin(b, s.plugin);
  if (allReads) b.setReads(VehicleReads{});
  while (b.running()) {
    b.step();
    plugin.update();
    r.steps.push_back(b.vehicles());
    r.personSteps.push_back(b.persons());
    for (const auto& w : plugin.takeFinished()) r.warnings.push_back(highway::warningCsvRow(w));
  }
  plugin.finish();
  for (const auto& w : plugin.takeFinished()) r.warnings.push_back(highway::warningCsvRow(w));
  r.departed = plugin.counters().departed;
  r.arrived = plugin.counters().arrived;
  r.teleports = plugin.counters().teleports;
  b.close();
  return r;
}

void expectSameRecords(const std::vector<std::vector<SumoVehicle>>& as, const std::vector<std::vector<SumoVehicle>>& bs) {
  ASSERT_EQ(as.size(), bs.size());
  for (std::size_t k = 0; k < as.size(); ++k) {
    ASSERT_EQ(as[k].size(), bs[k].size()) << "step " << k;
    for (std::size_t i = 0; i < as[k].size(); ++i) {
      const SumoVehicle& x = as[k][i];
      const SumoVehicle& y = bs[k][i];
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
      EXPECT_EQ(x.typeIndex, y.typeIndex);
      EXPECT_EQ(x.serial, y.serial);
      EXPECT_EQ(x.routeIndex, y.routeIndex);
      EXPECT_EQ(x.routeId, y.routeId);
      EXPECT_EQ(x.route, y.route);
      EXPECT_EQ(x.nextSignal, y.nextSignal);
      EXPECT_EQ(x.nextSignalDistance, y.nextSignalDistance);
    }
  }
}

// the vehicles and the persons on foot, step by step
void expectSameStates(const Recorded& a, const Recorded& b) {
  expectSameRecords(a.steps, b.steps);
  expectSameRecords(a.personSteps, b.personSteps);
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

// The plugin asks the backend for acceleration only with the constant-acceleration motion model
// and for blinkers only when it checks the road (lane markers); leaving them out changes no
// warning, and what is left out is 0.
TEST(Plugin, ReadsOnlyWhatItsConfigurationNeedsWithTheSameWarnings) {
  Scenario s = shortMotorway(90.0);
  const SumoLaunch launch{sumoArguments(s), false, "", ""};
  auto a = startLibsumo(launch);
  const Recorded all = run(*a, s);
  ASSERT_TRUE(a->reads().acceleration && a->reads().signals);
  auto b = startLibsumo(launch);
  const Recorded narrowed = run(*b, s, false);
  EXPECT_FALSE(b->reads().acceleration);  // the motorway scenario predicts with constant velocity
  EXPECT_TRUE(b->reads().signals);
  ASSERT_EQ(all.steps.size(), narrowed.steps.size());
  std::size_t accelerating = 0, blinking = 0;
  for (std::size_t k = 0; k < all.steps.size(); ++k) {
    ASSERT_EQ(all.steps[k].size(), narrowed.steps[k].size());
    for (std::size_t i = 0; i < all.steps[k].size(); ++i) {
      const SumoVehicle& x = all.steps[k][i];
      const SumoVehicle& y = narrowed.steps[k][i];
      ASSERT_EQ(x.id, y.id);
      EXPECT_EQ(x.x, y.x);
      EXPECT_EQ(x.angle, y.angle);
      EXPECT_EQ(x.speed, y.speed);
      EXPECT_EQ(x.signals, y.signals);
      EXPECT_EQ(y.acceleration, 0.0);
      accelerating += x.acceleration != 0.0;
      blinking += x.signals != 0;
    }
  }
  EXPECT_GT(accelerating, 1000u);  // so leaving acceleration out was tested
  EXPECT_GT(blinking, 0u);
  EXPECT_GT(all.warnings.size(), 50u);
  EXPECT_EQ(all.warnings, narrowed.warnings);

  // the other configurations ask for what they use
  s.plugin.monitor.detector.motion = highway::MotionModel::ConstantAcceleration;
  s.plugin.monitor.checkRoad = false;
  auto c = startLibsumo(launch);
  HighwayPlugin plugin(*c, s.plugin);
  EXPECT_TRUE(c->reads().acceleration);
  EXPECT_FALSE(c->reads().signals);
  c->close();
}

// A shipped scenario's first `end` seconds through libsumo, then libtraci: identical states and
// warnings; the libsumo run for the caller's own checks.
Recorded agreeOn(const std::string& network, double end) {
  Scenario s = loadScenario(sourceDir() / "networks" / network / "scenario.yaml");
  s.end = end;
  const SumoLaunch launch{sumoArguments(s), false, "", ""};
  auto a = startLibsumo(launch);
  Recorded viaLibsumo = run(*a, s);
  auto b = launchTraci(launch);
  const Recorded viaTraci = run(*b, s);
  expectSameStates(viaLibsumo, viaTraci);
  EXPECT_EQ(viaLibsumo.warnings, viaTraci.warnings);
  return viaLibsumo;
}

// The sublane model: lateral speeds and blinkers are non-zero here, and must agree as well.
TEST(Backends, LibsumoAndLibtraciAgreeOnTheSublaneModel) {
  const Recorded viaLibsumo = agreeOn("sublane", 60.0);
  std::size_t lateral = 0, blinking = 0;
  for (const auto& step : viaLibsumo.steps)
    for (const auto& v : step) {
      lateral += v.lateralSpeed != 0.0;
      blinking += (v.signals & (kSumoBlinkerLeft | kSumoBlinkerRight)) != 0;
    }
  EXPECT_GT(lateral, 1000u);
  EXPECT_GT(blinking, 100u);
}

// A traffic light: each car's next light (state and distance to its stop line) read the same way
// by both, and every state a light shows met (red, yellow, green) with a stop line ahead.
TEST(Backends, LibsumoAndLibtraciAgreeOnTrafficLights) {
  const Recorded viaLibsumo = agreeOn("intersection", 120.0);
  std::set<char> states;
  for (const auto& step : viaLibsumo.steps)
    for (const auto& v : step)
      if (v.nextSignal) {
        states.insert(v.nextSignal);
        EXPECT_GE(v.nextSignalDistance, 0.0);
        EXPECT_LE(v.nextSignalDistance, 200.0);  // the arms' length
      }
  // red, yellow, green, and m: a left turner on its minor green gives way at its wait point
  EXPECT_TRUE(states.count('r') && states.count('y') && states.count('G') && states.count('m'));
}

// Persons on foot (the crosswalk network: 12 flows of walkers): the same persons in the same order
// with the same records through both, and riders none of them.
TEST(Backends, LibsumoAndLibtraciAgreeOnPersons) {
  const Recorded viaLibsumo = agreeOn("crosswalk", 120.0);
  std::size_t seen = 0, walking = 0;
  for (const auto& step : viaLibsumo.personSteps)
    for (const auto& p : step) {
      ++seen;
      walking += p.speed > 0.5;
      EXPECT_EQ(p.signals, 0);
      EXPECT_TRUE(p.route.empty());
    }
  EXPECT_GT(seen, 5000u);
  EXPECT_GT(walking, 2000u);
}

// A teleport (a ramp car stuck for 1 s, t = 112.7 s, starting and ending in one step) goes
// through both backends' event lists the same way: identical states and warnings.
TEST(Backends, LibsumoAndLibtraciAgreeThroughTeleports) {
  Scenario s = shortMotorway(130.0);
  s.collisionAction = "teleport";
  s.sumoArgs.insert(s.sumoArgs.end(), {"--time-to-teleport", "1"});
  const SumoLaunch launch{sumoArguments(s), false, "", ""};
  auto a = startLibsumo(launch);
  const Recorded viaLibsumo = run(*a, s);
  auto b = launchTraci(launch);
  const Recorded viaTraci = run(*b, s);
  EXPECT_GT(viaLibsumo.teleports, 0u);
  EXPECT_EQ(viaLibsumo.teleports, viaTraci.teleports);
  expectSameStates(viaLibsumo, viaTraci);
  EXPECT_EQ(viaLibsumo.warnings, viaTraci.warnings);
}

// Over TraCI each vehicle is subscribed to just the variables the reads ask for; when the reads
// change mid-run every vehicle is subscribed again. The states must stay libsumo's through the
// changes: what is read has the same value, what is not is 0.
TEST(Backends, LibtraciFollowsReadsChangedMidRun) {
  const Scenario s = shortMotorway(60.0);
  const SumoLaunch launch{sumoArguments(s), false, "", ""};
  auto runSwitching = [&](Backend& b) {
    Recorded r;
    for (int k = 0; b.running(); ++k) {
      if (k == 200) b.setReads(VehicleReads{false, false, false});
      if (k == 400) b.setReads(VehicleReads{true, true, true});
      b.step();
      r.steps.push_back(b.vehicles());
    }
    b.close();
    return r;
  };
  auto a = startLibsumo(launch);
  const Recorded viaLibsumo = runSwitching(*a);
  auto b = launchTraci(launch);
  const Recorded viaTraci = runSwitching(*b);
  ASSERT_EQ(viaLibsumo.steps.size(), 600u);
  expectSameStates(viaLibsumo, viaTraci);
  // the narrowed stretch read nothing optional; the widened one read everything again
  std::size_t narrowedRead = 0, widenedAccelerating = 0, widenedRouted = 0;
  for (std::size_t k = 201; k < 400; ++k)
    for (const auto& v : viaTraci.steps[k]) narrowedRead += v.acceleration != 0.0 || v.routeIndex >= 0;
  for (std::size_t k = 401; k < 600; ++k)
    for (const auto& v : viaTraci.steps[k]) {
      widenedAccelerating += v.acceleration != 0.0;
      widenedRouted += !v.route.empty();
    }
  EXPECT_EQ(narrowedRead, 0u);
  EXPECT_GT(widenedAccelerating, 100u);
  EXPECT_GT(widenedRouted, 1000u);
}

// The brake action's slowDown must get the deceleration it asks for: SUMO's default speed mode
// caps a commanded slowdown at the vType's comfortable decel (4.5 m/s^2 for the motorway's cars).
TEST(Backends, SlowDownBrakesAtTheCommandedRateBeyondTheTypesDecel) {
  const Scenario s = shortMotorway(120.0);
  const SumoLaunch launch{sumoArguments(s), false, "", ""};
  for (int viaTraci = 0; viaTraci < 2; ++viaTraci) {
    auto b = viaTraci ? launchTraci(launch) : startLibsumo(launch);
    auto speedOf = [&](const std::string& id) {
      for (const SumoVehicle& v : b->vehicles())
        if (v.id == id) return v.speed;
      ADD_FAILURE() << id << " left the road";
      return 0.0;
    };
    while (b->time() < 100.0 - 1e-9) b->step();
    std::string id;
    for (const SumoVehicle& v : b->vehicles())
      if (v.type == "car" && v.speed > 25.0) id = v.id;
    ASSERT_FALSE(id.empty());
    const double v0 = speedOf(id), commanded = 8.0;
    b->slowDown(id, 0.0, v0 / commanded);
    for (int k = 0; k < 5; ++k) b->step();
    const double rate = (v0 - speedOf(id)) / 0.5;
    EXPECT_GT(rate, 7.0) << (viaTraci ? "libtraci" : "libsumo") << ": " << id << " from " << v0 << " m/s";
    EXPECT_LE(rate, commanded + 1e-9) << (viaTraci ? "libtraci" : "libsumo");
    b->close();
  }
}

// A scripted incident: the vehicle nearest the point brakes at the set rate to a stop, stands for
// `hold` seconds, then SUMO's driver model takes it on again.
TEST(Plugin, IncidentBrakesTheNearestVehicleHoldsItAndLetsGo) {
  Scenario s = shortMotorway(130.0);
  s.plugin.actions.action = Action::None;
  s.plugin.incidents = {Incident{100.0, 2200.0, -5.62, 0.0, 8.0, 5.0}};
  auto b = startLibsumo(SumoLaunch{sumoArguments(s), false, "", ""});
  HighwayPlugin plugin(*b, s.plugin);
  std::string id;
  double nearest = 1e9;
  std::vector<std::pair<double, double>> trace;  // (time, speed) of that vehicle
  while (b->running()) {
    b->step();
    plugin.update();
    if (id.empty() && b->time() >= 100.0 - 1e-9) {
      for (std::size_t i = 0; i < plugin.states().size(); ++i) {
        const double d = (plugin.states()[i].position - Vec2(2200.0, -5.62)).norm();
        if (d < nearest) nearest = d, id = plugin.states()[i].id;
      }
    }
    for (const auto& v : plugin.states())
      if (!id.empty() && v.id == id) trace.emplace_back(b->time(), v.speed);
  }
  b->close();
  ASSERT_FALSE(id.empty());
  EXPECT_LT(nearest, 60.0);
  EXPECT_EQ(plugin.counters().incidents, 1u);
  ASSERT_GT(trace.size(), 100u);
  const double v0 = trace.front().second;
  ASSERT_GT(v0, 15.0);
  const double stopAt = 100.0 + v0 / 8.0;  // commanded at 100 s, SUMO applies it from the next step
  double firstStill = -1.0, lastStill = -1.0;
  for (const auto& [t, v] : trace) {
    if (v < 0.01) {
      if (firstStill < 0) firstStill = t;
      lastStill = t;
    }
    if (t > 100.05 && t < stopAt - 0.2) {
      EXPECT_NEAR(v, v0 - 8.0 * (t - 100.0), 1.0) << "t=" << t;
    }
  }
  ASSERT_GT(firstStill, 0.0) << "never stopped";
  EXPECT_NEAR(firstStill, stopAt, 0.35);
  EXPECT_NEAR(lastStill - firstStill, 5.0, 0.35);  // held for `hold`
  EXPECT_GT(trace.back().second, 5.0);              // then driving again
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
  // SUMO's collisions cannot be had from a SUMO stsim did not start: said, not reported as 0
  EXPECT_EQ(summary.find("\"sumo_collision_steps\""), std::string::npos) << summary;
  EXPECT_EQ(jsonString(summary, "sumo_collisions").rfind("unknown", 0), 0u) << summary;
  const std::string a = slurp(dir / "attached/warnings.csv");
  EXPECT_GT(lines(a).size(), 20u);
  EXPECT_EQ(a, slurp(dir / "ref/warnings.csv"));
}

// A run stopped by an error leaves what it had: a valid warnings.csv with rows, and a summary
// that says why it stopped, counts those rows and ends strictly between `after` and `before`.
void expectOutputsSoFar(const std::filesystem::path& out, double after, double before) {
  std::size_t rows = 0;
  EXPECT_TRUE(validWarningsCsv(out / "warnings.csv", &rows));
  EXPECT_GT(rows, 0u);
  const std::string summary = slurp(out / "summary.json");
  EXPECT_EQ(jsonString(summary, "stop_reason"), "error");
  const double simulated = jsonNumber(summary, "simulated_s");
  EXPECT_GT(simulated, after);
  EXPECT_LT(simulated, before);
  EXPECT_DOUBLE_EQ(jsonNumber(summary, "total"), static_cast<double>(rows));
}

// A TraCI peer that is not (or stops being) SUMO: it listens on a free loopback port; its first
// client is relayed to a real SUMO at `upstreamPort` (0: none) until `replies` whole replies have
// passed, then it sends `garbage` instead and holds the connection open (at most `holdSeconds`, so
// a client that waits for more bytes forever is not hidden by a test that hangs).
class TamperingPeer {
 public:
  TamperingPeer(int upstreamPort, int replies, std::string garbage, double holdSeconds = 60.0)
      : upstream_(upstreamPort), replies_(replies), garbage_(std::move(garbage)), hold_(holdSeconds) {
    listen_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    EXPECT_EQ(::bind(listen_, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    EXPECT_EQ(::listen(listen_, 4), 0);
    ::getsockname(listen_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] { run(); });
  }
  ~TamperingPeer() {
    stop_ = true;
    thread_.join();
    for (int fd : {listen_, client_, server_})
      if (fd >= 0) ::close(fd);
  }
  int port() const { return port_; }
  int repliesPassed() const { return passed_; }

 private:
  static bool sendAll(int fd, const char* p, std::size_t n) {
    while (n > 0) {
      const ssize_t k = ::send(fd, p, n, MSG_NOSIGNAL);
      if (k <= 0) return false;
      p += k;
      n -= static_cast<std::size_t>(k);
    }
    return true;
  }
  // waits for fd to be readable; false on stop or timeout
  bool readable(int fd, double seconds) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (!stop_ && std::chrono::steady_clock::now() < until) {
      pollfd p{fd, POLLIN, 0};
      if (::poll(&p, 1, 50) > 0) return true;
    }
    return false;
  }
  void run() {
    if (!readable(listen_, 120.0)) return;
    client_ = ::accept(listen_, nullptr, nullptr);
    if (upstream_ > 0) {
      server_ = ::socket(AF_INET, SOCK_STREAM, 0);
      sockaddr_in a{};
      a.sin_family = AF_INET;
      a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      a.sin_port = htons(static_cast<std::uint16_t>(upstream_));
      if (::connect(server_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) return;
    }
    std::string fromServer;
    char buf[65536];
    while (!stop_ && passed_ < replies_) {
      pollfd p[2] = {{client_, POLLIN, 0}, {server_, POLLIN, 0}};
      if (::poll(p, server_ >= 0 ? 2 : 1, 50) <= 0) continue;
      if (p[0].revents) {
        const ssize_t n = ::recv(client_, buf, sizeof buf, 0);
        if (n <= 0 || !sendAll(server_, buf, static_cast<std::size_t>(n))) return;
      }
      if (server_ >= 0 && p[1].revents) {
        const ssize_t n = ::recv(server_, buf, sizeof buf, 0);
        if (n <= 0) return;
        fromServer.append(buf, static_cast<std::size_t>(n));
        // pass on whole replies ([length32] ...) until the count is reached
        while (fromServer.size() >= 4 && passed_ < replies_) {
          const auto* u = reinterpret_cast<const unsigned char*>(fromServer.data());
          const std::size_t len = (std::size_t{u[0]} << 24) | (std::size_t{u[1]} << 16) | (std::size_t{u[2]} << 8) | u[3];
          if (fromServer.size() < len) break;
          if (!sendAll(client_, fromServer.data(), len)) return;
          fromServer.erase(0, len);
          ++passed_;
        }
      }
    }
    // SUMO loses its client (and ends); the next request gets garbage
    if (server_ >= 0) ::shutdown(server_, SHUT_RDWR);
    if (!readable(client_, 120.0)) return;
    if (::recv(client_, buf, sizeof buf, 0) <= 0) return;
    sendAll(client_, garbage_.data(), garbage_.size());
    // hold the connection until the client gives up (or the time is over)
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(hold_);
    while (!stop_ && std::chrono::steady_clock::now() < until) {
      pollfd p{client_, POLLIN, 0};
      if (::poll(&p, 1, 50) > 0 && ::recv(client_, buf, sizeof buf, 0) <= 0) break;
    }
  }

  int upstream_, replies_;
  std::string garbage_;
  double hold_;
  int listen_ = -1, client_ = -1, server_ = -1, port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int> passed_{0};
  std::thread thread_;
};

std::string randomBytes(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (auto& c : s) c = static_cast<char>(rng() & 0xff);
  return s;
}

// What a user sees when --traci points at something that is not SUMO: one line naming the
// endpoint and what was wrong, exit 1, never a crash or a hang. libtraci alone aborts on a length
// field <= 4 and waits forever for the gigabyte that "HTTP/1.1" announces.
TEST(Backends, GarbageFromANonSumoPeerIsAOneLineError) {
  const auto dir = freshDir("garbage_peer");
  const std::vector<std::pair<std::string, std::string>> cases{
      {"http", "HTTP/1.1 400 Bad Request\r\n\r\n"},
      {"tiny_length", std::string("\0\0\0\x02", 4)},
      {"negative_length", std::string("\xff\xff\xff\xf0\0\0\0\0", 8)},
      {"random", randomBytes(4000, 7)},
      // a plausible length, then a status block for a command nobody sent
      {"wrong_command", std::string("\0\0\0\x0b\x07\x42\0\0\0\0\0", 11)},
  };
  for (const auto& [name, bytes] : cases) {
    TamperingPeer peer(0, 0, bytes);
    const auto r = runStsim({"highway", motorway().string(), "--traci", "localhost:" + std::to_string(peer.port()),
                             "--out", (dir / name).string()},
                            dir);
    EXPECT_EQ(r.code, 1) << name << ": " << r.err;
    const auto ls = lines(r.err);
    ASSERT_EQ(ls.size(), 1u) << name << ": " << r.err;
    EXPECT_NE(ls[0].find("localhost:" + std::to_string(peer.port())), std::string::npos) << ls[0];
    EXPECT_NE(ls[0].find("not a TraCI server"), std::string::npos) << name << ": " << ls[0];
  }
}

// SUMO's replies pass through a peer that, after 2000 of them (some 120 s of simulated time),
// answers with random bytes and keeps the connection open: stsim stops with one line, exit 1, and
// leaves everything computed up to then.
TEST(Backends, GarbageMidRunFlushesResultsSoFar) {
  const auto dir = freshDir("garbage_mid_run");
  Scenario s = shortMotorway(420.0);
  detail::SumoProcess sumo("sumo", sumoArguments(s), (dir / "sumo.log").string());
  TamperingPeer peer(sumo.port(), 2000, randomBytes(3000, 11));
  const auto r = runStsim({"highway", motorway().string(), "--traci", "localhost:" + std::to_string(peer.port()),
                           "--out", (dir / "out").string()},
                          dir);
  sumo.stop(0.0);
  EXPECT_EQ(peer.repliesPassed(), 2000);
  EXPECT_EQ(r.code, 1) << r.err;
  const auto ls = lines(r.err);
  ASSERT_EQ(ls.size(), 1u) << r.err;
  EXPECT_NE(ls[0].find("broken at t = "), std::string::npos) << ls[0];
  EXPECT_NE(ls[0].find("not a TraCI server"), std::string::npos) << ls[0];
  expectOutputsSoFar(dir / "out", 10.0, 420.0);
}

// SUMO dies mid-run: stsim reports the lost connection in one line, exits non-zero and leaves a
// valid warnings.csv with the warnings up to that point and a summary saying why it stopped.
// SUMO is killed once stsim has written warnings (so it has stepped), on the ring with a 10 h end,
// which no machine finishes before the kill: no sleeps to tune.
TEST(Backends, DroppedConnectionGivesClearErrorAndValidOutputs) {
  const auto dir = freshDir("dropped");
  const auto ring = sourceDir() / "networks/ring/scenario.yaml";
  Scenario s = loadScenario(ring);
  s.end = 36000.0;
  detail::SumoProcess sumo("sumo", sumoArguments(s), (dir / "sumo.log").string());
  StsimProcess attached({"highway", ring.string(), "--end", "36000", "--traci",
                         "localhost:" + std::to_string(sumo.port()), "--out", (dir / "out").string()},
                        dir);
  ASSERT_TRUE(waitForWarningRows(dir / "out/warnings.csv", attached)) << attached.err();
  ::kill(sumo.pid(), SIGKILL);
  const int code = attached.wait();
  sumo.stop(0.0);
  EXPECT_EQ(code, 1);
  const auto errLines = lines(attached.err());
  ASSERT_EQ(errLines.size(), 1u) << attached.err();
  EXPECT_NE(errLines[0].find("TraCI connection to localhost:"), std::string::npos) << errLines[0];
  EXPECT_NE(errLines[0].find("lost at t = "), std::string::npos) << errLines[0];
  expectOutputsSoFar(dir / "out", 0.0, 36000.0);
}

}  // namespace
}  // namespace st::cosim
