#include <starm/monitor.hpp>

#include <algorithm>
#include <optional>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <starm/sensor.hpp>

namespace st::arm {

namespace {

Aabb3 pointsBox(std::initializer_list<Vec3> pts, double grow) {
  Aabb3 b{*pts.begin(), *pts.begin()};
  for (const Vec3& p : pts) {
    b.min = b.min.cwiseMin(p);
    b.max = b.max.cwiseMax(p);
  }
  b.min.array() -= grow;
  b.max.array() += grow;
  return b;
}

Aabb3 merge(const Aabb3& a, const Aabb3& b) { return {a.min.cwiseMin(b.min), a.max.cwiseMax(b.max)}; }

bool inside(const Aabb3& inner, const Aabb3& outer) {
  return (inner.min.array() >= outer.min.array()).all() && (inner.max.array() <= outer.max.array()).all();
}

// World box of an obstacle over [0, horizon] from its current pose, grown by `grow`.
Aabb3 obstacleSweep(const Obstacle& o, double horizon, double grow) {
  const Vec3 shift = horizon * o.velocity;
  switch (o.kind) {
    case ShapeKind::Sphere:
      return pointsBox({o.sphere.center, o.sphere.center + shift}, o.sphere.radius + grow);
    case ShapeKind::Capsule:
      return pointsBox({o.capsule.a, o.capsule.b, o.capsule.a + shift, o.capsule.b + shift}, o.capsule.radius + grow);
    case ShapeKind::Box: {
      const Vec3 half = o.box.rotation.cwiseAbs() * o.box.halfExtents;
      Aabb3 b{o.box.center - half, o.box.center + half};
      b = merge(b, Aabb3{b.min + shift, b.max + shift});
      b.min.array() -= grow;
      b.max.array() += grow;
      return b;
    }
  }
  return {};
}

Obstacle advanced(const Obstacle& o, double dt) {
  if (!o.moving()) return o;
  Obstacle n = o;
  const Vec3 s = dt * o.velocity;
  n.sphere.center += s;
  n.capsule.a += s;
  n.capsule.b += s;
  n.box.center += s;
  return n;
}

}  // namespace

std::string bodyName(const ArmModel& m, int body) {
  if (body >= 0 && body < static_cast<int>(m.bodyNames.size())) return m.bodyNames[body];
  return body == m.dof() + 1 ? std::string("flange") : "link" + std::to_string(body);
}

int depthFromScene(const Aabb3& bounds, std::vector<double> movingSizes) {
  constexpr int kMin = 2, kMax = 8;
  const double edge = (bounds.max - bounds.min).maxCoeff();
  if (movingSizes.empty() || !(edge > 0.0)) return kMax;
  const auto mid = movingSizes.begin() + static_cast<std::ptrdiff_t>(movingSizes.size() / 2);
  std::nth_element(movingSizes.begin(), mid, movingSizes.end());
  if (!(*mid > 0.0)) return kMax;
  const double d = std::round(std::log2(edge / *mid));
  return static_cast<int>(std::clamp(d, static_cast<double>(kMin), static_cast<double>(kMax)));
}

std::string otherName(const Monitor& m, const Warning& w) {
  if (w.obstacle >= 0) return "obstacle:" + m.obstacles()[w.obstacle].name;
  return m.arm(w.otherArm).name + "/" + bodyName(m.arm(w.otherArm).model, w.otherBody);
}

Monitor::Monitor(std::vector<ArmInstance> arms, std::vector<Obstacle> obstacles, SafetyConfig safety,
                 BroadphaseConfig broad)
    : obstacles_(std::move(obstacles)), safety_(safety), broad_(broad) {
  if (!(safety_.lookAhead() >= safety_.safeTime()))
    throw std::invalid_argument("look-ahead horizon shorter than the safe time");
  const double grow = 0.5 * safety_.minSeparation;
  for (ArmInstance& inst : arms) addArm(std::move(inst));
  restPoses();
  obstaclesNow_ = obstacles_;
  for (int o = 0; o < static_cast<int>(obstacles_.size()); ++o)
    if (obstacles_[o].moving()) moving_.push_back(o);
  buildSpace(grow);
}

void Monitor::addArm(ArmInstance inst) {
  // arm capsules: struct of arrays, arms in order
  ArmState a;
  a.firstCapsule = static_cast<int>(capA_.size());
  a.frames.resize(inst.model.bodies());
  for (int k = 0; k < static_cast<int>(inst.model.capsules.size()); ++k) {
    capA_.emplace_back(Vec3::Zero());
    capB_.emplace_back(Vec3::Zero());
    capVa_.emplace_back(Vec3::Zero());
    capVb_.emplace_back(Vec3::Zero());
    capR_.push_back(inst.model.capsules[k].radius);
    capArm_.push_back(static_cast<int>(arms_.size()));
    capBody_.push_back(inst.model.capsules[k].body);
    capLocal_.push_back(k);
    capAllowedObstacles_.push_back(allowedObstacles(inst, inst.model.capsules[k].body));
  }
  if (!(inst.sensorDrift >= 0.0 && inst.sensorDrift < 0.5))
    throw std::invalid_argument("arm " + inst.name + ": sensor drift must be in [0, 0.5)");
  a.clock.drift = inst.sensorDrift;
  a.inst = std::move(inst);
  arms_.push_back(std::move(a));
}

std::vector<int> Monitor::allowedObstacles(const ArmInstance& inst, int body) const {
  // allowed obstacle pairs of a capsule's body, by obstacle index
  std::vector<int> allowedObs;
  for (const auto& allowed : inst.allowedObstacles) {
    const auto& [armBody, name] = allowed;
    if (armBody != body) continue;
    // (clang before 16 captures no structured binding)
    const auto it = std::find_if(obstacles_.begin(), obstacles_.end(),
                                 [&](const Obstacle& o) { return o.name == allowed.second; });
    if (it == obstacles_.end()) throw std::invalid_argument("arm " + inst.name + ": allowed obstacle '" + name + "' is not an obstacle");
    allowedObs.push_back(static_cast<int>(it - obstacles_.begin()));
  }
  return allowedObs;
}

void Monitor::restPoses() {
  // a valid pose until the first reading: zero, clamped into the limits
  for (int i = 0; i < armCount(); ++i) {
    const ArmModel& m = arms_[i].inst.model;
    std::vector<double> q(m.dof()), qd(m.dof(), 0.0);
    for (int k = 0; k < m.dof(); ++k) q[k] = std::clamp(0.0, m.joints[k].lower, m.joints[k].upper);
    setJointState(i, 0.0, q.data(), qd.data());
    arms_[i].read = false;  // a pose to file, not a reading: the arm is stale until its sensor reports
    arms_[i].markStamp = std::numeric_limits<double>::quiet_NaN();
  }
}

void Monitor::buildSpace(double grow) {
  const int nc = capsuleCount();
  const int total = nc + static_cast<int>(obstacles_.size());
  swept_.resize(total);
  fat_.resize(total);
  neighbours_.resize(total);
  filedAt_.assign(total, 0);
  const double h = safety_.lookAhead();
  for (int o = 0; o < static_cast<int>(obstacles_.size()); ++o) swept_[nc + o] = obstacleSweep(obstacles_[o], h, grow);
  bounds_ = broad_.bounds ? *broad_.bounds : sceneBounds(grow);
  if (broad_.depthFromScene) {
    // the moving objects' sizes: capsules in any pose, moving obstacles' swept boxes, fat
    std::vector<double> sizes;
    for (int i = 0; i < nc; ++i) {
      const LinkCapsule& lc = arms_[capArm_[i]].inst.model.capsules[capLocal_[i]];
      sizes.push_back((lc.b - lc.a).norm() + 2.0 * (lc.radius + grow + broad_.margin));
    }
    for (int o : moving_) sizes.push_back((swept_[nc + o].max - swept_[nc + o].min).maxCoeff() + 2.0 * broad_.margin);
    broad_.rule.maxDepth = depthFromScene(bounds_, sizes);
  }
  // SpaceKind::None is the brute force behind the same interface: every object a neighbour of
  // every other, so the cycle below never asks which kind it has
  space_ = Space<3>(broad_.kind, bounds_, broad_.rule);
  for (int o = 0; o < static_cast<int>(obstacles_.size()); ++o) {
    const int id = nc + o;
    const double margin = obstacles_[o].moving() ? broad_.margin : 0.0;
    fat_[id] = {swept_[id].min.array() - margin, swept_[id].max.array() + margin};
    space_.insert(id, swept_[id], margin);
    filedAt_[id] = ++fileClock_;
  }
}

Aabb3 Monitor::sceneBounds(double grow) const {
  // the space covers what the arms can reach and the obstacles (objects outside are clamped)
  const int nc = capsuleCount();
  Aabb3 bounds{Vec3::Constant(-1.0), Vec3::Constant(1.0)};
  bool first = true;
  for (const ArmState& a : arms_) {
    const ArmModel& m = a.inst.model;
    double reach = m.flange.translation().norm();
    for (const Joint& j : m.joints) reach += jointReach(j);
    double extent = 0.0;
    for (const LinkCapsule& c : m.capsules) extent = std::max({extent, c.a.norm() + c.radius, c.b.norm() + c.radius});
    reach += extent + grow;
    const Vec3 p = a.inst.base.translation();
    const Aabb3 b{p.array() - reach, p.array() + reach};
    bounds = first ? b : merge(bounds, b);
    first = false;
  }
  for (int o = 0; o < static_cast<int>(obstacles_.size()); ++o) {
    bounds = first ? swept_[nc + o] : merge(bounds, swept_[nc + o]);
    first = false;
  }
  return bounds;
}

double Monitor::staleAfter(int arm) const {
  const ArmInstance& a = arms_[arm].inst;
  const double gap = a.sensorPeriod > 0.0 ? a.sensorPeriod + a.sensorJitter : safety_.reactionTime + safety_.cycleTime;
  // a clock that may run slow stretches the gap between its readings on the monitor's clock
  return gap * (1.0 + a.sensorDrift);
}

void Monitor::setSensorRate(int arm, double period, double jitter, double drift) {
  ArmState& a = arms_[arm];
  if (!(period >= 0.0 && period <= 60.0)) throw std::invalid_argument("arm " + a.inst.name + ": sensor period must be in [0, 60] s");
  if (!(jitter >= 0.0 && (jitter < period || (period == 0.0 && jitter == 0.0))))
    throw std::invalid_argument("arm " + a.inst.name + ": sensor jitter must be at least 0 and less than the period");
  if (!(drift >= 0.0 && drift < 0.5)) throw std::invalid_argument("arm " + a.inst.name + ": sensor drift must be in [0, 0.5)");
  a.inst.sensorPeriod = period;
  a.inst.sensorJitter = jitter;
  a.inst.sensorDrift = drift;
  a.clock = SensorClock{drift};
  a.markStamp = std::numeric_limits<double>::quiet_NaN();
}

void Monitor::forget(int arm) {
  ArmState& a = arms_[arm];
  if (a.read && safety_.latchStale) a.latched = true;
  a.read = false;
  a.clock.reset();  // the next reading may come from another sensor, another clock
  a.markStamp = std::numeric_limits<double>::quiet_NaN();
}

bool Monitor::reset(int arm) {
  ArmState& a = arms_[arm];
  if (a.stale) return false;
  a.latched = false;
  return true;
}

void Monitor::setJointState(int arm, double t, const double* q, const double* qdot) {
  if (arm < 0 || arm >= armCount()) throw InputError("arm " + std::to_string(arm) + ": no such arm");
  ArmState& a = arms_[arm];
  const ArmModel& m = a.inst.model;
  // what the service refuses, the library refuses: a NaN joint gave no warning and an infinite TTC
  if (!std::isfinite(t) || (a.read && t < a.t))
    throw InputError("arm " + a.inst.name + ": reading time " + std::to_string(t) + " s is not finite or goes back");
  validateJointState(m, q, qdot, a.inst.name);
  forwardKinematics(m, a.inst.base, q, a.frames.data());
  bodyRates(m, a.frames.data(), qdot, a.rates);
  // capsule end points and their velocities (the geometric Jacobian applied to qdot)
  for (int k = 0; k < static_cast<int>(m.capsules.size()); ++k) {
    const LinkCapsule& lc = m.capsules[k];
    const int i = a.firstCapsule + k;
    const Eigen::Isometry3d& f = a.frames[lc.body];
    capA_[i] = f * lc.a;
    capB_[i] = f * lc.b;
    capVa_[i] = a.rates.velocity(lc.body, capA_[i]);
    capVb_[i] = a.rates.velocity(lc.body, capB_[i]);
  }
  // the same stamp again is a repeat, not news; a later one waits for its arrival mark
  if ((!a.read || t > a.t) && std::isnan(a.markStamp)) {
    a.markStamp = t, a.markAfter = started_ ? now_ : -std::numeric_limits<double>::infinity();
    a.markApplied = false;
  }
  a.t = t;
  a.read = true;
  a.fresh = true;
}

void Monitor::setObstaclePose(int o, double t, const Vec3& position, const Vec3& velocity) {
  Obstacle& ob = obstacles_[o];
  Vec3 ref = Vec3::Zero();
  switch (ob.kind) {
    case ShapeKind::Sphere: ref = ob.sphere.center; break;
    case ShapeKind::Capsule: ref = 0.5 * (ob.capsule.a + ob.capsule.b); break;
    case ShapeKind::Box: ref = ob.box.center; break;
  }
  // stored at the time the obstacles are given at (t0_), so that cycle() advances it to t
  const Vec3 shift = position - (t - t0_) * velocity - ref;
  ob.sphere.center += shift;
  ob.capsule.a += shift;
  ob.capsule.b += shift;
  ob.box.center += shift;
  ob.velocity = velocity;
  // from now on it is swept every cycle (refiled when it leaves its fat box)
  if (std::find(moving_.begin(), moving_.end(), o) == moving_.end()) moving_.push_back(o);
}

MovingCapsule Monitor::movingCapsule(int i) const {
  // extrapolated from the arm's last reading to the cycle time (its age on the monitor's clock)
  const ArmState& a = arms_[capArm_[i]];
  const double dt = a.clock.age(a.t, now_);
  return {{capA_[i] + dt * capVa_[i], capB_[i] + dt * capVb_[i], capR_[i]}, capVa_[i], capVb_[i]};
}

void Monitor::refile(int id) {
  const double m = broad_.margin;
  fat_[id] = {swept_[id].min.array() - m, swept_[id].max.array() + m};
  if (space_.contains(id)) space_.update(id, swept_[id], m);
  else space_.insert(id, swept_[id], m);
  ++counters_.refiled;
  filedAt_[id] = ++fileClock_;
  gather(id);
}

void Monitor::gather(int id) {
  std::vector<int>& nb = neighbours_[id];
  nb.clear();
  space_.forEachNeighbor(id, [&](int j) { nb.push_back(j); });
}

void Monitor::tuneSpace() {
  // decomposition_factor auto: the space sees the visits the cycle made from the lists, which it
  // does not make itself; a new factor changes what the lists would hold: they are gathered again
  const int nc = capsuleCount();
  std::uint64_t visits = 0;
  for (int i = 0; i < nc; ++i) visits += neighbours_[i].size();
  for (int o : moving_) visits += neighbours_[nc + o].size();
  if (space_.noteRound(static_cast<std::uint64_t>(nc) + moving_.size(), visits)) regather();
}

void Monitor::regather() {
  // the boxes are as filed, so each list stays a superset of the pairs whose boxes overlap
  const int nc = capsuleCount();
  for (int i = 0; i < nc; ++i) gather(i);
  for (int o : moving_)
    if (space_.contains(nc + o)) gather(nc + o);
}

void Monitor::cycle(double t) {
  now_ = t;
  // new readings arrive now, if this cycle is later than the last before they came (for the
  // clocks that may drift)
  for (ArmState& a : arms_) {
    if (std::isnan(a.markStamp)) continue;
    if (stampedCycles_ && !a.markApplied) {
      a.markApplied = true;
      a.markAfter = std::max(a.markAfter, t);
      continue;
    }
    if (!(t > a.markAfter)) continue;
    a.clock.arrived(a.markStamp, t);
    a.markStamp = std::numeric_limits<double>::quiet_NaN();
  }
  const double h = safety_.lookAhead();
  const double grow = 0.5 * safety_.minSeparation;
  const int nc = capsuleCount();
  // moving obstacles at the cycle time
  for (int o : moving_) {
    obstaclesNow_[o] = advanced(obstacles_[o], t - t0_);
    swept_[nc + o] = obstacleSweep(obstaclesNow_[o], h, grow);
    if (!started_ || !inside(swept_[nc + o], fat_[nc + o])) refile(nc + o);
  }
  // arm capsules: swept boxes over the look-ahead; re-filed in the space only on leaving the fat box
  for (int i = 0; i < nc; ++i) {
    const MovingCapsule c = movingCapsule(i);
    swept_[i] = pointsBox({c.c.a, c.c.b, c.c.a + h * c.va, c.c.b + h * c.vb}, c.c.radius + grow);
    if (!started_ || !inside(swept_[i], fat_[i])) refile(i);
  }
  started_ = true;

  warnings_.clear();
  nearest_ = Warning{};
  nearest_.t = t;
  nearest_.distance = std::numeric_limits<double>::infinity();
  nearest_.ttc = std::numeric_limits<double>::infinity();
  nearest_.outcome = Outcome::Miss;
  minTtc_ = std::numeric_limits<double>::infinity();
  armMinTtc_.assign(arms_.size(), std::numeric_limits<double>::infinity());
  armWorst_.assign(arms_.size(), Warning{});
  for (Warning& w : armWorst_) w.t = t, w.distance = w.ttc = std::numeric_limits<double>::infinity(), w.outcome = Outcome::Miss;
  for (ArmState& a : arms_) a.warned = false;
  // each candidate pair from the neighbour list of its more recently filed member (the brute
  // force lists every other object: all pairs, each once)
  for (int i = 0; i < nc; ++i) {
    for (int j : neighbours_[i]) {
      if (filedAt_[j] > filedAt_[i]) continue;
      if (j >= nc) testObstacle(i, j - nc, t);
      else testPair(std::min(i, j), std::max(i, j), t);
    }
  }
  for (int o : moving_) {
    for (int i : neighbours_[nc + o])
      if (i < nc && filedAt_[i] < filedAt_[nc + o]) testObstacle(i, o, t);
  }
  if (space_.tuner()) tuneSpace();
  // STOP: issued on an arm's first warned cycle, held while warnings continue
  for (int ai = 0; ai < armCount(); ++ai) {
    ArmState& a = arms_[ai];
    // the watchdog: a verdict on a reading that is not current (or none yet) is no verdict
    a.stale = !a.read || !(std::abs(a.clock.age(a.t, t)) <= staleAfter(ai));
    if (a.stale) ++counters_.staleStops;
    // a sensor that was current and fell silent latches (one never heard from does not)
    if (a.stale && a.read && safety_.latchStale) a.latched = true;
    if ((a.warned || a.stale || a.latched) && !a.stopped) {
      a.stopped = true;
      ++counters_.stops;
      for (Warning& w : warnings_)
        if (w.arm == ai) {
          w.stop = true;
          break;
        }
    } else if (!a.warned && !a.stale && !a.latched) {
      a.stopped = false;
    }
  }
  for (ArmState& a : arms_) a.fresh = false;
  ++counters_.cycles;
}

void Monitor::noteNearest(int i, int j, int obstacle, const AdvanceImpact& r) {
  minTtc_ = std::min(minTtc_, r.impact.t);
  armMinTtc_[capArm_[i]] = std::min(armMinTtc_[capArm_[i]], r.impact.t);
  if (j >= 0) armMinTtc_[capArm_[j]] = std::min(armMinTtc_[capArm_[j]], r.impact.t);
  // each side's worst pair, from its own side
  for (const auto& [me, other] : {std::pair{i, j}, std::pair{j, i}}) {
    if (me < 0) continue;
    Warning& w = armWorst_[capArm_[me]];
    if (r.impact.t < w.ttc || (r.impact.t == w.ttc && r.distance < w.distance)) w = pairRecord(me, other, obstacle, r);
  }
  if (r.distance < nearest_.distance) nearest_ = pairRecord(i, j, obstacle, r);
}

Warning Monitor::pairRecord(int i, int j, int obstacle, const AdvanceImpact& r) const {
  Warning w;
  w.t = now_;
  w.arm = capArm_[i];
  w.body = capBody_[i];
  w.capsule = capLocal_[i];
  w.otherArm = j >= 0 ? capArm_[j] : -1;
  w.otherBody = j >= 0 ? capBody_[j] : -1;
  w.otherCapsule = j >= 0 ? capLocal_[j] : -1;
  w.obstacle = obstacle;
  w.distance = r.distance;
  w.ttc = r.impact.t;
  w.outcome = r.impact.outcome;
  return w;
}

void Monitor::addWarning(const Warning& w) {
  warnings_.push_back(w);
  arms_[w.arm].warned = true;
  ++counters_.warnings;
}

std::optional<Warning> Monitor::warningFor(int i, const AdvanceImpact& r, double t) {
  counters_.advanceSteps += r.steps;
  if (r.capped) ++counters_.cappedAdvances;
  if (!(r.impact.outcome == Outcome::Overlapping || (r.impact.outcome == Outcome::Hit && r.impact.t <= safety_.safeTime())))
    return std::nullopt;
  Warning w;
  w.t = t;
  w.distance = r.distance;
  w.ttc = r.impact.t;
  w.outcome = r.impact.outcome;
  w.arm = capArm_[i];
  w.body = capBody_[i];
  w.capsule = capLocal_[i];
  return w;
}

void Monitor::testPair(int i, int j, double t) {
  const int ai = capArm_[i], aj = capArm_[j];
  if (ai == aj && arms_[ai].inst.model.isAllowed(capBody_[i], capBody_[j])) return;
  ++counters_.candidatePairs;
  if (!swept_[i].overlaps(swept_[j])) return;  // cannot come within the separation in the look-ahead
  ++counters_.exactPairs;
  const AdvanceImpact r = toiAdvance(movingCapsule(i), movingCapsule(j), safety_.minSeparation, safety_.lookAhead());
  noteNearest(i, j, -1, r);
  std::optional<Warning> found = warningFor(i, r, t);
  if (!found) return;
  Warning& w = *found;
  w.otherArm = aj;
  w.otherBody = capBody_[j];
  w.otherCapsule = capLocal_[j];
  addWarning(w);
  if (ai != aj) {
    // the other arm is warned too, from its side
    std::swap(w.arm, w.otherArm);
    std::swap(w.body, w.otherBody);
    std::swap(w.capsule, w.otherCapsule);
    addWarning(w);
  }
}

void Monitor::testObstacle(int i, int o, double t) {
  const int id = capsuleCount() + o;
  const std::vector<int>& allowed = capAllowedObstacles_[i];
  if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), o) != allowed.end()) return;
  ++counters_.candidatePairs;
  if (!swept_[i].overlaps(swept_[id])) return;
  ++counters_.exactPairs;
  const MovingCapsule c = movingCapsule(i);
  const Obstacle& ob = obstaclesNow_[o];
  const double sep = safety_.minSeparation, h = safety_.lookAhead();
  AdvanceImpact r;
  switch (ob.kind) {
    case ShapeKind::Sphere: r = toiAdvance(c, MovingSphere{ob.sphere, ob.velocity}, sep, h); break;
    case ShapeKind::Capsule:
      r = toiAdvance(c, MovingCapsule{ob.capsule, ob.velocity, ob.velocity}, sep, h);
      break;
    case ShapeKind::Box: r = toiAdvance(c, MovingBox{ob.box, ob.velocity}, sep, h); break;
  }
  noteNearest(i, -1, o, r);
  std::optional<Warning> w = warningFor(i, r, t);
  if (!w) return;
  w->obstacle = o;
  addWarning(*w);
}

}  // namespace st::arm
