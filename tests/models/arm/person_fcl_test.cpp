// Person-arm separation against FCL (an independent implementation, test-only): the capsules of
// persons posed from skeletons (bodyCapsules, as the monitor poses them) and their reachable sets
// over T_r + T_s (grown by v_h (T_r + T_s): S_h, formula (2)) against the capsules of every
// shipped scenario's arms at deterministic random poses. Each pair's distance (stcore's kernel,
// what SeparationMonitor measures) against fcl::distance on fcl::Capsule with transforms, and each
// cycle's verdict (separation, slack to S_p) and the run's minimum separation against the same
// figures built from FCL's pairs. Overlap is as the monitor defines it: distance 0, no
// penetration depth; FCL's capsule-capsule distance (|axes| - r1 - r2, negative on overlap) tells
// the overlapping pairs apart, and its GJK collision check agrees away from contact.
// FCL is required where this directory is configured (find_package(fcl REQUIRED), as for the
// stcore kernels' and the arm benchmark's comparisons): without it the configure fails naming
// it, so this test never passes for want of FCL.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>

#include <fcl/geometry/shape/capsule.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <stcore/distance.hpp>
#include <starm/scenario.hpp>

namespace st::arm {
namespace {

namespace fs = std::filesystem;

// Agreement with FCL (m). Both sides solve the segment-segment problem in closed form in doubles,
// so they differ by roundoff (the stcore kernels agree with FCL to 8e-12 m on 1e5 random pairs,
// tests/stcore/distance_test.cpp). Measured here: 1.8e-10 m at most, FCL's side, on axes 1e-9 rad
// apart (it divides by their vanishing determinant; stcore is within 1e-16 m of a 50-digit truth
// there). 1e-9 m is a millionth of a millimetre: far below any term of S_p (Z_r alone is 1e-2 m)
// and 1000x below FCL's own GJK tolerance (1e-6 m).
constexpr double kAgree = 1e-9;
// Away from contact by this much (m), FCL's GJK collision check must agree with its distance.
constexpr double kClear = 1e-6;

// FCL's capsule is centred on its frame origin with its segment along z. The frame's z is the
// axis itself, x any unit normal to it, y = z x x: orthonormal to roundoff whatever the axis.
// (Not Eigen's FromTwoVectors(z, axis): for an axis near -z, a hanging arm, it computes 1 + cos,
// which cancels, and tilts the capsule by up to 1e-6 m at its ends.)
fcl::Transform3d capsuleFrame(const Capsule& c) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = 0.5 * (c.a + c.b);
  const Vec3 d = c.b - c.a;
  if (d.norm() > 0.0) {
    const Vec3 z = d.normalized(), x = z.unitOrthogonal();
    tf.linear().col(0) = x;
    tf.linear().col(1) = z.cross(x);
    tf.linear().col(2) = z;
  }
  return tf;
}

struct FclPair {
  double signedDistance;  // m, negative: the penetration depth
  bool collides;          // FCL's collision check (GJK)
};

FclPair fclPair(const Capsule& a, const Capsule& b) {
  const fcl::Capsuled ga(a.radius, (a.b - a.a).norm());
  const fcl::Capsuled gb(b.radius, (b.b - b.a).norm());
  const fcl::Transform3d ta = capsuleFrame(a), tb = capsuleFrame(b);
  // FCL's distance request as it comes (libccd's solver): for two capsules its closed-form kernel
  // (capsuleCapsuleDistance), |axes| - r1 - r2, negative when they overlap. (Not the signed
  // request: that goes through GJK/EPA on support functions, which stops at its 1e-6 m tolerance.)
  fcl::DistanceRequestd dreq;
  fcl::DistanceResultd dres;
  const double d = fcl::distance(&ga, ta, &gb, tb, dreq, dres);
  fcl::CollisionRequestd creq;
  fcl::CollisionResultd cres;
  const bool hit = fcl::collide(&ga, ta, &gb, tb, creq, cres) > 0;
  return {d, hit};
}

// What the monitor's separation should be for one pair, from FCL: 0 where they touch or overlap.
double monitorDefined(const FclPair& f) { return std::max(0.0, f.signedDistance); }

std::string scenarioPath(const std::string& name) {
  return std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/" + name + ".yaml";
}

// The rigid motion taking a skeleton's part (its capsule's axis) to midpoint `mid` along unit
// `dir`, with a spin about it: every joint moved alike (the person stays a person).
Skeleton placePart(const Skeleton& s, int part, const Vec3& mid, const Vec3& dir, double spin) {
  const BodyPart& bp = bodyParts()[part];
  const Vec3 p0 = s.p[bp.a], p1 = s.p[bp.b];
  const Vec3 c = 0.5 * (p0 + p1);
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(spin, dir).toRotationMatrix() * Eigen::Quaterniond::FromTwoVectors(p1 - p0, dir).toRotationMatrix();
  Skeleton out;
  for (int j = 0; j < kSkeletonJoints; ++j) out.p[j] = mid + r * (s.p[j] - c);
  return out;
}

struct Tally {
  long pairs = 0;           // body-arm capsule pairs compared (the body's and the reachable sets')
  long overlapping = 0;     // FCL: signed distance < 0
  long touching = 0;        // |FCL's signed distance| <= kAgree
  long nearParallel = 0;    // axes within 1e-3 rad of parallel, the pair within 5 cm
  long crossing = 0;        // axes >= 0.3 rad apart, closest points inside both, the pair within 5 cm
  long verdicts = 0;        // arm verdicts compared
  double worst = 0.0;       // m, largest |ours - FCL's| over pairs and verdicts
};

// Classifies and checks one pair; returns FCL's signed distance.
double comparePair(const Capsule& arm, const Capsule& body, Tally& t, const std::string& at) {
  const double ours = distance(arm, body);
  const FclPair f = fclPair(arm, body);
  ++t.pairs;
  if (f.signedDistance < 0.0) ++t.overlapping;
  if (std::abs(f.signedDistance) <= kAgree) ++t.touching;
  const double diff = std::abs(ours - monitorDefined(f));
  t.worst = std::max(t.worst, diff);
  EXPECT_LE(diff, kAgree) << at << ": ours " << ours << ", FCL " << f.signedDistance;
  // overlapping beyond roundoff: exactly 0, as the monitor defines it (no penetration depth)
  if (f.signedDistance < -kAgree) {
    EXPECT_EQ(ours, 0.0) << at;
  }
  // FCL's two answers agree away from contact (the transforms are read as FCL means them)
  if (std::abs(f.signedDistance) > kClear) {
    EXPECT_EQ(f.collides, f.signedDistance < 0.0) << at << " " << f.signedDistance;
  }
  // the regimes
  const Vec3 u = arm.b - arm.a, v = body.b - body.a;
  if (u.norm() > 1e-9 && v.norm() > 1e-9 && f.signedDistance < 0.05) {
    const double angle = std::atan2(u.cross(v).norm(), std::abs(u.dot(v)));
    const SegmentPair sp = closestSegmentSegment(arm.a, arm.b, body.a, body.b);
    if (angle < 1e-3) ++t.nearParallel;
    if (angle >= 0.3 && sp.s > 0.0 && sp.s < 1.0 && sp.t > 0.0 && sp.t < 1.0) ++t.crossing;
  }
  return f.signedDistance;
}

TEST(PersonVsFcl, SeparationEqualsFclOnEveryShippedScenario) {
  Tally tally;
  double runMin = INFINITY;  // over every scenario: the minimum separation from FCL's pairs
  for (const auto& entry : fs::directory_iterator(std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios")) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string name = entry.path().stem().string();
    const Scenario s = loadScenario(scenarioPath(name));
    Monitor mon = makeMonitor(s);
    const SsmConfig& cfg = s.ssm;
    SeparationMonitor ssm(cfg, mon.armCount());
    // the scenario's own persons where it has scripted ones, a standing person otherwise
    std::vector<ScriptedPerson> own;
    for (const Scenario::Person& p : s.persons)
      if (p.trace.empty()) own.emplace_back(p.script);
    std::mt19937_64 rng(54);  // fixed: the same poses every run
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    auto uni = [&](double lo, double hi) { return lo + (hi - lo) * u01(rng); };
    auto unit = [&] {
      Vec3 d;
      do d = Vec3(uni(-1, 1), uni(-1, 1), uni(-1, 1));
      while (d.squaredNorm() < 1e-4 || d.squaredNorm() > 1.0);
      return Vec3(d.normalized());
    };
    double scenarioMin = INFINITY;
    constexpr int kTrials = 120;
    for (int trial = 0; trial < kTrials; ++trial) {
      // the arms at a random pose within their limits (continuous joints: one turn), moving
      const double t = (trial + 1) * s.safety.cycleTime;
      for (int a = 0; a < mon.armCount(); ++a) {
        const ArmModel& model = mon.arm(a).model;
        std::vector<double> q(model.joints.size()), qd(model.joints.size());
        for (std::size_t k = 0; k < q.size(); ++k) {
          const Joint& j = model.joints[k];
          const double lo = std::isfinite(j.lower) ? j.lower : -M_PI, hi = std::isfinite(j.upper) ? j.upper : M_PI;
          q[k] = uni(lo, hi);
          qd[k] = uni(-1.0, 1.0);
        }
        mon.setJointState(a, t, q.data(), qd.data());
      }
      mon.cycle(t);
      // an arm capsule of some length to place a body part against
      int target = 0;
      do target = static_cast<int>(u01(rng) * mon.capsuleCount()) % mon.capsuleCount();
      while ((mon.movingCapsule(target).c.b - mon.movingCapsule(target).c.a).norm() < 0.02);
      const Capsule arm = mon.movingCapsule(target).c;
      const Vec3 axis = (arm.b - arm.a).normalized();
      const Vec3 onArm = arm.a + uni(0.15, 0.85) * (arm.b - arm.a);
      // a person: the scenario's at a random time of its script, or standing 0.5-1.0 m from the
      // arm capsule facing it and reaching towards it, then (two trials in four) moved rigidly so
      // that one body part lies near-parallel to or across that capsule, at a gap from 3 cm of
      // overlap to 5 cm apart, exactly touching in one such trial in four
      Skeleton skel;
      const int mode = trial % 4;
      if (mode == 0 && !own.empty()) {
        ScriptedPerson& p = own[static_cast<std::size_t>(trial / 4) % own.size()];
        ASSERT_TRUE(p.at(uni(0.0, p.end() + 0.5), skel));
      } else {
        const double bearing = uni(-M_PI, M_PI), range = uni(0.5, 1.0);
        const Vec3 feet(onArm.x() + range * std::cos(bearing), onArm.y() + range * std::sin(bearing), 0.0);
        PersonScript script;
        script.start = feet;
        script.heading = bearing + M_PI;
        script.actions = {{PersonAction::Reach, onArm + 0.1 * unit(), 2.0, 0.0, trial % 2 == 0}};
        ScriptedPerson p(script);
        ASSERT_TRUE(p.at(p.end() + 1.0, skel));
        if (mode >= 2) {
          const int part = static_cast<int>(u01(rng) * kBodyParts) % kBodyParts;
          const double rBody = bodyParts()[part].radius;
          const Vec3 n = axis.cross(unit()).normalized();  // the gap's direction, across the axis
          const double gap = arm.radius + rBody + ((trial / 4) % 4 == 0 ? 0.0 : uni(-0.03, 0.05));
          Vec3 dir;
          if (mode == 2) {
            // near-parallel: tilted by 1e-9 .. 1e-3 rad, either way round, slid along
            const double tilt = std::pow(10.0, uni(-9.0, -3.0));
            dir = (axis + tilt * n.cross(axis)).normalized();
            if (u01(rng) < 0.5) dir = -dir;
          } else {
            // crossing: 0.3 .. pi/2 rad apart, in a plane the gap is normal to
            const double phi = uni(0.3, M_PI / 2);
            dir = std::cos(phi) * axis + std::sin(phi) * n.cross(axis);
          }
          skel = placePart(skel, part, onArm + gap * n + (mode == 2 ? uni(-0.05, 0.05) : 0.0) * axis, dir,
                           uni(-M_PI, M_PI));
        }
      }
      auto held = std::make_unique<HeldPerson>();
      held->set(skel);
      PersonSet persons;
      persons.add("p", std::move(held));
      persons.pose(t);
      ssm.cycle(mon, persons);
      // every pair against FCL, the body's capsules and their reachable sets over T_r + T_s
      const auto body = bodyCapsules(skel);
      const double reachTime = cfg.reactionTime + cfg.stoppingTime;
      for (int a = 0; a < mon.armCount(); ++a) {
        double vr = 0.0;
        for (int i = 0; i < mon.capsuleCount(); ++i)
          if (mon.capsuleArm(i) == a) vr = std::max({vr, mon.movingCapsule(i).va.norm(), mon.movingCapsule(i).vb.norm()});
        double sep = INFINITY, slack = INFINITY, slackReach = INFINITY;
        for (int i = 0; i < mon.capsuleCount(); ++i) {
          if (mon.capsuleArm(i) != a) continue;
          const Capsule c = mon.movingCapsule(i).c;
          for (int k = 0; k < kBodyParts; ++k) {
            std::ostringstream at;
            at << name << " trial " << trial << " arm " << a << " capsule " << i << " part " << bodyParts()[k].name;
            const double vh = bodyParts()[k].hand ? cfg.handSpeed : cfg.bodySpeed;
            const SeparationTerms terms = protectiveSeparation(cfg, vh, vr);
            // formula (2) by hand: the reachable set's growth is S_h
            EXPECT_NEAR(terms.sh, vh * reachTime, 1e-15) << at.str();
            const double d = monitorDefined({comparePair(c, body[k], tally, at.str()), false});
            const double dReach = comparePair(c, reachable(body[k], vh, reachTime), tally, at.str() + " reachable");
            sep = std::min(sep, d);
            slack = std::min(slack, d - terms.total());
            // the same slack from the reachable set: its signed distance is the separation less S_h
            // (down to -S_h, where the body itself touches: the monitor counts no penetration)
            slackReach = std::min(slackReach, std::max(dReach, -terms.sh) - (terms.total() - terms.sh));
          }
        }
        // the monitor's figures for this arm (it measures each part against its nearest arm
        // capsule only) against FCL's over every pair
        const SsmVerdict& v = ssm.verdict(a);
        std::ostringstream at;
        at << name << " trial " << trial << " arm " << a;
        ++tally.verdicts;
        EXPECT_NEAR(v.separation, sep, kAgree) << at.str();
        EXPECT_NEAR(v.slack, slack, kAgree) << at.str();
        EXPECT_NEAR(v.slack, slackReach, kAgree) << at.str();
        EXPECT_EQ(v.violated, v.slack < 0.0) << at.str();
        tally.worst = std::max({tally.worst, std::abs(v.separation - sep), std::abs(v.slack - slack)});
        scenarioMin = std::min(scenarioMin, sep);
      }
    }
    // the minimum-separation figure of the run
    EXPECT_NEAR(ssm.counters().minSeparation, scenarioMin, kAgree) << name;
    EXPECT_EQ(ssm.counters().cycles, static_cast<std::uint64_t>(kTrials)) << name;
    runMin = std::min(runMin, scenarioMin);
  }
  std::printf("person-arm vs FCL: %ld pairs (%ld overlapping, %ld touching within %.0e m, %ld near-parallel, %ld "
              "crossing within 5 cm), %ld verdicts; largest |stsim - FCL| = %.3g m; smallest separation %.3g m\n",
              tally.pairs, tally.overlapping, tally.touching, kAgree, tally.nearParallel, tally.crossing, tally.verdicts,
              tally.worst, runMin);
  // every regime is actually exercised
  EXPECT_GE(tally.pairs, 1000);
  EXPECT_GE(tally.overlapping, 100);
  EXPECT_GE(tally.touching, 20);
  EXPECT_GE(tally.nearParallel, 100);
  EXPECT_GE(tally.crossing, 100);
  EXPECT_EQ(runMin, 0.0);  // some person touches some arm
}

}  // namespace
}  // namespace st::arm
