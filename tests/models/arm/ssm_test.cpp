// Persons and speed and separation monitoring (ISO/TS 15066 §5.5.4), against independent truth:
// S_p terms worked out by hand from formulae (1)-(4), verdict transitions of a person walking at
// constant speed towards a post at times solved from the geometry, person-arm separation against
// brute-force sampling, the reachable set against sampled motions, and the closed loop never
// letting a person touch a moving arm.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <starm/study.hpp>

namespace st::arm {
namespace {

namespace fs = std::filesystem;

std::string scenarioPath(const std::string& name) {
  return std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/" + name + ".yaml";
}

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("stsim_arm_ssm_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

TEST(Ssm, TermsEqualTheStandardsFormulaeByHand) {
  // (a) the defaults: T_r = 0.011, T_s = 0.2, C = 0, Z_d = 0.05, Z_r = 0.01; walking, robot 1 m/s
  SsmConfig a;
  SeparationTerms t = protectiveSeparation(a, 1.6, 1.0);
  EXPECT_NEAR(t.sh, 0.3376, 1e-15);  // 1.6 * (0.011 + 0.2)
  EXPECT_NEAR(t.sr, 0.011, 1e-15);   // 1.0 * 0.011
  EXPECT_NEAR(t.ss, 0.1, 1e-15);     // 1.0 * 0.2 / 2
  EXPECT_NEAR(t.total(), 0.5086, 1e-15);
  EXPECT_STREQ(t.dominant(), "S_h");
  // (b) a slow drive: T_r = 0.1, T_s = 0.5, C = 0.2, Z_d = 0.1, Z_r = 0.02; a hand, robot 0.5 m/s
  SsmConfig b;
  b.reactionTime = 0.1;
  b.stoppingTime = 0.5;
  b.intrusion = 0.2;
  b.personUncertainty = 0.1;
  b.robotUncertainty = 0.02;
  t = protectiveSeparation(b, 2.0, 0.5);
  EXPECT_NEAR(t.sh, 1.2, 1e-15);     // 2.0 * 0.6
  EXPECT_NEAR(t.sr, 0.05, 1e-15);    // 0.5 * 0.1
  EXPECT_NEAR(t.ss, 0.125, 1e-15);   // 0.5 * 0.5 / 2
  EXPECT_NEAR(t.total(), 1.695, 1e-14);
  // (c) a light curtain's intrusion (ISO 13855, 850 mm), no uncertainties, a fast robot
  SsmConfig c;
  c.reactionTime = 0.05;
  c.stoppingTime = 0.3;
  c.intrusion = 0.85;
  c.personUncertainty = 0.0;
  c.robotUncertainty = 0.0;
  t = protectiveSeparation(c, 1.6, 2.0);
  EXPECT_NEAR(t.sh, 0.56, 1e-15);   // 1.6 * 0.35
  EXPECT_NEAR(t.sr, 0.1, 1e-15);    // 2.0 * 0.05
  EXPECT_NEAR(t.ss, 0.3, 1e-15);    // 2.0 * 0.3 / 2
  EXPECT_NEAR(t.total(), 1.81, 1e-14);
  EXPECT_STREQ(t.dominant(), "C");
  // the speed that keeps S_p at the next cycle, (a) at 0.8 m: room 0.8 - 1.6 * 0.001 - (0.3376 + 0.06),
  // per m/s 0.011 + 0.1 + 0.001
  EXPECT_NEAR(allowedRobotSpeed(a, 1.6, 0.8), 0.4008 / 0.112, 1e-12);
  // and at that speed S_p after one cycle of both closing is exactly the distance left
  const double v = allowedRobotSpeed(a, 1.6, 0.8);
  EXPECT_NEAR(protectiveSeparation(a, 1.6, v).total(), 0.8 - (1.6 + v) * 0.001, 1e-12);
  EXPECT_LT(allowedRobotSpeed(a, 2.0, 0.4), 0.0);  // within S_h + Z of a hand: no speed
}

TEST(Person, ReachableCapsuleHoldsEverySampledMotion) {
  // end points moving at most v (any direction, changing every 10 ms): every point of the moved
  // capsule stays inside the capsule grown by v t
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  auto unit = [&] {
    Vec3 d(u(rng), u(rng), u(rng));
    while (d.norm() < 1e-3) d = Vec3(u(rng), u(rng), u(rng));
    return Vec3(d.normalized());
  };
  for (int trial = 0; trial < 2000; ++trial) {
    const Capsule c0{Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), 0.02 + 0.1 * u01(rng)};
    const double v = trial % 2 ? 2.0 : 1.6, T = 0.211;
    Vec3 a = c0.a, b = c0.b;
    for (double t = 0.0; t < T;) {
      const double dt = std::min(0.01, T - t);
      a += unit() * (v * u01(rng) * dt);
      b += unit() * (v * u01(rng) * dt);
      t += dt;
      const Capsule grown = reachable(c0, v, t);
      for (int k = 0; k < 20; ++k) {
        const double s = u01(rng);
        const Vec3 p = a + s * (b - a) + unit() * c0.radius;  // on the moved capsule's surface
        // distance from p to the original axis
        const Vec3 ab = c0.b - c0.a;
        const double w = std::clamp((p - c0.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        ASSERT_LE((p - (c0.a + w * ab)).norm(), grown.radius + 1e-12) << trial;
      }
    }
  }
}

// A post (one capsule, 0..1.5 m high, radius 0.1) at the origin and a person walking at 1 m/s
// along x towards it from x = 3. Each body part's distance to the post is worked out from the
// standing pose (all parts beside the post's height): head x - 0.21, torso x - 0.27, upper arm
// sqrt(x^2 + 0.2^2) - 0.15, lower arm sqrt(x^2 + 0.22^2) - 0.14, hand sqrt(x^2 + 0.22^2) - 0.15,
// thigh sqrt(x^2 + 0.1^2) - 0.18, lower leg sqrt(x^2 + 0.1^2) - 0.16.
struct PostWalk {
  static constexpr double x0 = 3.0, speed = 1.0, dt = 0.001;
  // the largest x at which some part's distance is below its own threshold R(vh)
  static double crossing(const std::function<double(double vh)>& R) {
    const double body = R(1.6), hand = R(2.0);
    auto radial = [](double r, double y, double c) { return std::sqrt((r + c) * (r + c) - y * y); };
    return std::max({body + 0.21, body + 0.27, radial(body, 0.2, 0.15), radial(body, 0.22, 0.14), radial(hand, 0.22, 0.15),
                     radial(body, 0.1, 0.18), radial(body, 0.1, 0.16)});
  }
  // first cycle time at which pred(verdict) holds
  static double first(SsmResponse response, const std::function<bool(const SsmVerdict&)>& pred, SsmConfig cfg) {
    ArmModel m;
    m.name = "post";
    m.joints = {{0, 0, 0.1, 0, -1, 1}};
    m.capsules = {{0, {0, 0, 0}, {0, 0, 1.5}, 0.1}};
    m.resetAllowedToAdjacent();
    Monitor mon({ArmInstance{"post", m, Eigen::Isometry3d::Identity()}}, {}, SafetyConfig{});
    PersonScript script;
    script.start = Vec3(x0, 0, 0);
    script.heading = M_PI;
    script.actions = {{PersonAction::Walk, Vec3(0.0, 0, 0), speed, 0.0, true}};
    PersonSet persons;
    persons.add("walker", std::make_unique<ScriptedPerson>(script));
    cfg.response = response;
    SeparationMonitor ssm(cfg, 1);
    const double q = 0.0, qd = 0.0;
    for (long k = 0; k < 3000; ++k) {
      const double t = static_cast<double>(k) * dt;
      mon.setJointState(0, t, &q, &qd);
      mon.cycle(t);
      persons.pose(t);
      ssm.cycle(mon, persons);
      if (pred(ssm.verdict(0))) return t;
    }
    return NAN;
  }
};

TEST(Ssm, WalkingPersonTransitionsAtTheSolvedTimes) {
  SsmConfig cfg;
  cfg.robotSpeed = 1.1;
  const double P = cfg.reactionTime + cfg.stoppingTime / 2.0 + cfg.cycleTime;
  auto S0 = [&](double vh) { return vh * (cfg.reactionTime + cfg.stoppingTime) + cfg.personUncertainty + cfg.robotUncertainty; };
  auto expectAt = [&](double xStar, double t, const char* what) {
    const double tStar = (PostWalk::x0 - xStar) / PostWalk::speed;
    // the first cycle past the crossing (d < threshold from there on)
    EXPECT_GT(t, tStar - 1e-9) << what;
    EXPECT_LE(t, tStar + PostWalk::dt + 1e-9) << what << " solved " << tStar;
  };
  // binary: STOP below S_p at the arm's top speed (the post stands still, v_r = 0)
  expectAt(PostWalk::crossing([&](double vh) { return S0(vh) + 1.1 * (cfg.reactionTime + cfg.stoppingTime / 2.0); }),
           PostWalk::first(SsmResponse::Stop, [](const SsmVerdict& v) { return v.stop; }, cfg), "binary STOP");
  // scaling: slowing where the top speed no longer keeps S_p at the next cycle, at rest where no
  // speed does, STOP only below S_p at rest
  expectAt(PostWalk::crossing([&](double vh) { return S0(vh) + vh * cfg.cycleTime + 1.1 * P; }),
           PostWalk::first(SsmResponse::Scaling, [](const SsmVerdict& v) { return v.factor < 1.0; }, cfg), "scaling");
  expectAt(PostWalk::crossing([&](double vh) { return S0(vh) + vh * cfg.cycleTime; }),
           PostWalk::first(SsmResponse::Scaling, [](const SsmVerdict& v) { return v.factor == 0.0; }, cfg), "factor 0");
  expectAt(PostWalk::crossing(S0), PostWalk::first(SsmResponse::Scaling, [](const SsmVerdict& v) { return v.stop; }, cfg),
           "scaling STOP");
}

// minimum over sampled point pairs of two capsules' axes, minus the radii
double sampledDistance(const Capsule& a, const Capsule& b, int n) {
  double best = INFINITY;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = a.a + (static_cast<double>(i) / (n - 1)) * (a.b - a.a);
    for (int j = 0; j < n; ++j) {
      const Vec3 q = b.a + (static_cast<double>(j) / (n - 1)) * (b.b - b.a);
      best = std::min(best, (p - q).norm());
    }
  }
  return std::max(0.0, best - a.radius - b.radius);
}

TEST(Ssm, SeparationEqualsBruteForceSampling) {
  // a Panda at random poses, a person at random places reaching at random points
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Monitor mon({ArmInstance{"panda", pandaModel(), Eigen::Isometry3d::Identity()}}, {}, SafetyConfig{});
  const ArmModel& pm = mon.arm(0).model;
  constexpr int n = 301;
  for (int trial = 0; trial < 12; ++trial) {
    std::vector<double> q(7), qd(7, 0.0);
    for (int k = 0; k < 7; ++k) q[k] = 0.5 * (pm.joints[k].lower + pm.joints[k].upper) + 0.4 * u(rng);
    mon.setJointState(0, trial, q.data(), qd.data());
    mon.cycle(trial);
    PersonScript s;
    s.start = Vec3(0.9 + 0.4 * u(rng), 0.6 * u(rng), 0);
    s.heading = M_PI + 0.5 * u(rng);
    s.actions = {{PersonAction::Reach, Vec3(0.4 + 0.2 * u(rng), 0.3 * u(rng), 0.6 + 0.3 * u(rng)), 2.0, 0.0, trial % 2 == 0}};
    PersonSet persons;
    persons.add("p", std::make_unique<ScriptedPerson>(s));
    persons.pose(10.0);  // reach done
    SeparationMonitor ssm(SsmConfig{}, 1);
    ssm.cycle(mon, persons);
    double brute = INFINITY, bound = 0.0;
    const auto body = bodyCapsules(persons.skeleton(0));
    for (int i = 0; i < mon.capsuleCount(); ++i)
      for (const Capsule& pc : body) {
        const Capsule ac = mon.movingCapsule(i).c;
        const double d = sampledDistance(ac, pc, n);
        // the true closest pair lies within half a sample step of a sampled one on each axis
        const double err = 0.5 * ((ac.b - ac.a).norm() + (pc.b - pc.a).norm()) / (n - 1);
        if (d < brute) brute = d, bound = err;
      }
    EXPECT_LE(ssm.verdict(0).separation, brute + 1e-12) << trial;
    EXPECT_GE(ssm.verdict(0).separation, brute - bound - 1e-12) << trial;
  }
}

TEST(ArmDrive, ScalingFollowsTheFactorAtTheBrakingRate) {
  BrakeConfig cfg;
  cfg.stoppingTime = 0.2;
  cfg.delay = 0.01;
  ArmDrive d(cfg);
  double tau = 0.0;
  for (long k = 0; k <= 2000; ++k) {
    const double t = static_cast<double>(k) * 0.001;
    tau = d.advance(t);
    if (k == 1000) {
      // s = 1 until 0.51, down to 0.5 at 0.61: tau = 0.51 + 0.075 + 0.5 (1.0 - 0.61)
      EXPECT_NEAR(tau, 0.78, 1e-12);
      EXPECT_NEAR(d.speed(), 0.5, 1e-12);
      EXPECT_EQ(d.mode(), DriveMode::Scaled);
    }
    if (k == 500) d.limit(t, 0.5);
    if (k == 1000) d.limit(t, 1.0);
  }
  // back up from 1.01 to 1 at 1.11: tau = 0.78 + 0.005 + 0.075 + 0.89
  EXPECT_NEAR(tau, 1.75, 1e-12);
  EXPECT_EQ(d.mode(), DriveMode::Following);
  EXPECT_DOUBLE_EQ(d.speed(), 1.0);
  // a STOP while scaled brakes from the scaled speed
  ArmDrive e(cfg);
  for (long k = 0; k <= 1000; ++k) {
    const double t = static_cast<double>(k) * 0.001;
    e.advance(t);
    if (k == 100) e.limit(t, 0.5);
    if (k == 500) e.observe(t, true, true, 1.0);
  }
  EXPECT_EQ(e.mode(), DriveMode::Stopped);
  EXPECT_EQ(e.speed(), 0.0);
}

TEST(Ssm, ClosedLoopNoPersonTouchesAMovingArm) {
  // every shipped person scenario (walking up, walking past, reaching at 2.0 and 1.6 m/s), both responses
  for (const char* name : {"person_walkup", "person_walkpast", "person_reach"}) {
    const Scenario s = loadScenario(scenarioPath(name));
    ASSERT_EQ(s.persons.size(), 1u);
    double progress[2] = {0, 0};
    int k = 0;
    for (SsmResponse r : {SsmResponse::Stop, SsmResponse::Scaling}) {
      std::uint64_t unstopped = 0, cycles = 0;
      double minSep = INFINITY;
      const CoexistenceOutcome o = runCoexistence(s, r, [&](const Monitor&, const SeparationMonitor& ssm) {
        ++cycles;
        const SsmVerdict& v = ssm.verdict(0);
        // S_p is never broken at the arm's speed without a STOP verdict that cycle
        if (v.violated && !v.stop) ++unstopped;
        minSep = std::min(minSep, v.separation);
      });
      EXPECT_EQ(o.contacts, 0u) << name << " " << toString(r);
      EXPECT_EQ(unstopped, 0u) << name << " " << toString(r);
      EXPECT_GT(minSep, 0.2) << name << " " << toString(r);  // far from contact
      EXPECT_EQ(o.cycles, cycles);
      progress[k++] = o.progress;
    }
    // scaling never does worse than the binary STOP; where the person works at the table it keeps
    // the arm going while binary STOP parks it
    EXPECT_GE(progress[1], progress[0]) << name;
    EXPECT_LE(progress[1], 1.0 + 1e-12);
    if (std::string(name) != "person_walkpast") {
      EXPECT_GE(progress[1] / progress[0], 1.4) << name << " " << progress[0] << " " << progress[1];
    }
  }
}

TEST(Person, CsvTraceIsInterpolatedBetweenLines) {
  auto row = [](double t, const Skeleton& s) {
    std::ostringstream r;
    r << t << ",worker";
    for (const Vec3& p : s.p) r << ',' << p.x() << ',' << p.y() << ',' << p.z();
    r << '\n';
    return r.str();
  };
  const fs::path csv = write("walk.csv", "# two readings of one person\n" + row(0.0, standingSkeleton(Vec3(2, 0, 0), M_PI)) +
                                             row(1.0, standingSkeleton(Vec3(1, 0, 0), M_PI)));
  const CsvPersonTrace trace(csv.string(), {"worker"});
  TracedPerson person(trace.rows(0));
  Skeleton s;
  EXPECT_FALSE(person.at(-0.5, s));  // before its first reading: not there
  ASSERT_TRUE(person.at(0.5, s));
  const Skeleton mid = standingSkeleton(Vec3(1.5, 0, 0), M_PI);
  for (int j = 0; j < kSkeletonJoints; ++j) EXPECT_LT((s.p[j] - mid.p[j]).norm(), 1e-6) << jointName(j);
  ASSERT_TRUE(person.at(5.0, s));  // after the last: stays
  EXPECT_NEAR(s.p[kPelvis].x(), 1.0, 1e-6);
  fs::remove(csv);
}

void expectError(const std::string& name, const std::string& yaml, const std::string& mention) {
  const fs::path p = write(name, yaml);
  try {
    const Scenario s = loadScenario(p.string());
    makePersons(s);
    ADD_FAILURE() << name << ": no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
  fs::remove(p);
}

TEST(Ssm, BadPersonInputIsNamed) {
  const std::string arm = "arms:\n  - {name: a, model: panda, waypoints: [{t: 0, q: [0, 0, 0, -1, 0, 1, 0]}]}\n";
  expectError("fast.yaml", arm + "persons:\n  - {name: p, start: {xy: [2, 0]}, script: [{walk: {to: [1, 0], speed: 3}}]}\n",
              ":4: persons[0].script[0].walk.speed: 3 m/s is beyond ssm.body_speed 1.6 m/s");
  expectError("resp.yaml", arm + "ssm: {response: maybe}\n", ":3: ssm.response: expected stop or scaling");
  expectError("nostart.yaml", arm + "persons:\n  - {name: p, script: []}\n", "persons[0].start: missing");
  expectError("hand.yaml", arm + "persons:\n  - {start: {xy: [2, 0]}, script: [{reach: {hand: third, to: [1, 0, 1], speed: 1}}]}\n",
              "persons[0].script[0].reach.hand: expected right or left");
  expectError("jitter.yaml", arm + "persons:\n  - {start: {xy: [2, 0]}, sensor: {period: 0.033, jitter: 0.05}}\n",
              "persons[0].sensor.jitter: must be at least 0 and less than the period");
  const fs::path csv = write("trace.csv", "t,person\n0,p\n");
  expectError("traced.yaml", arm + "persons:\n  - {name: p, trace: " + csv.string() + "}\n", csv.string() + ":2: expected t, person");
  fs::remove(csv);
}

}  // namespace
}  // namespace st::arm
