// Closed loop: a STOP brakes the arm along its path. The profile against its analytic stopping
// distance, resume rules, and the two Pandas: open loop they touch, closed loop they do not
// (brute-force distances of every capsule pair, not the monitor's own bookkeeping).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <starm/study.hpp>

namespace st::arm {
namespace {

std::string scenarioPath(const std::string& name) {
  return std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/" + name + ".yaml";
}

TEST(Ramp, IntegralIsExactAcrossTheKinks) {
  const Ramp r{1.0, 1.0, -5.0};  // brakes from 1 at t = 1 to 0 at t = 1.2
  EXPECT_DOUBLE_EQ(r.at(0.5), 1.0);
  EXPECT_NEAR(r.at(1.1), 0.5, 1e-15);
  EXPECT_DOUBLE_EQ(r.at(2.0), 0.0);
  // brute force: midpoint sums
  auto sum = [&](double a, double b) {
    const int n = 200000;
    double s = 0;
    for (int k = 0; k < n; ++k) s += r.at(a + (k + 0.5) * (b - a) / n) * (b - a) / n;
    return s;
  };
  for (auto [a, b] : {std::pair{0.0, 2.0}, {0.9, 1.05}, {1.05, 1.15}, {1.1, 3.0}, {0.0, 1.0}})
    EXPECT_NEAR(r.integral(a, b), sum(a, b), 1e-9) << a << " " << b;
  EXPECT_NEAR(r.integral(0.0, 2.0), 1.0 + 0.1, 1e-15);
}

// A joint path at constant rate w from tau = 0; STOP seen at t0. Steps at dt, returns tau at the end.
struct Braked {
  double tau = 0.0;
  std::vector<double> speed;  // s per cycle
};
Braked brake(const BrakeConfig& cfg, double dt, double t0, double until, double w = 1.0) {
  ArmDrive d(cfg);
  Braked b;
  for (long k = 0;; ++k) {
    const double t = static_cast<double>(k) * dt;
    if (t > until) break;
    b.tau = d.advance(t);
    b.speed.push_back(d.speed());
    d.observe(t, std::abs(t - t0) < 0.5 * dt, std::abs(t - t0) < 0.5 * dt, w);
  }
  return b;
}

TEST(ArmDrive, StopsAtTheAnalyticStoppingDistance) {
  // w * (t0 + delay) at full speed, then w * T / 2 while braking at constant deceleration w / T
  BrakeConfig cfg;
  cfg.stoppingTime = 0.2;
  cfg.delay = 0.01;
  const double dt = 0.001, t0 = 0.5;
  const Braked b = brake(cfg, dt, t0, 2.0);
  EXPECT_NEAR(b.tau, t0 + cfg.delay + 0.5 * cfg.stoppingTime, 1e-12);
  // the joint rate (w s) falls by w dt / T every braking cycle: constant deceleration, then rest
  const int first = static_cast<int>(std::lround((t0 + cfg.delay) / dt));
  for (int k = first + 1; k < first + 200; ++k) EXPECT_NEAR(b.speed[k - 1] - b.speed[k], dt / cfg.stoppingTime, 1e-9) << k;
  for (int k = first + 200; k < static_cast<int>(b.speed.size()); ++k) EXPECT_EQ(b.speed[k], 0.0);
  for (int k = 0; k <= first; ++k) EXPECT_EQ(b.speed[k], 1.0);
}

TEST(ArmDrive, DecelerationSetsTheStoppingTime) {
  // 2 rad/s at 5 rad/s^2: 0.4 s to rest, 0.4 rad of braking travel (w^2 / 2a)
  BrakeConfig cfg;
  cfg.deceleration = 5.0;
  cfg.delay = 0.0;
  const double w = 2.0, t0 = 0.3;
  const Braked b = brake(cfg, 0.001, t0, 2.0, w);
  // tau is program time at unit rate; the joint travels w * tau
  EXPECT_NEAR(w * b.tau, w * t0 + w * w / (2 * cfg.deceleration), 1e-12);
}

// stops in 0.1 s with no delay and resumes 0.25 s after the threat clears
BrakeConfig quickBrakes() {
  BrakeConfig cfg;
  cfg.stoppingTime = 0.1;
  cfg.delay = 0.0;
  cfg.resumeAfter = 0.25;
  return cfg;
}

TEST(ArmDrive, ResumesAfterTheThreatClears) {
  BrakeConfig cfg = quickBrakes();
  ArmDrive d(cfg);
  const double dt = 0.001;
  double t = 0;
  for (long k = 0; k <= 3000; ++k) {
    t = static_cast<double>(k) * dt;
    d.advance(t);
    // a threat from 0.5 s to 0.6 s
    const bool threat = t >= 0.5 - 1e-12 && t < 0.6 - 1e-12;
    d.observe(t, threat, threat, 1.0);
  }
  EXPECT_EQ(d.stops(), 1);
  EXPECT_EQ(d.resumes(), 1);
  EXPECT_EQ(d.mode(), DriveMode::Following);
  // lost program time: T/2 braking + standstill from 0.6 (rest) to 0.6 + clear time, + T/2 ramping up
  const double lastThreat = 0.599, resumeAt = lastThreat + cfg.resumeAfter;
  const double lost = 0.5 * cfg.stoppingTime + (resumeAt - 0.6) + 0.5 * cfg.stoppingTime;
  EXPECT_NEAR(t - d.tau(), lost, 1.5e-3);
  // and never resumes under the default rule
  cfg.resumeAfter = BrakeConfig{}.resumeAfter;
  ArmDrive never(cfg);
  for (long k = 0; k <= 3000; ++k) {
    t = static_cast<double>(k) * dt;
    never.advance(t);
    never.observe(t, k == 500, k == 500, 1.0);
  }
  EXPECT_EQ(never.mode(), DriveMode::Stopped);
  EXPECT_NEAR(never.tau(), 0.5 + 0.05, 1e-12);
}

TEST(ArmDrive, AGradedStopResumesWhenUnblockedWithoutTheHold) {
  // a STOP at 0.5 s blocked (a graded check allows no motion) until 0.6 s and never a warning:
  // the arm stands until 0.6 s, then goes at once, not braking.resume (0.25 s) later
  BrakeConfig cfg = quickBrakes();
  ArmDrive d(cfg);
  const double dt = 0.001;
  double t = 0, resumedAt = -1;
  for (long k = 0; k <= 3000; ++k) {
    t = static_cast<double>(k) * dt;
    d.advance(t);
    const bool blocked = t >= 0.5 - 1e-12 && t < 0.6 - 1e-12;
    const int before = d.resumes();
    d.observe(t, false, blocked, 1.0, blocked);
    if (d.resumes() > before && resumedAt < 0) resumedAt = t;
  }
  EXPECT_EQ(d.stops(), 1);
  EXPECT_EQ(d.resumes(), 1);
  EXPECT_NEAR(resumedAt, 0.6, 1e-9);
  // lost: T/2 braking from 0.5, standstill from 0.6 (rest) to 0.6, T/2 ramping up
  EXPECT_NEAR(t - d.tau(), cfg.stoppingTime, 1.5e-3);
  // the same STOP as a threat (warned) waits braking.resume after it
  ArmDrive held(cfg);
  resumedAt = -1;
  for (long k = 0; k <= 3000; ++k) {
    t = static_cast<double>(k) * dt;
    held.advance(t);
    const bool threat = t >= 0.5 - 1e-12 && t < 0.6 - 1e-12;
    const int before = held.resumes();
    held.observe(t, threat, threat, 1.0);
    if (held.resumes() > before && resumedAt < 0) resumedAt = t;
  }
  EXPECT_NEAR(resumedAt, 0.599 + cfg.resumeAfter, 1e-9);
}

// Brute force over the run: the smallest exact distance of any pair the monitor must check
// (arm-arm, self pairs outside the allowed matrix, arm-obstacle), and the first time it is <= 0.
struct Truth {
  double minDistance = INFINITY;
  double firstContact = NAN;
  std::vector<double> finalRates;  // max |qdot| per arm in the last reading
};

Truth bruteForce(const Scenario& s, bool closedLoop) {
  Monitor m = makeMonitor(s);
  std::unique_ptr<ClosedLoopSensor> closed;
  std::unique_ptr<SensorSource> open;
  if (closedLoop) closed = makeClosedLoopSensor(s);
  else open = makeSensor(s);
  SensorSource& src = closedLoop ? static_cast<SensorSource&>(*closed) : *open;
  Truth tr;
  tr.finalRates.assign(m.armCount(), 0.0);
  RunStats st;
  run(m, src, st, [&](const Monitor& mon) {
    if (closed) closed->observe(mon, mon.time());
    double d = INFINITY;
    for (int i = 0; i < mon.capsuleCount(); ++i) {
      const Capsule ci = mon.movingCapsule(i).c;
      for (int j = i + 1; j < mon.capsuleCount(); ++j) {
        if (mon.capsuleArm(i) == mon.capsuleArm(j) &&
            mon.arm(mon.capsuleArm(i)).model.isAllowed(mon.capsuleBody(i), mon.capsuleBody(j)))
          continue;
        d = std::min(d, distance(ci, mon.movingCapsule(j).c));
      }
      for (const Obstacle& o : mon.obstacles()) {
        ASSERT_FALSE(o.moving());
        switch (o.kind) {
          case ShapeKind::Sphere: d = std::min(d, distance(ci, o.sphere)); break;
          case ShapeKind::Capsule: d = std::min(d, distance(ci, o.capsule)); break;
          case ShapeKind::Box: d = std::min(d, distance(ci, o.box)); break;
        }
      }
    }
    tr.minDistance = std::min(tr.minDistance, d);
    if (std::isnan(tr.firstContact) && d <= 0.0) tr.firstContact = mon.time();
  });
  if (closed)
    for (int a = 0; a < m.armCount(); ++a) tr.finalRates[a] = closed->drive(a).speed();
  return tr;
}

TEST(ClosedLoop, TwoPandasTouchOpenLoopButNotClosedLoop) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  const Truth open = bruteForce(s, false);
  ASSERT_FALSE(std::isnan(open.firstContact));
  EXPECT_NEAR(open.firstContact, 1.33, 0.01);
  const Truth closed = bruteForce(s, true);
  EXPECT_TRUE(std::isnan(closed.firstContact)) << "closed loop touched at " << closed.firstContact;
  EXPECT_GT(closed.minDistance, 0.0);
  // both arms came to rest (no resume rule in the scenario)
  for (double sp : closed.finalRates) EXPECT_EQ(sp, 0.0);
  // the monitor's own watch agrees with brute force
  const CourseOutcome o = runCourse(s, false), c = runCourse(s, true);
  EXPECT_TRUE(o.contact);
  EXPECT_NEAR(o.firstContact, open.firstContact, 1e-12);
  EXPECT_FALSE(c.contact);
  // the monitor tests only pairs that can come within the separation: its minimum is never below the truth
  EXPECT_GE(c.minDistance, closed.minDistance - 1e-12);
  std::printf("two pandas: open loop contact at %.3f s; closed loop min distance %.4f m\n", open.firstContact,
              closed.minDistance);
}

TEST(ClosedLoop, SafeTimeShorterThanTheStopFails) {
  // the monitor assumes no braking time, the arms need 0.4 s: STOP comes too late
  Scenario s = loadScenario(scenarioPath("two_pandas"));
  s.safety.stoppingTime = 0.0;
  s.braking.stoppingTime = 0.4;
  const Truth t = bruteForce(s, true);
  EXPECT_FALSE(std::isnan(t.firstContact));
}

TEST(ClosedLoop, RandomCoursesAgreeWithBruteForce) {
  int contacts = 0;
  for (int i = 0; i < 4; ++i) {
    Scenario s = randomCourse(7, i);
    for (bool closed : {false, true}) {
      const Truth t = bruteForce(s, closed);
      const CourseOutcome c = runCourse(s, closed);
      EXPECT_EQ(c.contact, !std::isnan(t.firstContact)) << i << " closed " << closed;
      if (c.contact) {
        EXPECT_NEAR(c.firstContact, t.firstContact, 1e-12);
      }
      // the monitor sees only pairs near enough to matter; where it sees the minimum it is exact
      if (t.minDistance < s.safety.minSeparation) {
        EXPECT_NEAR(c.minDistance, t.minDistance, 1e-12);
      }
      contacts += c.contact ? 1 : 0;
    }
  }
  EXPECT_GT(contacts, 0) << "the random family must produce contacts for the study to mean something";
}

TEST(Study, NoContactWhenTheSafeTimeCoversTheStop) {
  StudyConfig cfg;
  cfg.randomCourses = 12;
  cfg.seed = 3;
  cfg.stoppingTime = 0.2;
  cfg.assumedStopping = {0.0, 0.2};
  const StudyResult r = stoppingStudy(cfg);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_GT(r.randomContactsOpen, 3);
  EXPECT_GT(r.rows[0].contactsClosed, 0) << "no braking time assumed: some STOPs must come too late";
  for (int k : {1}) {
    EXPECT_GE(r.rows[k].safeTime + 1e-12, r.rows[k].needed);
    EXPECT_EQ(r.rows[k].contactsClosed, 0) << r.rows[k].assumedStopping;
    EXPECT_GT(r.rows[k].minDistanceClosed, 0.0);
  }
}

TEST(Scenario, BrakingKeys) {
  namespace fs = std::filesystem;
  const fs::path p = fs::temp_directory_path() / ("stsim_arm_brk_" + std::to_string(::getpid()) + ".yaml");
  auto load = [&](const std::string& braking) {
    std::ofstream(p) << "safety: {reaction_time: 0.02, stopping_time: 0.3}\n" << braking
                     << "arms:\n  - {name: a, model: panda, waypoints: [{t: 0, q: [0, 0, 0, -1, 0, 1, 0]}]}\n";
    return loadScenario(p.string());
  };
  Scenario s = load("");
  EXPECT_EQ(s.braking.stoppingTime, 0.3);
  EXPECT_EQ(s.braking.delay, 0.02);
  EXPECT_FALSE(s.braking.resumes());
  s = load("braking: {deceleration: 6, delay: 0.005, resume: 0.5}\n");
  EXPECT_EQ(s.braking.deceleration, 6.0);
  EXPECT_EQ(s.braking.delay, 0.005);
  EXPECT_EQ(s.braking.resumeAfter, 0.5);
  s = load("braking: {stopping_time: 0.1, resume: never}\n");
  EXPECT_EQ(s.braking.stoppingTime, 0.1);
  EXPECT_FALSE(s.braking.resumes());
  auto error = [&](const std::string& b) {
    try {
      load(b);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("braking: {stopping_time: 0.1, deceleration: 3}\n").find(":2: braking.deceleration: give either"),
            std::string::npos);
  EXPECT_NE(error("braking: {resume: sometimes}\n").find(":2: braking.resume: must be a number or never, got 'sometimes'"), std::string::npos);
  EXPECT_NE(error("braking: {stoping_time: 0.1}\n").find("braking.stoping_time: unknown key"), std::string::npos);
  EXPECT_NE(error("braking: {delay: -1}\n").find("braking.delay: must not be negative"), std::string::npos);
  fs::remove(p);
}

}  // namespace
}  // namespace st::arm
