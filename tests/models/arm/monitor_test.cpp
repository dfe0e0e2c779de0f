// The monitor on the shipped scenarios: octree invariants while the arms move, the octree
// finds exactly the warnings all-pairs finds, and the two Pandas are stopped before contact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

#include <starm/scenario.hpp>

namespace st::arm {
namespace {

std::string scenarioPath(const std::string& name) {
  return std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/" + name + ".yaml";
}

using Key = std::tuple<double, int, int, int, int, int, int, int, double, double, int, bool>;

std::vector<Key> runAll(const Scenario& s) {
  Monitor m = makeMonitor(s);
  auto src = makeSensor(s);
  RunStats st;
  std::vector<Key> keys;
  run(m, *src, st, [&](const Monitor& mon) {
    for (const Warning& w : mon.warnings())
      keys.emplace_back(w.t, w.arm, w.body, w.capsule, w.otherArm, w.otherBody, w.otherCapsule, w.obstacle, w.distance,
                        w.ttc, static_cast<int>(w.outcome), w.stop);
  });
  std::sort(keys.begin(), keys.end());
  return keys;
}

class Scenarios : public ::testing::TestWithParam<const char*> {};

TEST_P(Scenarios, OctreeFindsExactlyTheAllPairsWarnings) {
  Scenario s = loadScenario(scenarioPath(GetParam()));
  Scenario ref = s;
  ref.broad.kind = SpaceKind::None;
  const std::vector<Key> all = runAll(ref);
  ASSERT_GT(all.size(), 0u) << "the scenario must raise warnings for the comparison to mean something";
  EXPECT_EQ(runAll(s), all);
  // other octree rules find the same (the shipped scenarios set auto: these are fixed)
  for (int df : {1, 2, 4, 16}) {
    Scenario v = s;
    v.broad.rule.autoFactor = false;
    v.broad.rule.decompositionFactor = df;
    v.broad.margin = 0.0;
    EXPECT_EQ(runAll(v), all) << "decomposition factor " << df;
  }
  // decomposition_factor: auto, from the arm's start (2) and from the pool's (16, so that the
  // factor changes and every list is gathered again)
  for (int start : {2, 16}) {
    Scenario v = s;
    v.broad.rule.autoFactor = true;
    v.broad.rule.autoStart = start;
    EXPECT_EQ(runAll(v), all) << "auto from " << start;
  }
  // and the other kinds of space
  for (SpaceKind kind : {SpaceKind::Cells, SpaceKind::Single}) {
    Scenario v = s;
    v.broad.kind = kind;
    v.broad.rule.cellSize = 0.2;
    EXPECT_EQ(runAll(v), all) << toString(kind);
  }
}

TEST_P(Scenarios, OctreeInvariantsWhileMoving) {
  const Scenario s = loadScenario(scenarioPath(GetParam()));
  Monitor m = makeMonitor(s);
  auto src = makeSensor(s);
  RunStats st;
  int checks = 0;
  run(m, *src, st, [&](const Monitor& mon) {
    if (st.cycles % 50 != 1) return;
    ++checks;
    const Space<3>& sp = *mon.space();
    const Aabb3 bounds = sp.bounds();
    auto clamp = [&](const Aabb3& b) {
      return Aabb3{b.min.cwiseMax(bounds.min).cwiseMin(bounds.max), b.max.cwiseMin(bounds.max).cwiseMax(bounds.min)};
    };
    const std::vector<int> leaves = sp.leaves();
    double volume = 0.0;
    for (int leaf : leaves) {
      const Aabb3 lb = sp.leafBounds(leaf);
      volume += lb.extent().prod();
      const auto& objs = sp.objectsIn(leaf);
      // a leaf over the decomposition factor is at the depth limit
      if (static_cast<int>(objs.size()) > sp.rule().decompositionFactor) {
        ASSERT_EQ(sp.depthOf(leaf), sp.rule().maxDepth);
      }
      for (int id : objs) ASSERT_TRUE(lb.overlaps(clamp(mon.fatBox(id)))) << "object " << id << " listed in a leaf it is not in";
    }
    // the leaves tile the space
    ASSERT_NEAR(volume, bounds.extent().prod(), 1e-9 * bounds.extent().prod());
    for (int id = 0; id < mon.objectCount(); ++id) {
      ASSERT_TRUE(sp.contains(id));
      // the look-ahead sweep stays inside the box the space files the object under
      const Aabb3& sw = mon.sweptBox(id);
      const Aabb3& fat = mon.fatBox(id);
      ASSERT_TRUE((sw.min.array() >= fat.min.array()).all() && (sw.max.array() <= fat.max.array()).all()) << id;
      // listed in exactly the leaves its box touches
      std::vector<int> expect;
      for (int leaf : leaves)
        if (sp.leafBounds(leaf).overlaps(clamp(fat))) expect.push_back(leaf);
      std::vector<int> got = sp.leavesOf(id);
      std::sort(got.begin(), got.end());
      ASSERT_EQ(got, expect) << "object " << id;
    }
    // every arm capsule's sweep contains the capsule now and after the look-ahead
    const double h = mon.safety().lookAhead();
    for (int i = 0; i < mon.capsuleCount(); ++i) {
      const MovingCapsule c = mon.movingCapsule(i);
      for (double t : {0.0, h})
        for (const Vec3& p : {c.at(t).a, c.at(t).b})
          ASSERT_TRUE((mon.sweptBox(i).min.array() <= p.array() - c.c.radius).all() &&
                      (mon.sweptBox(i).max.array() >= p.array() + c.c.radius).all());
    }
  });
  EXPECT_GT(checks, 20);
  // the tree followed the arms: it divided and reunited on the way
  EXPECT_GT(m.space()->counters().subdivisions, 0u);
  EXPECT_GT(m.space()->counters().reunions, 0u);
}

// decomposition_factor: auto with the monitor's rounds: from a start of 16 the windows close (16
// cycles each) and the factor comes down to the arm's finest (its lists are tested every cycle and
// re-filed rarely); every list, gathered again at each change of factor, holds every object whose
// fat box overlaps its owner's and which was filed before it (the pairs the cycle must test).
TEST_P(Scenarios, AutoFactorRegathersSupersetLists) {
  Scenario s = loadScenario(scenarioPath(GetParam()));
  s.broad.rule.autoFactor = true;
  s.broad.rule.autoStart = 16;
  Monitor m = makeMonitor(s);
  auto src = makeSensor(s);
  RunStats st;
  int checks = 0;
  std::uint64_t lastDf = 16;
  run(m, *src, st, [&](const Monitor& mon) {
    const auto df = static_cast<std::uint64_t>(mon.space()->rule().decompositionFactor);
    const bool changed = df != lastDf;
    lastDf = df;
    // each cycle just after a change of factor, and every 50th
    if (!changed && st.cycles % 50 != 1) return;
    ++checks;
    const int nc = mon.capsuleCount();
    for (int i = 0; i < nc; ++i) {
      const std::vector<int>& list = mon.neighbours(i);
      for (int j = 0; j < mon.objectCount(); ++j) {
        if (j == i || mon.filedAt(j) >= mon.filedAt(i) || !mon.fatBox(i).overlaps(mon.fatBox(j))) continue;
        ASSERT_NE(std::find(list.begin(), list.end(), j), list.end())
            << "cycle " << st.cycles << ", df " << df << ": " << j << " missing from " << i << "'s list";
      }
    }
  });
  EXPECT_GT(checks, 20);
  ASSERT_NE(m.space()->tuner(), nullptr);
  EXPECT_GT(m.space()->tuner()->decisions(), 100u);      // windows closed: a cycle's round each
  EXPECT_GT(m.space()->tuner()->factorChanges(), 0u);    // and moved the factor
  EXPECT_LE(m.space()->rule().decompositionFactor, 4);   // toward the finest
}

INSTANTIATE_TEST_SUITE_P(Shipped, Scenarios, ::testing::Values("two_pandas", "iiwa_truss", "panda_clutter"));

// "none" is the brute force behind the Space interface (no null space): every pair that is not
// allowed is a candidate, each once per cycle, on every shipped scenario.
TEST_P(Scenarios, NoneIsTheBruteForceSpaceWithEveryPairOncePerCycle) {
  Scenario s = loadScenario(scenarioPath(GetParam()));
  s.broad.kind = SpaceKind::None;
  Monitor m = makeMonitor(s);
  ASSERT_NE(m.space(), nullptr);
  EXPECT_EQ(m.space()->kind(), SpaceKind::None);
  const int nc = m.capsuleCount();
  std::uint64_t pairs = 0;
  for (int i = 0; i < nc; ++i) {
    for (int j = i + 1; j < nc; ++j) {
      const int a = m.capsuleArm(i);
      if (a != m.capsuleArm(j) || !m.arm(a).model.isAllowed(m.capsuleBody(i), m.capsuleBody(j))) ++pairs;
    }
  }
  for (int a = 0; a < m.armCount(); ++a) ASSERT_TRUE(m.arm(a).allowedObstacles.empty()) << "count them below";
  pairs += static_cast<std::uint64_t>(nc) * m.obstacles().size();
  for (int k = 0; k < 3; ++k) m.cycle(0.001 * k);
  EXPECT_EQ(m.counters().candidatePairs, 3 * pairs);
}

TEST(TwoPandas, StopBeforeFirstContact) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Monitor m = makeMonitor(s);
  auto src = makeSensor(s);
  RunStats st;
  double contact = NAN;
  run(m, *src, st, [&](const Monitor& mon) {
    if (!std::isnan(contact)) return;
    // first contact of the two arms in the trace: exact capsule distance zero, no growth
    for (int i = 0; i < mon.capsuleCount(); ++i)
      for (int j = i + 1; j < mon.capsuleCount(); ++j)
        if (mon.capsuleArm(i) != mon.capsuleArm(j) && distance(mon.movingCapsule(i).c, mon.movingCapsule(j).c) <= 0.0)
          contact = static_cast<double>(st.cycles - 1) * s.safety.cycleTime;
  });
  ASSERT_FALSE(std::isnan(contact)) << "the scenario must put the arms on a collision course";
  ASSERT_GT(contact, 0.0);
  for (int a = 0; a < 2; ++a) {
    ASSERT_FALSE(std::isnan(st.firstStop[a])) << "no STOP for arm " << a;
    EXPECT_LT(st.firstStop[a], contact);
    // and early enough to brake: at least the safe time ahead
    EXPECT_GE(contact - st.firstStop[a], s.safety.safeTime()) << "arm " << a;
  }
  std::printf("two pandas: STOP at %.3f s / %.3f s, first contact at %.3f s\n", st.firstStop[0], st.firstStop[1], contact);
}

TEST(Monitor, MovingObstacleStopsArmOneSafeTimeAhead) {
  // a ball thrown at a resting Panda's hand from 1 m at 2 m/s: motion exactly linear, so the
  // STOP must come within one cycle of (contact with the grown objects) - (safe time)
  ArmInstance arm{"p", pandaModel(), Eigen::Isometry3d::Identity()};
  const std::vector<double> q{0, -0.785, 0, -2.356, 0, 1.571, 0.785}, qd(7, 0.0);
  const Vec3 hand = forwardKinematics(arm.model, arm.base, q).back().translation();
  Obstacle ball;
  ball.name = "ball";
  ball.kind = ShapeKind::Sphere;
  ball.sphere = {hand + Vec3(1.0, 0, 0), 0.05};
  ball.velocity = Vec3(-2.0, 0, 0);
  SafetyConfig safety;
  Monitor m({arm}, {ball}, safety);
  double stop = NAN;
  for (int k = 0; k < 600 && std::isnan(stop); ++k) {
    const double t = k * safety.cycleTime;
    m.setJointState(0, t, q.data(), qd.data());
    m.cycle(t);
    for (const Warning& w : m.warnings())
      if (w.stop) {
        stop = t;
        EXPECT_EQ(w.obstacle, 0);
        EXPECT_LE(w.ttc, safety.safeTime());
      }
  }
  ASSERT_FALSE(std::isnan(stop));
  // truth: bisection on the exact distance of the ball to every capsule
  auto gap = [&](double t) {
    double d = 1e9;
    for (int i = 0; i < m.capsuleCount(); ++i)
      d = std::min(d, distance(m.movingCapsule(i).c, Sphere{ball.sphere.center + t * ball.velocity, 0.05}));
    return d;
  };
  auto firstBelow = [&](double level) {
    double lo = 0.0, hi = 1.0;
    for (int k = 0; k < 100; ++k) {
      const double mid = 0.5 * (lo + hi);
      (gap(mid) > level ? lo : hi) = mid;
    }
    return hi;
  };
  const double contact = firstBelow(0.0), grownContact = firstBelow(safety.minSeparation);
  EXPECT_GE(contact - stop, safety.safeTime());
  EXPECT_LE(grownContact - stop, safety.safeTime() + safety.cycleTime + 1e-9);
}

TEST(Monitor, SelfCollisionFollowsTheAllowedCollisionMatrix) {
  // find a Panda pose where two bodies the matrix checks come within the minimum separation
  const ArmModel model = pandaModel();
  std::mt19937_64 g(5);
  SafetyConfig safety;
  std::vector<double> q(7), qd(7, 0.0);
  int bi = -1, bj = -1;
  for (int trial = 0; trial < 100000 && bi < 0; ++trial) {
    for (int k = 0; k < 7; ++k) q[k] = std::uniform_real_distribution<double>(model.joints[k].lower, model.joints[k].upper)(g);
    const auto f = forwardKinematics(model, Eigen::Isometry3d::Identity(), q);
    for (const LinkCapsule& a : model.capsules)
      for (const LinkCapsule& b : model.capsules)
        if (a.body < b.body && !model.isAllowed(a.body, b.body) &&
            distance(Capsule{f[a.body] * a.a, f[a.body] * a.b, a.radius}, Capsule{f[b.body] * b.a, f[b.body] * b.b, b.radius}) <
                0.5 * safety.minSeparation)
          bi = a.body, bj = b.body;
  }
  ASSERT_GE(bi, 0);
  auto selfWarnings = [&](const ArmModel& mm) {
    Monitor m({ArmInstance{"p", mm, Eigen::Isometry3d::Identity()}}, {}, safety);
    m.setJointState(0, 0.0, q.data(), qd.data());
    m.cycle(0.0);
    int n = 0;
    for (const Warning& w : m.warnings())
      if (w.otherArm == 0 && std::minmax(w.body, w.otherBody) == std::minmax(bi, bj)) ++n;
    return n;
  };
  EXPECT_GT(selfWarnings(model), 0);
  ArmModel edited = model;
  edited.setAllowed(bi, bj, true);
  EXPECT_EQ(selfWarnings(edited), 0);
}

// ---- the library checks its input and watches its sensors as the service does ----

const std::vector<double> kHome = {0, -0.785, 0, -2.356, 0, 1.571, 0.785};

TEST(Monitor, ARefusedReadingChangesNothing) {
  Monitor m = makeMonitor(loadScenario(scenarioPath("two_pandas")));
  const std::vector<double> still(7, 0.0);
  for (int a = 0; a < 2; ++a) m.setJointState(a, 0.0, kHome.data(), still.data());
  m.cycle(0.0);
  ASSERT_FALSE(m.stopped(0));
  const MovingCapsule before = m.movingCapsule(0);
  std::vector<double> bad = kHome;
  bad[2] = std::nan("");
  // a NaN joint gave no warning and an infinite TTC in process; the service refused it
  EXPECT_THROW(m.setJointState(0, 0.001, bad.data(), still.data()), InputError);
  bad = kHome;
  bad[3] = 4.0;  // beyond the Panda's joint 4 limits
  try {
    m.setJointState(0, 0.001, bad.data(), still.data());
    FAIL() << "an angle beyond its limits was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("left: joint 4 angle 4 rad is beyond its limits"), std::string::npos) << e.what();
  }
  EXPECT_THROW(m.setJointState(0, -0.5, kHome.data(), still.data()), InputError) << "time went back";
  EXPECT_THROW(m.setJointState(7, 0.001, kHome.data(), still.data()), InputError) << "no arm 7";
  const MovingCapsule after = m.movingCapsule(0);
  EXPECT_EQ(before.c.a, after.c.a);
  EXPECT_EQ(before.va, after.va);
}

// Both Pandas at rest at home (no pair within the look-ahead); arm 0's sensor reports every
// `period` +- `jitter` (uniform) until `silentAt`; arm 1 every cycle. Cycles at
// 1 kHz until 2 s: the cycles arm 0 is STOPped, and the first STOP after it falls silent.
struct Watch {
  int stopped = 0, cycles = 0;
  double lastReading = 0.0, firstStopAfterSilence = -1.0;
};
Watch watch(double period, double jitter, double declaredPeriod, double declaredJitter, double silentAt) {
  Scenario s = loadScenario(scenarioPath("two_pandas"));
  s.arms[0].sensorPeriod = declaredPeriod;
  s.arms[0].sensorJitter = declaredJitter;
  s.safety.latchStale = false;  // the watchdog alone (its latch: below)
  Monitor m = makeMonitor(s);
  std::mt19937_64 g(5);
  const std::vector<double> still(7, 0.0);
  Watch w;
  double next = 0.0;
  for (int k = 0; k <= 2000; ++k) {
    const double t = 0.001 * k;
    // readings arrive at the cycle after their stamp (the stamp itself jittered)
    while (next <= t && next < silentAt) {
      m.setJointState(0, std::max(next, w.lastReading), kHome.data(), still.data());
      w.lastReading = std::max(next, w.lastReading);
      const double u = static_cast<double>(g() >> 11) * 0x1.0p-53;
      next += period + (2.0 * u - 1.0) * jitter;
    }
    m.setJointState(1, t, kHome.data(), still.data());
    m.cycle(t);
    ++w.cycles;
    if (m.stopped(0)) {
      ++w.stopped;
      if (t >= silentAt && w.firstStopAfterSilence < 0) w.firstStopAfterSilence = t;
    }
    EXPECT_EQ(m.stale(0), m.stopped(0)) << "at rest, only the watchdog stops arm 0 (t = " << t << ")";
  }
  return w;
}

TEST(Monitor, DeclaredSensorRatesMeanNoSpuriousStopAndASilentSensorStillStops) {
  // 50 Hz joint states with +-3 ms jitter: undeclared (stale after reaction + cycle, 11 ms) the
  // arm is STOPped on about half the cycles; declared, never while the sensor talks
  const Watch undeclared = watch(0.02, 0.003, 0.0, 0.0, 10.0);
  EXPECT_GT(undeclared.stopped, undeclared.cycles / 3);
  const Watch declared = watch(0.02, 0.003, 0.02, 0.003, 1.5);
  EXPECT_GT(declared.firstStopAfterSilence, 0.0) << "the silent sensor was never stopped";
  // ... and once it falls silent, STOP within period + jitter + one cycle of its last reading,
  // and no earlier than period + jitter
  const double age = declared.firstStopAfterSilence - declared.lastReading;
  EXPECT_GT(age, 0.02 + 0.003 - 1e-9);
  EXPECT_LE(age, 0.02 + 0.003 + 0.001 + 1e-9);
  EXPECT_EQ(declared.stopped, static_cast<int>(std::lround((2.0 - declared.firstStopAfterSilence) / 0.001)) + 1)
      << "STOPs before the sensor fell silent";
}

// Arm 0's sensor keeps its own clock, running (1 + rate) times the monitor's: it reads every
// `period` +- `jitter` (uniform) of its own clock and stamps the reading with it; the reading
// arrives at the first monitor cycle at or after the monitor's time it was taken, plus `delay`
// from `delayFrom` on (a backlog). Silent from its own time `silentAt`. Both Pandas at rest.
struct DriftWatch {
  int stoppedTalking = 0, stoppedSilent = 0;
  double lastTaken = 0.0, lastArrival = 0.0, firstStopAfterSilence = -1.0, firstStop = -1.0;
  double staleAfter = 0.0;
};
DriftWatch driftWatch(double rate, double declaredDrift, double silentAt, double delay = 0.0, double delayFrom = 1e9,
                      bool repeatStamps = false) {
  Scenario s = loadScenario(scenarioPath("two_pandas"));
  s.arms[0].sensorPeriod = 0.02;
  s.arms[0].sensorJitter = 0.003;
  s.arms[0].sensorDrift = declaredDrift;
  s.safety.latchStale = false;
  Monitor m = makeMonitor(s);
  std::mt19937_64 g(7);
  const std::vector<double> still(7, 0.0);
  DriftWatch w;
  w.staleAfter = m.staleAfter(0);
  double next = 0.0;  // its own clock's time of its next reading
  bool silent = false;
  for (int k = 0; k <= 6000; ++k) {
    const double t = 0.001 * k;
    for (;;) {
      const double taken = next / (1.0 + rate);  // the monitor's time it is taken at
      const double arrives = taken + (taken >= delayFrom ? delay : 0.0);
      if (next >= silentAt) silent = true;
      if (silent || arrives > t) break;
      const double stamp = repeatStamps && taken >= delayFrom ? delayFrom * (1.0 + rate) : next;
      m.setJointState(0, stamp, kHome.data(), still.data());
      w.lastTaken = taken;
      w.lastArrival = t;
      const double u = static_cast<double>(g() >> 11) * 0x1.0p-53;
      next += 0.02 + (2.0 * u - 1.0) * 0.003;
    }
    m.setJointState(1, t, kHome.data(), still.data());
    m.cycle(t);
    EXPECT_EQ(m.stale(0), m.stopped(0)) << "at rest, only the watchdog stops arm 0 (t = " << t << ")";
    if (!m.stopped(0)) continue;
    if (w.firstStop < 0.0) w.firstStop = t;
    if (silent) {
      ++w.stoppedSilent;
      if (w.firstStopAfterSilence < 0.0) w.firstStopAfterSilence = t;
    } else {
      ++w.stoppedTalking;
    }
  }
  return w;
}

TEST(Monitor, ASensorClockTwoPerCentOffIsNoStopOnceItsDriftIsDeclared) {
  for (const double rate : {0.02, -0.02}) {
    SCOPED_TRACE(rate > 0 ? "its clock 2 % fast" : "its clock 2 % slow");
    // 50 Hz +- 3 ms declared, its clock's drift not: judged by its stamps, the clocks part by
    // 20 ms a second and the arm is STOPped within about a second and a quarter (a slow clock's
    // longest gaps, 23 ms of its own, are 23.5 ms of the monitor's: its first STOP comes sooner),
    // and from then on on most cycles
    const DriftWatch undeclared = driftWatch(rate, 0.0, 100.0);
    EXPECT_GT(undeclared.stoppedTalking, 3000);
    EXPECT_LT(undeclared.firstStop, 1.5);
    // declared (drift: 0.02): 5.5 s, 275 readings, the clocks 110 ms apart at the end, no STOP ...
    const DriftWatch declared = driftWatch(rate, 0.02, 5.5 * (1.0 + rate));
    EXPECT_EQ(declared.stoppedTalking, 0);
    EXPECT_DOUBLE_EQ(declared.staleAfter, 0.023 * 1.02);
    // ... and silent, STOP within (period + jitter)(1 + drift) + one cycle of its last reading's
    // arrival, never before (period + jitter)(1 + drift) after it was taken
    ASSERT_GT(declared.firstStopAfterSilence, 0.0) << "the silent sensor was never stopped";
    EXPECT_LE(declared.firstStopAfterSilence - declared.lastArrival, declared.staleAfter + 0.001 + 1e-9);
    EXPECT_GT(declared.firstStopAfterSilence - declared.lastTaken, declared.staleAfter);
    EXPECT_EQ(declared.stoppedSilent, static_cast<int>(std::lround((6.0 - declared.firstStopAfterSilence) / 0.001)) + 1);
  }
}

TEST(Monitor, ADeclaredDriftStillAgesABacklogAndARepeatedStamp) {
  // from 2 s on, each reading arrives 50 ms after it is taken (a queue backs up): the sensor still
  // talks at its rate, but what it says is older than its period + jitter. STOP once the last
  // prompt reading is period + jitter old; it holds while the offset's envelope, rising at most
  // at the declared drift, has not taken the new delay up as drift: about (50 ms - 23.5 ms) /
  // 2 % = 1.3 s wholly, partly until 50 ms / 2 % = 2.5 s (the latch, on by default, holds it).
  const DriftWatch backlog = driftWatch(0.0, 0.02, 100.0, 0.05, 2.0);
  EXPECT_GT(backlog.firstStop, 2.0);
  EXPECT_LE(backlog.firstStop, 2.0 + backlog.staleAfter + 0.001 + 1e-9);
  EXPECT_GT(backlog.stoppedTalking, 1300) << "a backlog of 50 ms looked current";
  EXPECT_LT(backlog.stoppedTalking, 2600);
  // from 2 s on, the same stamp again and again (a sensor stuck on one reading): a repeat is no
  // news, so the arm is STOPped as if silent, and stays STOPped
  const DriftWatch stuck = driftWatch(0.02, 0.02, 100.0, 0.0, 2.0, true);
  EXPECT_GT(stuck.firstStop, 2.0);
  EXPECT_LE(stuck.firstStop, 2.0 + 0.024 + stuck.staleAfter + 0.001 + 1e-9);
  EXPECT_EQ(stuck.stoppedTalking, static_cast<int>(std::lround((6.0 - stuck.firstStop) / 0.001)) + 1);
}

TEST(Monitor, ASensorThatFellSilentHoldsItsStopUntilReset) {
  Monitor m = makeMonitor(loadScenario(scenarioPath("two_pandas")));
  const std::vector<double> still(7, 0.0);
  const auto tick = [&](double t, bool arm0) {
    if (arm0) m.setJointState(0, t, kHome.data(), still.data());
    m.setJointState(1, t, kHome.data(), still.data());
    m.cycle(t);
  };
  tick(0.0, true);
  EXPECT_FALSE(m.stopped(0));
  tick(0.012, false);  // 12 ms without arm 0: stale
  EXPECT_TRUE(m.stale(0));
  EXPECT_FALSE(m.reset(0)) << "reset while the sensor is still silent";
  tick(0.013, true);  // back: current, but held
  EXPECT_FALSE(m.stale(0));
  EXPECT_TRUE(m.latched(0));
  EXPECT_TRUE(m.stopped(0)) << "a silent sensor's STOP cleared itself";
  EXPECT_FALSE(m.stopped(1));
  EXPECT_TRUE(m.reset(0));
  tick(0.014, true);
  EXPECT_FALSE(m.stopped(0));
  // a sensor never heard from is STOP but does not latch: its first reading is enough
  Monitor fresh = makeMonitor(loadScenario(scenarioPath("two_pandas")));
  fresh.setJointState(1, 0.0, kHome.data(), still.data());
  fresh.cycle(0.0);
  EXPECT_TRUE(fresh.stopped(0));
  fresh.setJointState(0, 0.001, kHome.data(), still.data());
  fresh.setJointState(1, 0.001, kHome.data(), still.data());
  fresh.cycle(0.001);
  EXPECT_FALSE(fresh.stopped(0));
}

TEST(Monitor, AnArmNeverReadIsStopped) {
  Monitor m = makeMonitor(loadScenario(scenarioPath("two_pandas")));
  const std::vector<double> still(7, 0.0);
  m.setJointState(1, 0.0, kHome.data(), still.data());
  m.cycle(0.0);
  EXPECT_TRUE(m.stopped(0));
  EXPECT_TRUE(m.stale(0));
  EXPECT_FALSE(m.stopped(1));
  EXPECT_EQ(m.counters().staleStops, 1u);
}

}  // namespace
}  // namespace st::arm

namespace st::arm {
namespace {

// The octree depth for a scenario without octree.max_depth: leaves about the moving objects' size.
TEST(DepthFromScene, LeavesAboutTheMovingObjectsSize) {
  const Aabb3 b{Vec3::Zero(), Vec3(3.2, 1.0, 1.0)};
  EXPECT_EQ(depthFromScene(b, {0.2, 0.1, 0.4}), 4);        // 3.2 / 0.2 = 16
  EXPECT_EQ(depthFromScene(b, {0.3, 0.3, 0.1, 5.0}), 3);   // median 0.3: log2 10.7 = 3.4
  EXPECT_EQ(depthFromScene(b, {3.0}), 2);                  // never shallower than 2
  EXPECT_EQ(depthFromScene(b, {1e-4}), 8);                 // never deeper than the old default
  EXPECT_EQ(depthFromScene(b, {}), 8);                     // nothing moves
}

TEST(DepthFromScene, ScenarioWithoutTheKeyChoosesIt) {
  Scenario s = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/two_pandas.yaml");
  EXPECT_FALSE(s.broad.depthFromScene);  // the file sets max_depth: 4
  s.broad = BroadphaseConfig{};
  const Monitor m = makeMonitor(s);
  EXPECT_EQ(m.space()->rule().maxDepth, 4);
}

}  // namespace
}  // namespace st::arm
