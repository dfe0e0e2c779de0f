// bench/arm_cycle: per-cycle latency of the arm monitor, side by side in one run with FCL's
// DynamicAABBTreeCollisionManager doing the same work on the same trace:
//   (a) Shaffer & Herb's scale: 2 Pandas + 24 stationary primitives (bench/arm_cycle/shaffer_scale.yaml)
//   (b) 1 Panda + 1000 random obstacles (models/arm/scenarios/panda_clutter.yaml)
//   (c) two UR5s from a URDF on a table with a fixture (models/arm/scenarios/two_ur5_cell.yaml)
// and, second table, the octree depth when the scenario sets no broadphase key: the old fixed
// default (8) against the depth chosen from the scene (depthFromScene) and each hand-set depth
// 2..6, on each case.
// "The same work" per cycle: forward kinematics and end-point velocities (shared code), every
// capsule's look-ahead swept box given to the broad phase (FCL: as the object's AABB), the
// allowed-collision matrix, exact distance for each overlapping pair, and time to collision by
// conservative advancement with FCL's distance as the oracle. Both sides must raise the same
// warnings; the table says whether they did.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/distance.h>

#include <starm/scenario.hpp>

namespace {

using namespace st;
using namespace st::arm;
using Clock = std::chrono::steady_clock;

struct Readings {
  std::vector<std::vector<Reading>> cycles;  // readings grouped by time
};

Readings record(const Scenario& s) {
  Readings r;
  auto src = makeSensor(s);
  Reading x;
  while (src->next(x)) {
    if (r.cycles.empty() || r.cycles.back().front().t != x.t) r.cycles.emplace_back();
    r.cycles.back().push_back(x);
  }
  return r;
}

struct Stats {
  double p50 = 0, p99 = 0, max = 0, mean = 0;
  std::uint64_t warnings = 0;
  double pairsPerCycle = 0;
};

Stats summarize(std::vector<double>& us, std::uint64_t warnings, double pairs) {
  Stats s;
  s.p50 = percentile(us, 50);
  s.p99 = percentile(us, 99);
  s.max = *std::max_element(us.begin(), us.end());
  double sum = 0;
  for (double v : us) sum += v;
  s.mean = sum / static_cast<double>(us.size());
  s.warnings = warnings;
  s.pairsPerCycle = pairs;
  return s;
}

// ---- ours --------------------------------------------------------------------------------------

Stats runOurs(const Scenario& sc, const Readings& rd, int reps) {
  std::vector<double> us;
  std::uint64_t warnings = 0;
  double pairs = 0;
  for (int rep = 0; rep < reps; ++rep) {
    Monitor m = makeMonitor(sc);
    for (const auto& cyc : rd.cycles) {
      const auto t0 = Clock::now();
      for (const Reading& r : cyc) m.setJointState(r.arm, r.t, r.q.data(), r.qdot.data());
      m.cycle(cyc.front().t);
      const auto t1 = Clock::now();
      if (rep > 0) us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
    warnings = m.counters().warnings;
    pairs = static_cast<double>(m.counters().exactPairs) / static_cast<double>(rd.cycles.size());
  }
  return summarize(us, warnings, pairs);
}

// ---- FCL ---------------------------------------------------------------------------------------

// A collision object whose broad-phase box is the look-ahead sweep, as ours.
struct SweptObject : fcl::CollisionObjectd {
  using fcl::CollisionObjectd::CollisionObjectd;
  void setBox(const Aabb3& b) { aabb = fcl::AABBd(b.min, b.max); }
};

fcl::Transform3d capsuleFrame(const Vec3& a, const Vec3& b) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = 0.5 * (a + b);
  const Vec3 d = b - a;
  if (d.squaredNorm() > 0) tf.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), d).toRotationMatrix();
  return tf;
}

struct FclWorld {
  const Scenario* sc = nullptr;
  std::vector<std::unique_ptr<SweptObject>> arm, obs;
  std::vector<int> capArm, capBody, capLocal;
  std::vector<MovingCapsule> caps;  // current
  std::vector<Obstacle> obstacles;
  fcl::DynamicAABBTreeCollisionManagerd armManager, obsManager;
  fcl::DistanceRequestd request;
  std::uint64_t warnings = 0, exactPairs = 0;
  double clearance = 0, horizon = 0, safeTime = 0;

  double fclSep(const fcl::CollisionGeometryd& g1, const fcl::Transform3d& t1, const fcl::CollisionGeometryd& g2,
                const fcl::Transform3d& t2) {
    fcl::DistanceResultd res;
    return std::max(0.0, fcl::distance(&g1, t1, &g2, t2, request, res));
  }

  // conservative advancement, FCL's distance as the oracle
  template <class Sep>
  void judge(Sep&& sep, double speed) {
    ++exactPairs;
    const AdvanceImpact r = toiAdvanceSeparation(sep, clearance, speed, horizon);
    if (r.impact.outcome == Outcome::Overlapping || (r.impact.outcome == Outcome::Hit && r.impact.t <= safeTime)) ++warnings;
  }

  void pair(int i, int j) {
    // same arm: the allowed-collision matrix
    if (capArm[i] == capArm[j] && sc->arms[capArm[i]].model.isAllowed(capBody[i], capBody[j])) return;
    const MovingCapsule& a = caps[i];
    const MovingCapsule& b = caps[j];
    judge([&](double t) {
      const Capsule ca = a.at(t), cb = b.at(t);
      const fcl::Capsuled ga(ca.radius, (ca.b - ca.a).norm()), gb(cb.radius, (cb.b - cb.a).norm());
      return fclSep(ga, capsuleFrame(ca.a, ca.b), gb, capsuleFrame(cb.a, cb.b));
    }, closingSpeedBound(a, b));
  }

  void obstaclePair(int i, int o) {
    const Obstacle& ob = obstacles[o];
    // the arm's allowed obstacle pairs, as the monitor skips them (a base on its table)
    for (const auto& [body, name] : sc->arms[capArm[i]].allowedObstacles)
      if (body == capBody[i] && name == ob.name) return;
    const MovingCapsule& a = caps[i];
    const fcl::CollisionGeometryd& g = *obs[o]->collisionGeometry();
    auto sep = [&](double t) {
      const Capsule ca = a.at(t);
      const fcl::Capsuled ga(ca.radius, (ca.b - ca.a).norm());
      return fclSep(ga, capsuleFrame(ca.a, ca.b), g, obs[o]->getTransform());
    };
    // stationary obstacles (both benchmark scenes)
    judge(sep, closingSpeedBound(a, MovingSphere{ob.sphere, ob.velocity}));
  }
};

// ownBoxes: stationary objects keep the AABB FCL computes itself (for a rotated shape, the box of
// its bounding sphere, grown by half the separation) instead of our tight box: FCL as usually
// set up. Same warnings (extra pairs are judged and cleared), more work.
Stats runFcl(const Scenario& sc, const Readings& rd, int reps, bool ownBoxes) {
  std::vector<double> us;
  std::uint64_t warnings = 0;
  double pairs = 0;
  for (int rep = 0; rep < reps; ++rep) {
    FclWorld w;
    w.sc = &sc;
    w.clearance = sc.safety.minSeparation;
    w.horizon = sc.safety.lookAhead();
    w.safeTime = sc.safety.safeTime();
    w.request.gjk_solver_type = fcl::GST_INDEP;
    w.obstacles = sc.obstacles;
    const double grow = 0.5 * sc.safety.minSeparation;
    // stationary obstacles in their own manager
    std::vector<fcl::CollisionObjectd*> obsPtrs;
    for (int o = 0; o < static_cast<int>(sc.obstacles.size()); ++o) {
      const Obstacle& ob = sc.obstacles[o];
      std::shared_ptr<fcl::CollisionGeometryd> g;
      fcl::Transform3d tf = fcl::Transform3d::Identity();
      switch (ob.kind) {
        case ShapeKind::Sphere: g = std::make_shared<fcl::Sphered>(ob.sphere.radius); tf.translation() = ob.sphere.center; break;
        case ShapeKind::Capsule:
          g = std::make_shared<fcl::Capsuled>(ob.capsule.radius, (ob.capsule.b - ob.capsule.a).norm());
          tf = capsuleFrame(ob.capsule.a, ob.capsule.b);
          break;
        case ShapeKind::Box:
          g = std::make_shared<fcl::Boxd>(2.0 * ob.box.halfExtents);
          tf.translation() = ob.box.center;
          tf.linear() = ob.box.rotation;
          break;
      }
      auto obj = std::make_unique<SweptObject>(g, tf);
      // the same tight box as ours, grown by half the separation (FCL's computeAABB bounds a
      // rotated shape by its bounding sphere, ten times the pairs on this scene's long beams)
      Aabb3 b{Vec3::Zero(), Vec3::Zero()};
      switch (ob.kind) {
        case ShapeKind::Sphere: b = boundsOf<3>(ob.sphere.center, ob.sphere.radius); break;
        case ShapeKind::Capsule: b = boundsOf(ob.capsule); break;
        case ShapeKind::Box: {
          const Vec3 half = ob.box.rotation.cwiseAbs() * ob.box.halfExtents;
          b = {ob.box.center - half, ob.box.center + half};
        }
      }
      if (ownBoxes) {
        obj->computeAABB();
        b = {obj->getAABB().min_, obj->getAABB().max_};
      }
      obj->setBox({b.min.array() - grow, b.max.array() + grow});
      obj->setUserData(reinterpret_cast<void*>(static_cast<std::intptr_t>(-1 - o)));
      obsPtrs.push_back(obj.get());
      w.obs.push_back(std::move(obj));
    }
    w.obsManager.registerObjects(obsPtrs);
    w.obsManager.setup();
    // arm capsules
    std::vector<fcl::CollisionObjectd*> armPtrs;
    for (int a = 0; a < static_cast<int>(sc.arms.size()); ++a) {
      const ArmModel& m = sc.arms[a].model;
      for (int k = 0; k < static_cast<int>(m.capsules.size()); ++k) {
        const LinkCapsule& c = m.capsules[k];
        auto obj = std::make_unique<SweptObject>(std::make_shared<fcl::Capsuled>(c.radius, (c.b - c.a).norm()));
        obj->setUserData(reinterpret_cast<void*>(static_cast<std::intptr_t>(w.caps.size())));
        w.caps.push_back({{Vec3::Zero(), Vec3::Zero(), c.radius}, Vec3::Zero(), Vec3::Zero()});
        w.capArm.push_back(a);
        w.capBody.push_back(c.body);
        w.capLocal.push_back(k);
        armPtrs.push_back(obj.get());
        w.arm.push_back(std::move(obj));
      }
    }
    std::vector<std::vector<Eigen::Isometry3d>> frames(sc.arms.size());
    std::vector<BodyRates> rates(sc.arms.size());
    for (std::size_t a = 0; a < sc.arms.size(); ++a) frames[a].resize(sc.arms[a].model.bodies());
    bool registered = false;
    const double h = w.horizon;
    for (const auto& cyc : rd.cycles) {
      const auto t0 = Clock::now();
      // kinematics (shared code), capsule poses and sweeps
      for (const Reading& r : cyc) {
        const ArmModel& m = sc.arms[r.arm].model;
        forwardKinematics(m, sc.arms[r.arm].base, r.q.data(), frames[r.arm].data());
        bodyRates(m, frames[r.arm].data(), r.qdot.data(), rates[r.arm]);
      }
      for (std::size_t i = 0; i < w.caps.size(); ++i) {
        const int a = w.capArm[i];
        const LinkCapsule& lc = sc.arms[a].model.capsules[w.capLocal[i]];
        const Eigen::Isometry3d& f = frames[a][lc.body];
        MovingCapsule& c = w.caps[i];
        c.c = {f * lc.a, f * lc.b, lc.radius};
        c.va = rates[a].velocity(lc.body, c.c.a);
        c.vb = rates[a].velocity(lc.body, c.c.b);
        w.arm[i]->setTransform(capsuleFrame(c.c.a, c.c.b));
        Aabb3 box{c.c.a.cwiseMin(c.c.b), c.c.a.cwiseMax(c.c.b)};
        const Vec3 ea = c.c.a + h * c.va, eb = c.c.b + h * c.vb;
        box.min = box.min.cwiseMin(ea).cwiseMin(eb).array() - (c.c.radius + grow);
        box.max = box.max.cwiseMax(ea).cwiseMax(eb).array() + (c.c.radius + grow);
        w.arm[i]->setBox(box);
      }
      if (!registered) {
        w.armManager.registerObjects(armPtrs);
        w.armManager.setup();
        registered = true;
      } else {
        w.armManager.update();
      }
      // arm-arm and self pairs, then arm-obstacle pairs
      auto cb = [](fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
        auto* world = static_cast<FclWorld*>(data);
        const auto i = reinterpret_cast<std::intptr_t>(o1->getUserData());
        const auto j = reinterpret_cast<std::intptr_t>(o2->getUserData());
        if (i >= 0 && j >= 0) world->pair(static_cast<int>(std::min(i, j)), static_cast<int>(std::max(i, j)));
        else if (i >= 0) world->obstaclePair(static_cast<int>(i), static_cast<int>(-1 - j));
        else world->obstaclePair(static_cast<int>(j), static_cast<int>(-1 - i));
        return false;
      };
      w.armManager.collide(&w, cb);
      w.armManager.collide(&w.obsManager, &w, cb);
      const auto t1 = Clock::now();
      if (rep > 0) us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
    warnings = w.warnings;
    pairs = static_cast<double>(w.exactPairs) / static_cast<double>(rd.cycles.size());
  }
  return summarize(us, warnings, pairs);
}

// Warnings counted per pair (ours emits one row per arm for arm-arm pairs): count ours the same way.
std::uint64_t pairWarnings(const Scenario& sc, const Readings& rd) {
  Monitor m = makeMonitor(sc);
  std::uint64_t n = 0;
  for (const auto& cyc : rd.cycles) {
    for (const Reading& r : cyc) m.setJointState(r.arm, r.t, r.q.data(), r.qdot.data());
    m.cycle(cyc.front().t);
    for (const Warning& w : m.warnings()) n += (w.obstacle >= 0 || w.otherArm == w.arm || w.arm < w.otherArm);
  }
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  const int reps = argc > 1 ? std::max(2, std::atoi(argv[1])) : 6;
  const std::string root = STSIM_SOURCE_DIR;
  struct Case {
    const char* label;
    std::string file;
  };
  const Case cases[] = {{"(a) 2 arms + 24 primitives", root + "/bench/arm_cycle/shaffer_scale.yaml"},
                        {"(b) 1 arm + 1000 obstacles", root + "/models/arm/scenarios/panda_clutter.yaml"},
                        {"(c) two UR5 (URDF) + table", root + "/models/arm/scenarios/two_ur5_cell.yaml"}};
  std::printf("arm_cycle: per-cycle latency (us) over %d timed passes of each trace, one core\n", reps - 1);
  std::printf("%-28s %-22s %7s %7s %8s %8s %9s %10s\n", "case", "detector", "p50", "p99", "max", "mean", "pairs/cyc",
              "warnings");
  for (const Case& c : cases) {
    const Scenario sc = loadScenario(c.file);
    const Readings rd = record(sc);
    const Stats ours = runOurs(sc, rd, reps);
    if (argc > 2 && std::string(argv[2]) == "ours") continue;  // profiling
    const Stats fcl = runFcl(sc, rd, reps, false);
    const Stats fclOwn = runFcl(sc, rd, reps, true);
    const std::uint64_t oursPairs = pairWarnings(sc, rd);
    std::printf("%-28s %-22s %7.2f %7.2f %8.1f %8.2f %9.1f %10llu\n", c.label, "stsim octree", ours.p50, ours.p99,
                ours.max, ours.mean, ours.pairsPerCycle, static_cast<unsigned long long>(oursPairs));
    std::printf("%-28s %-22s %7.2f %7.2f %8.1f %8.2f %9.1f %10llu\n", "", "FCL DynamicAABBTree", fcl.p50, fcl.p99,
                fcl.max, fcl.mean, fcl.pairsPerCycle, static_cast<unsigned long long>(fcl.warnings));
    std::printf("%-28s %-22s %7.2f %7.2f %8.1f %8.2f %9.1f %10llu\n", "", "FCL, its own AABBs", fclOwn.p50, fclOwn.p99,
                fclOwn.max, fclOwn.mean, fclOwn.pairsPerCycle, static_cast<unsigned long long>(fclOwn.warnings));
    std::printf("%-28s vs FCL on the same boxes: p50 %.1fx, p99 %.1fx faster; same warnings: %s (%zu cycles)\n", "", fcl.p50 / ours.p50,
                fcl.p99 / ours.p99, oursPairs == fcl.warnings && oursPairs == fclOwn.warnings ? "yes" : "NO", rd.cycles.size());
  }
  // the default depth: every broadphase key unset
  std::printf("\narm_cycle: every broadphase key unset; per-cycle latency (us), octree depth by rule\n");
  std::printf("%-28s %-26s %7s %7s %8s %8s\n", "case", "max_depth", "p50", "p99", "max", "mean");
  for (const Case& c : cases) {
    Scenario sc = loadScenario(c.file);
    sc.broad = BroadphaseConfig{};
    const Readings rd = record(sc);
    auto row = [&](const char* label, const std::string& what, const Stats& st) {
      std::printf("%-28s %-26s %7.2f %7.2f %8.1f %8.2f\n", label, what.c_str(), st.p50, st.p99, st.max, st.mean);
    };
    const int chosen = makeMonitor(sc).space()->rule().maxDepth;
    const Stats scene = runOurs(sc, rd, reps);
    sc.broad.depthFromScene = false;
    sc.broad.rule.maxDepth = 8;
    const Stats old = runOurs(sc, rd, reps);
    row(c.label, "8 (fixed, before)", old);
    row("", "from the scene: " + std::to_string(chosen) + " (now)", scene);
    double best = 1e300;
    int bestDepth = 0;
    for (int d = 2; d <= 6; ++d) {
      sc.broad.rule.maxDepth = d;
      const Stats st = runOurs(sc, rd, reps);
      row("", "hand-set " + std::to_string(d), st);
      if (st.p99 < best) best = st.p99, bestDepth = d;
    }
    std::printf("%-28s p99 from the scene / best hand-set (%d): %.2fx; before / now: %.0fx\n", "", bestDepth, scene.p99 / best,
                old.p99 / scene.p99);
  }
  return 0;
}
