// Scenario files: an arm defined in YAML, allowed-collision edits, and errors naming the key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <tuple>

#include <starm/scenario.hpp>

namespace st::arm {
namespace {

namespace fs = std::filesystem;

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("stsim_arm_scn_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

TEST(Scenario, YamlArmMatchesTheBuiltInIiwa) {
  // the iiwa's classic DH written out in YAML, with a base pose and an edited matrix
  const fs::path p = write("yaml_arm.yaml", R"(
models:
  my_iiwa:
    convention: classic
    joints:
      - {d: 0.36, alpha: -1.5707963267948966, limits: [-2.9, 2.9]}
      - {alpha: 1.5707963267948966, limits: [-2.0, 2.0]}
      - {d: 0.42, alpha: 1.5707963267948966, limits: [-2.9, 2.9]}
      - {alpha: -1.5707963267948966, limits: [-2.0, 2.0]}
      - {d: 0.40, alpha: -1.5707963267948966, limits: [-2.9, 2.9]}
      - {alpha: 1.5707963267948966, limits: [-2.0, 2.0]}
      - {d: 0.126, limits: [-3.0, 3.0]}
    capsules:
      - {body: 3, a: [0, 0, 0], b: [0, 0.2, 0], radius: 0.07}
      - {body: 7, a: [0, 0, -0.08], b: [0, 0, 0], radius: 0.05}
arms:
  - name: a
    model: my_iiwa
    base: {xyz: [0.1, 0.2, 0.3], rpy: [0, 0, 0.5]}
    allow: [[3, 7]]
    check: [[0, 1]]
    waypoints: [{t: 0, q: [0, 0, 0, 0, 0, 0, 0]}]
)");
  const Scenario s = loadScenario(p.string());
  ASSERT_EQ(s.arms.size(), 1u);
  const ArmInstance& a = s.arms[0];
  EXPECT_EQ(a.model.dof(), 7);
  EXPECT_TRUE(a.model.isAllowed(3, 7));
  EXPECT_FALSE(a.model.isAllowed(0, 1));
  EXPECT_TRUE(a.model.isAllowed(1, 2));
  const ArmModel ref = iiwa14Model();
  const Eigen::Isometry3d base = Eigen::Translation3d(0.1, 0.2, 0.3) * Eigen::AngleAxisd(0.5, Vec3::UnitZ());
  std::mt19937_64 g(3);
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<double> q;
    for (int k = 0; k < 7; ++k) q.push_back(std::uniform_real_distribution<double>(-1.9, 1.9)(g));
    const auto f = forwardKinematics(a.model, a.base, q);
    const auto r = forwardKinematics(ref, base, q);
    for (int k = 0; k < 9; ++k) ASSERT_LT((f[k].matrix() - r[k].matrix()).cwiseAbs().maxCoeff(), 1e-12);
  }
  fs::remove(p);
}

void expectError(const std::string& name, const std::string& yaml, const std::string& mention) {
  const fs::path p = write(name, yaml);
  try {
    loadScenario(p.string());
    ADD_FAILURE() << name << ": no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
  fs::remove(p);
}

TEST(Scenario, AutoDecompositionFactor) {
  const std::string arm = "arms:\n  - {name: a, model: panda, waypoints: [{t: 0, q: [0, 0, 0, -1, 0, 1, 0]}]}\n";
  const fs::path p = write("auto_df.yaml", arm + "octree: {kind: octree, decomposition_factor: auto}\n");
  EXPECT_TRUE(loadScenario(p.string()).broad.rule.autoFactor);
  fs::remove(p);
  expectError("bad_df.yaml", arm + "octree: {decomposition_factor: often}\n", "octree.decomposition_factor");
}

TEST(Scenario, ErrorsNameFileLineAndKey) {
  const std::string arm = "arms:\n  - {name: a, model: panda, waypoints: [{t: 0, q: [0, 0, 0, -1, 0, 1, 0]}]}\n";
  expectError("repeated_key.yaml", arm + "safety: {cycle_time: 0.001, cycle_time: 0.01}\n",
              ":3: safety.cycle_time: repeated key (first given at line 3)");
  // a missing key is named (not yaml-cpp's "invalid node"); a horizon of 1e300 and a cycle of
  // 1e-12 are refused at once
  expectError("only_name.yaml", "name: x\n", ":1: arms: missing key");
  expectError("huge_horizon.yaml", arm + "safety: {horizon: 1e300}\n", ":3: safety.horizon: 1e+300 s is more than the 60 s look-ahead limit");
  expectError("tiny_cycle.yaml", arm + "safety: {cycle_time: 1e-12}\nduration: 10\n",
              ":3: safety.cycle_time: the waypoints' 10 s would take more than 1e7 cycles");
  // a duration of 1e300 is named as the duration; 1e300 m of separation and two obstacles of one
  // name are refused
  expectError("long_duration.yaml", arm + "duration: 1e300\n",
              ":3: duration: 1e+300 s would take more than 1e7 cycles at the cycle time of 0.001 s");
  expectError("huge_separation.yaml", arm + "safety: {min_separation: 1e300}\n",
              ":3: safety.min_separation: 1e+300 m is more than 10 m");
  expectError("same_obstacle_name.yaml",
              arm + "obstacles:\n  - {name: post, sphere: {center: [1, 1, 1], radius: 0.1}}\n"
                    "  - {name: post, sphere: {center: [2, 1, 1], radius: 0.1}}\n",
              ":5: obstacles[1].name: duplicate obstacle name 'post' (also obstacles[0])");
  expectError("two_shapes.yaml",
              arm + "obstacles:\n  - {sphere: {center: [1, 1, 1], radius: 0.1}, box: {center: [0, 0, 0], half_extents: [1, 1, 1]}}\n",
              ":4: obstacles[0]: give one of sphere, capsule, box");
  expectError("trace_dir.yaml", "arms:\n  - {name: a, model: panda}\ntrace: " + fs::temp_directory_path().string() + "\n",
              ":3: trace: is a directory");
  expectError("unknown_key.yaml", arm + "safety: {cycle_tme: 0.001}\n", ":3: safety.cycle_tme: unknown key");
  expectError("bad_number.yaml", arm + "safety: {stopping_time: fast}\n", ":3: safety.stopping_time: must be a number, got 'fast'");
  expectError("short_horizon.yaml", arm + "safety: {horizon: 0.01}\n", "safety.horizon: must be at least the safe time");
  expectError("joint_count.yaml", "arms:\n  - {name: a, model: panda, waypoints: [{t: 0, q: [0, 0, 0]}]}\n",
              ":2: arms[0].waypoints[0].q: expected 7 joint angles and rates, got 3 and 3");
  expectError("nan.yaml", "arms:\n  - {name: a, model: panda, waypoints: [{t: 0, q: [0, .nan, 0, -1, 0, 1, 0]}]}\n",
              "arms[0].waypoints[0].q[1]: not a finite number");
  expectError("no_motion.yaml", "arms:\n  - {name: a, model: panda}\n", "trace: expected a sensor trace or waypoints");
  expectError("box.yaml", arm + "obstacles:\n  - {box: {center: [0, 0, 0], half_extents: [0.1, -0.1, 0.1]}}\n",
              ":4: obstacles[0].box.half_extents: must be positive");
  expectError("bad_body.yaml",
              "models:\n  m:\n    convention: modified\n    joints: [{d: 0.1}]\n    capsules: [{body: 5, a: [0, 0, 0], b: [0, 0, 1], radius: 0.1}]\n" +
                  std::string("arms:\n  - {name: a, model: m, waypoints: [{t: 0, q: [0]}]}\n"),
              "models.m.capsules[0].body: expected an integer 0..2");
}

TEST(Scenario, ADeviceOrBinaryIsNamedNotABadAlloc) {
  // /dev/zero ended in std::bad_alloc naming no file
  try {
    loadScenario("/dev/zero");
    ADD_FAILURE() << "/dev/zero loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/zero: holds a NUL byte: not a text file"), std::string::npos) << e.what();
  }
}

// Shapes yaml-cpp would otherwise throw on ("bad conversion", no file, no key) or that were
// silently ignored or truncated.
TEST(Scenario, MisshapenYamlNamesFileLineAndKey) {
  const std::string wp = "waypoints: [{t: 0, q: [0, 0, 0, -1, 0, 1, 0]}]";
  const std::string arm = "arms:\n  - {name: a, model: panda, " + wp + "}\n";
  expectError("name_list.yaml", "arms:\n  - {name: [a], model: panda, " + wp + "}\n", ":2: arms[0].name: expected a name");
  expectError("trace_list.yaml", "arms:\n  - {name: a, model: panda}\ntrace: [t.csv]\n", ":3: trace: expected a name");
  expectError("kind_list.yaml", arm + "octree: {kind: [tree]}\n", ":3: octree.kind: must be one of tree, octree, quadtree, cells, single, none");
  expectError("obstacle_name.yaml", arm + "obstacles: [{name: {x: 1}, sphere: {center: [1, 1, 1], radius: 0.1}}]\n",
              ":3: obstacles[0].name: expected a name");
  expectError("convention_list.yaml",
              "models:\n  m: {convention: [x], joints: [{d: 0.1}], capsules: [{body: 1, a: [0, 0, 0], b: [0, 0, 1], radius: 0.1}]}\n"
              "arms:\n  - {name: a, model: m, waypoints: [{t: 0, q: [0]}]}\n",
              ":2: models.m.convention: expected a name");
  expectError("models_list.yaml", "models: [1, 2]\narms:\n  - {name: a, model: m, waypoints: [{t: 0, q: [0]}]}\n",
              ":1: models: expected a mapping");
  expectError("obstacles_map.yaml", arm + "obstacles: {name: x}\n", ":3: obstacles: expected a list");
  expectError("sensor_no_period.yaml", "arms:\n  - {name: a, model: panda, sensor: {jitter: 0.001}}\n",
              ":2: arms[0].sensor.period: missing");
  expectError("sensor_jitter.yaml", "arms:\n  - {name: a, model: panda, sensor: {period: 0.02, jitter: 0.02}}\n",
              ":2: arms[0].sensor.jitter: must be at least 0 and less than the period");
  expectError("sensor_key.yaml", "arms:\n  - {name: a, model: panda, sensor: {rate: 50}}\n", "arms[0].sensor.rate: unknown key");
  expectError("tracked_yes.yaml", arm + "obstacles: [{sphere: {center: [1, 1, 1], radius: 0.1}, tracked: yes}]\n",
              ":3: obstacles[0].tracked: expected true or false, got 'yes'");
  expectError("allow_scalar.yaml", "arms:\n  - {name: a, model: panda, allow: 3, " + wp + "}\n",
              ":2: arms[0].allow: expected a list");
  expectError("allow_fraction.yaml", "arms:\n  - {name: a, model: panda, allow: [[1, 2.5]], " + wp + "}\n",
              ":2: arms[0].allow[0][1]: expected an integer 0..8");
  expectError("allow_range.yaml", "arms:\n  - {name: a, model: panda, check: [[1, 9]], " + wp + "}\n",
              ":2: arms[0].check[0][1]: expected an integer 0..8");
  expectError("keep_out.yaml", arm + "random_obstacles: {count: 3, min: [0, 0, 0], max: [1, 1, 1], keep_out: 5}\n",
              ":3: random_obstacles.keep_out: expected a list");
  expectError("bounds.yaml", arm + "octree:\n  bounds: {min: [1, 1, 1], max: [2, 0, 2]}\n",
              ":4: octree.bounds.max: must exceed octree.bounds.min on every axis");
  expectError("duration.yaml", arm + "duration: -5\n", ":3: duration: must not be negative");
  expectError("complex_key.yaml", arm + "? [1, 2]\n: 3\n", ":3: (key): keys must be names");
  // 1 rad in 1 ms on joint 1: a 1000 rad/s piece
  expectError("fast_waypoints.yaml",
              "arms:\n  - name: a\n    model: panda\n    waypoints:\n      - {t: 0, q: [0, 0, 0, -1, 0, 1, 0]}\n"
              "      - {t: 0.001, q: [1, 0, 0, -1, 0, 1, 0]}\n",
              ":6: arms[0].waypoints[1].q: joint 1 rate 1000 rad/s is beyond its limit 100 rad/s");
  expectError("max_rate.yaml",
              "models:\n  m: {convention: classic, joints: [{d: 0.1, max_rate: -1}], capsules: [{body: 1, a: [0, 0, 0], b: [0, 0, 1], radius: 0.1}]}\n"
              "arms:\n  - {name: a, model: m, waypoints: [{t: 0, q: [0]}]}\n",
              ":2: models.m.joints[0].max_rate: must be positive");
  // and a model's own rate limit applies to its waypoints
  expectError("own_rate.yaml",
              "models:\n  m: {convention: classic, joints: [{d: 0.1, max_rate: 2}], capsules: [{body: 1, a: [0, 0, 0], b: [0, 0, 1], radius: 0.1}]}\n"
              "arms:\n  - {name: a, model: m, waypoints: [{t: 0, q: [0]}, {t: 1, q: [2.5]}]}\n",
              "arms[0].waypoints[1].q: joint 1 rate 2.5 rad/s is beyond its limit 2 rad/s");
}

TEST(Scenario, CsvTraceGivesTheSameWarningsAsTheScriptItRecords) {
  // record the two-Panda waypoint motion to CSV at full precision, replay it through CsvSensor
  const Scenario s = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/two_pandas.yaml");
  const fs::path csv = write("trace.csv", "");
  {
    std::ofstream out(csv);
    out.precision(17);
    auto src = makeSensor(s);
    Reading r;
    while (src->next(r)) {
      out << r.t << ", " << s.arms[r.arm].name;
      for (double v : r.q) out << ", " << v;
      for (double v : r.qdot) out << ", " << v;
      out << "\n";
    }
  }
  Scenario replay = s;
  replay.scripts.clear();
  replay.tracePath = csv.string();
  auto collect = [](const Scenario& sc) {
    Monitor m = makeMonitor(sc);
    auto src = makeSensor(sc);
    RunStats st;
    std::vector<std::tuple<double, int, int, int, int, double, double>> out;
    run(m, *src, st, [&](const Monitor& mon) {
      for (const Warning& w : mon.warnings()) out.emplace_back(w.t, w.arm, w.capsule, w.otherCapsule, w.obstacle, w.distance, w.ttc);
    });
    return out;
  };
  const auto a = collect(s);
  ASSERT_GT(a.size(), 1000u);
  EXPECT_EQ(collect(replay), a);
  fs::remove(csv);
}

TEST(Scenario, TimeGoingBackwardsNamesTheTraceLine) {
  const fs::path csv = write("back.csv", "t,arm,q1,qd1\n0.0,a,0.1,0\n0.001,a,0.1,0\n0.0005,a,0.1,0\n");
  ArmModel m;
  m.name = "one";
  m.joints = {{0, 0, 0.1, 0, -1, 1}};
  m.capsules = {{1, {0, 0, 0}, {0.1, 0, 0}, 0.01}};
  m.resetAllowedToAdjacent();
  Monitor mon({ArmInstance{"a", m, Eigen::Isometry3d::Identity()}}, {}, SafetyConfig{});
  CsvSensor src(csv.string(), {"a"}, {1});
  RunStats st;
  try {
    run(mon, src, st, [](const Monitor&) {});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("back.csv:4: time"), std::string::npos) << e.what();
  }
  EXPECT_EQ(st.cycles, 2u);
  fs::remove(csv);
}


// One arm, one time, one state: a second line that differs names both lines (neither is taken
// silently); the same line repeated is read once.
TEST(Scenario, ConflictingReadingsOfOneArmAtOneTimeNameBothLines) {
  const fs::path csv =
      write("conflict.csv", "t,arm,q1,qd1\n0.0,a,0.1,0\n0.0,a,0.1,0\n0.001,a,0.1,0\n# c\n0.001,a,0.2,0\n");
  CsvSensor src(csv.string(), {"a"}, {1});
  Reading r;
  ASSERT_TRUE(src.next(r));
  EXPECT_EQ(r.where, csv.string() + ":2");
  ASSERT_TRUE(src.next(r));  // line 3 repeats line 2: skipped
  EXPECT_EQ(r.where, csv.string() + ":4");
  try {
    src.next(r);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              csv.string() + ":6: arm 'a' at t = 0.001 s differs from its reading at line 4 (one arm, one time, one state)");
  }
  fs::remove(csv);
}

// The run asks stopRequested before each cycle and stops at a whole cycle (Ctrl-C in stsim arm).
TEST(Scenario, RunStopsAtAWholeCycleWhenAsked) {
  const Scenario s = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/two_pandas.yaml");
  Monitor m = makeMonitor(s);
  auto src = makeSensor(s);
  RunStats st;
  int seen = 0;
  run(m, *src, st, [&](const Monitor&) { ++seen; }, [&] { return seen == 10; });
  EXPECT_TRUE(st.interrupted);
  EXPECT_EQ(st.cycles, 10u);
  EXPECT_DOUBLE_EQ(m.time(), 0.009);
  Monitor m2 = makeMonitor(s);
  auto src2 = makeSensor(s);
  RunStats all;
  run(m2, *src2, all, [](const Monitor&) {}, [] { return false; });
  EXPECT_FALSE(all.interrupted);
  EXPECT_EQ(all.cycles, 3001u);
}

}  // namespace
}  // namespace st::arm
