#include <stcore/simulator.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <stcore/resolve.hpp>
#include <stcore/toi.hpp>
#include <stcore/tolerances.hpp>

namespace st {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

const char* toString(EventKind kind) {
  switch (kind) {
    case EventKind::BallBall: return "ball-ball";
    case EventKind::BallWall: return "ball-wall";
    case EventKind::BallSegment: return "ball-segment";
    case EventKind::BallPoint: return "ball-point";
    case EventKind::Sensor: return "sensor";
    case EventKind::Boundary: return "boundary";
    case EventKind::Rest: return "rest";
    case EventKind::Model: return "model";
    case EventKind::Count: break;
  }
  return "?";
}

template <int D>
Simulator<D>::Simulator(const Aabb<D>& bounds, const SimulatorConfig& config)
    : config_(config), bounds_(bounds), space_(config.spaceKind, bounds, config.rule), lists_(config.neighborShell), heap_(config.eventsPerBlock) {
  // A ball's box in the space must be strictly larger than the ball: with no margin a moving ball
  // touches the edge of its membership at once, and each Boundary event schedules the next at the
  // same instant (a livelock). Any margin well above position rounding gives progress. (The brute
  // force lists no boxes.)
  if (config_.spaceKind != SpaceKind::None && !(config_.marginFactor > 0.0))
    throw std::invalid_argument("simulator margin factor must be positive when a space is used");
  if (!(config_.eventsPerBlock >= 0.0) || !std::isfinite(config_.eventsPerBlock))
    throw std::invalid_argument("simulator events per block must be finite and >= 0");
  if (!(config_.neighborShell >= 0.0) || !std::isfinite(config_.neighborShell))
    throw std::invalid_argument("simulator neighbour shell must be finite and >= 0");
  // a tree re-files balls by where they are (relisted, widened), where the lists need them listed
  // by their list centres
  if (lists_.enabled() && config_.spaceKind == SpaceKind::Tree)
    throw std::invalid_argument("neighbour lists need a space of kind none, single or cells");
}

template <int D>
Aabb<D> Simulator<D>::boxOf(int i, double t) const {
  const BallState<D>& b = balls_[i];
  return boundsOf<D>(b.positionAt(t), b.radius);
}

template <int D>
int Simulator<D>::addBall(const Vec<D>& p, const Vec<D>& v, double radius, double mass, int type) {
  if (!(radius > 0.0) || !(mass > 0.0)) throw std::invalid_argument("ball radius and mass must be positive");
  if (!p.allFinite() || !v.allFinite()) throw std::invalid_argument("ball position and velocity must be finite");
  const int i = static_cast<int>(balls_.size());
  BallState<D> b;
  b.p = p;
  b.v = v;
  b.t = now_;
  b.radius = radius;
  b.mass = mass;
  b.type = type;
  balls_.push_back(b);
  motion_.push_back(Motion{b.p, b.v, b.t, b.radius});
  next_.push_back(Next{});
  mark_.push_back(0u);
  if (lists_.enabled()) {
    lists_.add(i, radius);
    nearWalls_.push_back(0u);
    space_.insert(i, boundsOf<D>(p, 0.0), 0.0);
    rebuildList(i, now_);
  } else {
    space_.insert(i, boxOf(i, now_), spaceMargin(i));
    settleSpace();
  }
  predict(i);
  return i;
}

template <int D>
int Simulator<D>::addWall(const Wall<D>& w) {
  walls_.push_back({w.normal.normalized(), w.offset / w.normal.norm()});
  const int k = static_cast<int>(walls_.size()) - 1;
  // the balls' lists were built without it: every ball checks it until its next rebuild
  if (k < 32)
    for (std::uint32_t& m : nearWalls_) m |= 1u << k;
  return k;
}

template <int D>
int Simulator<D>::addPoint(const Vec<D>& p) {
  points_.push_back(p);
  return static_cast<int>(points_.size()) - 1;
}

template <int D>
int Simulator<D>::addSegment(const Segment& s) {
  if constexpr (D != 2) {
    (void)s;
    throw std::logic_error("segments are 2-D obstacles");
  } else {
    segments_.push_back(s);
    return static_cast<int>(segments_.size()) - 1;
  }
}

template <int D>
int Simulator<D>::addSensor(const Sensor<D>& s) {
  sensors_.push_back(s);
  return static_cast<int>(sensors_.size()) - 1;
}

template <int D>
void Simulator<D>::advance(int i, double t) {
  BallState<D>& b = balls_[i];
  if (b.accelerating()) {
    const Vec<D> v = b.velocityAt(t);
    b.p = b.positionAt(t);
    b.v = v;
  } else {
    b.p = b.positionAt(t);
  }
  b.t = t;
  syncMotion(i);
}

template <int D>
void Simulator<D>::setVelocity(int i, const Vec<D>& v) {
  if (!v.allFinite()) throw std::invalid_argument("velocity must be finite");
  BallState<D>& b = balls_[i];
  if (!b.active) throw std::invalid_argument("ball is no longer in the simulation");
  advance(i, now_);
  redirect(i, v);
  settleSpace();
}

// Ball i, advanced to now, leaves with velocity v: a new generation, membership and prediction.
template <int D>
void Simulator<D>::redirect(int i, const Vec<D>& v) {
  BallState<D>& b = balls_[i];
  b.v = v;
  syncMotion(i);
  ++b.gen;
  spaceUpdate(i);
  predict(i);
}

template <int D>
void Simulator<D>::deactivate(int i) {
  BallState<D>& b = balls_[i];
  if (!b.active) return;
  advance(i, now_);
  b.active = false;
  ++b.gen;
  heap_.remove(i);
  if (lists_.enabled()) lists_.remove(i);
  space_.remove(i);
  settleSpace();
}

template <int D>
void Simulator<D>::setDeceleration(int i, double decel) {
  if (!(decel >= 0.0) || !std::isfinite(decel)) throw std::invalid_argument("deceleration must be finite and >= 0");
  BallState<D>& b = balls_[i];
  if (!b.active) throw std::invalid_argument("ball is no longer in the simulation");
  advance(i, now_);
  if ((b.decel > 0.0) != (decel > 0.0)) decelerating_ += decel > 0.0 ? 1 : -1;
  b.decel = decel;
  ++b.gen;
  predict(i);
}

template <int D>
void Simulator<D>::synchronize(double t) {
  if (t < now_) throw std::invalid_argument("cannot synchronize to the past");
  for (int i = 0; i < static_cast<int>(balls_.size()); ++i)
    if (balls_[i].active) advance(i, t);
  now_ = t;
}

// Cells: the fat margin; a tree: the slop its region events keep against rounding.
template <int D>
double Simulator<D>::spaceMargin(int i) const {
  return space_.listingMargin(balls_[i].radius, config_.marginFactor);
}

template <int D>
void Simulator<D>::spaceUpdate(int i) {
  if (lists_.enabled()) return;  // listed by its list centre, which moves only at a rebuild
  space_.update(i, boxOf(i, balls_[i].t), spaceMargin(i));
}

// Ball i's list centred where it is at time t: the space lists its centre (one cell), and the
// centres in the box of the search radius around it are its candidates. The walls it may reach
// before it leaves its shell are marked.
template <int D>
void Simulator<D>::rebuildList(int i, double t) {
  const BallState<D>& b = balls_[i];
  const Vec<D> centre = b.positionAt(t);
  space_.update(i, boundsOf<D>(centre, 0.0), 0.0);
  const Aabb<D> search = boundsOf<D>(centre, lists_.searchRadius(i));
  constexpr int kRoom = 512;
  int found[kRoom];
  const int n = space_.gatherInBox(search, found, kRoom);
  if (n >= 0) {
    lists_.rebuild(i, centre, [&](auto&& f) {
      for (int k = 0; k < n; ++k) f(found[k]);
    });
  } else {
    lists_.rebuild(i, centre, [&](auto&& f) { space_.forEachInBox(search, f); });
  }
  const double reach = b.radius + lists_.skin(b.radius) + tol::kRegionSlop;
  std::uint32_t near = 0;
  for (int w = 0; w < std::min(32, static_cast<int>(walls_.size())); ++w)
    near |= static_cast<std::uint32_t>(std::abs(walls_[w].normal.dot(centre) - walls_[w].offset) < reach) << w;
  nearWalls_[i] = near;
}

// A space that does not name the neighbours an update brings (a tree): ball i's membership moves
// to its box now; its path is unchanged, so its prediction stands and only the neighbours it
// gained, found by comparing its leaves before and after, are checked.
template <int D>
void Simulator<D>::refileGained(int i) {
  oldLeaves_ = space_.leavesOf(i);
  const std::uint64_t restructures = space_.counters().subdivisions + space_.counters().reunions;
  if (!space_.update(i, boxOf(i, now_), spaceMargin(i))) {
    schedule(i, next_[i]);  // the same neighbours: only the region event moves
    return;
  }
  if (space_.counters().subdivisions + space_.counters().reunions != restructures) {
    predict(i);  // leaves were rebuilt: the old ones name other regions now
    return;
  }
  // The old leaves are still the leaves they were, so a new neighbour is one listed in a leaf
  // the ball entered and in none of its old ones (a ball that only left leaves gained none).
  auto inOld = [&](int leaf) { return std::find(oldLeaves_.begin(), oldLeaves_.end(), leaf) != oldLeaves_.end(); };
  const Next old = next_[i];
  Next best = old;
  bool stamped = false;
  for (int leaf : space_.leavesOf(i)) {
    if (inOld(leaf)) continue;
    if (!stamped) {
      // once each, should it lie in several entered leaves
      if (++markNow_ == 0) {
        std::fill(mark_.begin(), mark_.end(), 0u);
        markNow_ = 1;
      }
      mark_[i] = markNow_;
      stamped = true;
    }
    for (int j : space_.objectsIn(leaf)) {
      if (mark_[j] == markNow_) continue;
      mark_[j] = markNow_;
      const std::vector<int>& shared = space_.leavesOf(j);
      if (std::none_of(shared.begin(), shared.end(), inOld)) pairCandidate(i, j, best);
    }
  }
  // a new partner is taken as it is now; the old one keeps the generation it was predicted with
  if (best.kind == EventKind::BallBall && (best.other != old.other || best.t != old.t || old.kind != best.kind))
    best.otherGen = balls_[best.other].gen;
  schedule(i, best);
}

// After a change to the space: a tree's divisions and reunions re-listed other balls by the
// boxes they were last filed with; each is re-filed where it is now (checking the neighbours it
// gained), and those a reunion listed in a wider region are predicted again.
template <int D>
void Simulator<D>::settleSpace() {
  while (space_.hasRelisted() || space_.hasWidened()) {
    space_.takeWidened(widened_);
    space_.takeRelisted(relisted_);
    for (int j : relisted_)
      if (balls_[j].active) refileGained(j);
    for (int j : widened_)
      if (balls_[j].active) predict(j);
  }
}

template <int D>
void Simulator<D>::consider(Next& best, double t, EventKind kind, int other) const {
  t = std::max(t, now_);
  // ties broken by kind, then by the other index: independent of the order candidates arrive in
  if (t < best.t || (t == best.t && (kind < best.kind || (kind == best.kind && other < best.other)))) {
    best.t = t;
    best.kind = kind;
    best.other = other;
  }
}

// Ball i against ball j when either decelerates: quadratic paths until the first of the two stops
// (that ball's Rest event re-predicts it). Out of line: pairCandidate stays small.
template <int D>
void Simulator<D>::pairCandidateAccelerated(int i, int j, Next& best) {
  const BallState<D>& bi = balls_[i];
  const BallState<D>& bj = balls_[j];
  const double t0 = std::max(bi.t, bj.t);
  const double tEnd = std::min(bi.stopTime(), bj.stopTime());
  const Impact hit = toiBallsAccelerated<D>(bj.positionAt(t0) - bi.positionAt(t0), bj.velocityAt(t0) - bi.velocityAt(t0),
                                            bj.acceleration() - bi.acceleration(), bi.radius + bj.radius, tEnd - t0);
  if (hit.acts()) consider(best, t0 + hit.actTime(), EventKind::BallBall, j);
}

// Ball i against ball j (both active, j != i).
template <int D>
inline void Simulator<D>::pairCandidate(int i, int j, Next& best) {
  ++counters_.pairChecks;
  if (accelerating(i) || accelerating(j)) {
    pairCandidateAccelerated(i, j, best);
    return;
  }
  pairStraight(i, j, best);
}

// Ball i against ball j on straight paths.
// A contact later than `limit` (absolute) may be skipped: the caller has an event by then.
template <int D>
inline void Simulator<D>::pairStraight(int i, int j, Next& best, double limit) const {
  const Motion& mi = motion_[i];
  const Motion& mj = motion_[j];
  const double t0 = std::max(mi.t, mj.t);
  // BallState::positionAt on a straight path, term for term
  const Vec<D> p_rel = (mj.p + mj.v * (t0 - mj.t)) - (mi.p + mi.v * (t0 - mi.t));
  const Vec<D> v_rel = mj.v - mi.v;
  // toiBalls acts only on closing pairs (p_rel . v_rel < 0): skip the rest before its square root
  const double b = p_rel.dot(v_rel);
  if (!(b < 0.0)) return;
  const double sigma = mi.radius + mj.radius;
  // Smallenburg's early out: |p + v t|^2 - sigma^2 >= |p|^2 - sigma^2 + 2 b t, a falling line; if
  // it is still positive at the horizon h (widened against rounding), no contact comes before it
  const double h = (limit - t0) * (1.0 + 1e-9) + 1e-12;
  if (p_rel.squaredNorm() - sigma * sigma + 2.0 * b * h > 1e-12 * sigma * sigma) return;
  const Impact hit = toiBalls<D>(p_rel, v_rel, sigma);
  if (hit.acts()) consider(best, t0 + hit.actTime(), EventKind::BallBall, j);
}

template <int D>
void Simulator<D>::predict(int i) {
  Next best;
  // with lists, the ball rebuilds (and predicts again) when it leaves its shell: a contact after
  // that need not be found, and the exit bounds every pair's search
  const double exit = lists_.enabled() ? std::max(exitTime(i), now_) : kInf;
  {
    // gather, then predict: the neighbours' motion comes from memory while the cells are walked
    // (the order candidates arrive in does not matter: consider() breaks every tie)
    constexpr int kGather = 256;
    int gathered[kGather];
    int n = lists_.enabled() ? -2 : space_.gatherNeighbors(i, gathered, kGather);
    if (n == -2) {
      // neighbour lists: the list is the candidates
      n = lists_.count(i);
      const int* list = lists_.begin(i);
      if (n > kGather) {
        for (int k = kGather; k < n; ++k) pairCandidate(i, list[k], best);
        n = kGather;
      }
      for (int k = 0; k < n; ++k) {
        gathered[k] = list[k];
        __builtin_prefetch(&motion_[list[k]]);
      }
    } else if (n >= 0) {
      for (int k = 0; k < n; ++k) __builtin_prefetch(&motion_[gathered[k]]);
    } else {
      n = 0;
      space_.forEachNeighbor(i, [&](int j) {
        if (n == kGather) {
          pairCandidate(i, j, best);
          return;
        }
        __builtin_prefetch(&motion_[j]);
        gathered[n++] = j;
      });
    }
    if (decelerating_ == 0) {
      // keep the closing pairs first, without a branch (half of them close, unpredictably), then
      // predict those
      const Motion& mi = motion_[i];
      int closing[kGather];
      int m = 0;
      for (int k = 0; k < n; ++k) {
        const Motion& mj = motion_[gathered[k]];
        const double t0 = std::max(mi.t, mj.t);
        const Vec<D> p_rel = (mj.p + mj.v * (t0 - mj.t)) - (mi.p + mi.v * (t0 - mi.t));
        closing[m] = gathered[k];
        m += static_cast<int>(p_rel.dot(mj.v - mi.v) < 0.0);
      }
      counters_.pairChecks += static_cast<std::uint64_t>(n);
      for (int k = 0; k < m; ++k) pairStraight(i, closing[k], best, std::min(exit, best.t));
    } else {
      for (int k = 0; k < n; ++k) pairCandidate(i, gathered[k], best);
    }
  }
  if (accelerating(i)) predictObstaclesAccelerated(i, best);
  else predictObstacles(i, best);
  if (best.kind == EventKind::BallBall) best.otherGen = balls_[best.other].gen;
  if (lists_.enabled()) schedule(i, best, exit);
  else schedule(i, best);
}

// After a Boundary event: the path is unchanged, so the physical prediction stands (a partner that
// changed since makes it stale, as ever); only the neighbours gained can bring an earlier contact.
template <int D>
void Simulator<D>::predictGained(int i) {
  const Next old = next_[i];
  Next best = old;
  space_.forEachNeighborGained(i, [&](int j) { pairCandidate(i, j, best); });
  // a new partner is taken as it is now; the old one keeps the generation it was predicted with
  if (best.kind == EventKind::BallBall && (best.other != old.other || best.t != old.t || old.kind != best.kind))
    best.otherGen = balls_[best.other].gen;
  schedule(i, best);
}

// The boundary time, then the heap.
template <int D>
void Simulator<D>::schedule(int i, const Next& best) {
  schedule(i, best, std::max(exitTime(i), now_));
}

template <int D>
void Simulator<D>::schedule(int i, const Next& best, double exit) {
  // field by field: a copy of the whole struct after writing exit into it stalls on store forwarding
  Next& n = next_[i];
  n.t = best.t;
  n.exit = exit;
  n.other = best.other;
  n.otherGen = best.otherGen;
  n.kind = best.kind;
  heap_.set(i, n.due());
}

// When the ball may first touch a region it is not listed in (infinity for one region or none).
template <int D>
double Simulator<D>::exitTime(int i) const {
  const BallState<D>& bi = balls_[i];
  if (lists_.enabled()) {
    // leaving the shell; while the ball slows, the straight path from now runs ahead of it along
    // its one direction, so its exit is a safe (early) bound
    if (accelerating(i)) {
      const double t0 = std::max(now_, bi.t);
      const double dt = lists_.exitTime(i, bi.positionAt(t0), bi.velocityAt(t0), bi.radius);
      return dt < kInf ? t0 + dt : kInf;
    }
    const double dt = lists_.exitTime(i, bi.p, bi.v, bi.radius);
    return dt < kInf ? bi.t + dt : kInf;
  }
  if (space_.followsSlowingPaths()) {
    // exact along the path, quadratic while the ball slows
    BallPath<D> path{bi.p, bi.v, bi.radius};
    if (accelerating(i)) {
      path.a = bi.acceleration();
      path.horizon = bi.stopTime() - bi.t;
    }
    const double dt = space_.exitTime(i, path);
    return dt < kInf ? bi.t + dt : kInf;
  }
  if (accelerating(i)) {
    // the straight constant-velocity path from now runs ahead of the decelerating one along every
    // axis, so its exit time is a safe (early) bound
    const double dt = space_.exitTime(i, bi.positionAt(now_), bi.velocityAt(now_), bi.radius);
    return dt < kInf ? std::max(now_, bi.t) + dt : kInf;
  }
  const double dt = space_.exitTime(i, bi.p, bi.v, bi.radius);
  return dt < kInf ? bi.t + dt : kInf;
}

template <int D>
void Simulator<D>::predictObstacles(int i, Next& best) {
  const BallState<D>& bi = balls_[i];
  const Ball<D> me{bi.p, bi.radius};
  auto wall = [&](int w) {
    ++counters_.staticChecks;
    const Impact hit = toiBallPlane<D>(me, bi.v, walls_[w].normal, walls_[w].offset);
    if (hit.acts()) consider(best, bi.t + hit.actTime(), EventKind::BallWall, w);
  };
  if (lists_.enabled()) {
    // only the walls within reach of its shell (the rest cannot be touched before its rebuild)
    for (std::uint32_t near = nearWalls_[i]; near != 0; near &= near - 1) wall(std::countr_zero(near));
    for (int w = 32; w < static_cast<int>(walls_.size()); ++w) wall(w);
  } else {
    for (int w = 0; w < static_cast<int>(walls_.size()); ++w) wall(w);
  }
  if constexpr (D == 2) {
    for (int s = 0; s < static_cast<int>(segments_.size()); ++s) {
      ++counters_.staticChecks;
      const Impact hit = toiCircleSegment(Circle{bi.p, bi.radius}, bi.v, segments_[s]).impact;
      if (hit.acts()) consider(best, bi.t + hit.actTime(), EventKind::BallSegment, s);
    }
  }
  for (int q = 0; q < static_cast<int>(points_.size()); ++q) {
    ++counters_.staticChecks;
    const Impact hit = toiBalls<D>(points_[q] - bi.p, -bi.v, bi.radius);
    if (hit.acts()) consider(best, bi.t + hit.actTime(), EventKind::BallPoint, q);
  }
  for (int s = 0; s < static_cast<int>(sensors_.size()); ++s) {
    ++counters_.staticChecks;
    const Impact hit = toiBalls<D>(sensors_[s].center - bi.p, -bi.v, sensors_[s].radius);
    if (hit.acts()) consider(best, bi.t + hit.actTime(), EventKind::Sensor, s);
  }
}

// A decelerating ball against the obstacles and its own stop: the same queries as
// predictObstacles' on quadratic paths, each searched only until the ball stops.
template <int D>
void Simulator<D>::predictObstaclesAccelerated(int i, Next& best) {
  const BallState<D>& bi = balls_[i];
  const double tEnd = bi.stopTime() - bi.t;
  const Vec<D> a = bi.acceleration();
  const Ball<D> me{bi.p, bi.radius};
  for (int w = 0; w < static_cast<int>(walls_.size()); ++w) {
    ++counters_.staticChecks;
    const Impact hit = toiBallPlaneAccelerated<D>(me, bi.v, a, walls_[w].normal, walls_[w].offset, tEnd);
    if (hit.acts()) consider(best, bi.t + hit.actTime(), EventKind::BallWall, w);
  }
  if constexpr (D == 2) {
    for (int s = 0; s < static_cast<int>(segments_.size()); ++s) {
      ++counters_.staticChecks;
      const Impact hit = toiCircleSegmentAccelerated(Circle{bi.p, bi.radius}, bi.v, a, segments_[s], tEnd).impact;
      if (hit.acts()) consider(best, bi.t + hit.actTime(), EventKind::BallSegment, s);
    }
  }
  for (int q = 0; q < static_cast<int>(points_.size()); ++q) {
    ++counters_.staticChecks;
    const Impact hit = toiBallsAccelerated<D>(points_[q] - bi.p, -bi.v, -a, bi.radius, tEnd);
    if (hit.acts()) consider(best, bi.t + hit.actTime(), EventKind::BallPoint, q);
  }
  for (int s = 0; s < static_cast<int>(sensors_.size()); ++s) {
    ++counters_.staticChecks;
    const Impact hit = toiBallsAccelerated<D>(sensors_[s].center - bi.p, -bi.v, -a, sensors_[s].radius, tEnd);
    if (hit.acts()) consider(best, bi.t + hit.actTime(), EventKind::Sensor, s);
  }
  consider(best, bi.stopTime(), EventKind::Rest, -1);
}

template <int D>
double Simulator<D>::nextEventTime() const {
  const double t = heap_.empty() ? kInf : heap_.topTime();
  return modelHeap_.empty() ? t : std::min(t, modelHeap_.front().t);
}

template <int D>
int Simulator<D>::scheduleEvent(double t, int tag) {
  if (!(t >= now_) || !std::isfinite(t)) throw std::invalid_argument("a model event needs a finite time not before now");
  const int handle = static_cast<int>(modelTags_.size());
  modelTags_.push_back(tag);
  modelCancelled_.push_back(false);
  modelHeap_.push_back({t, handle});
  std::push_heap(modelHeap_.begin(), modelHeap_.end(), std::greater<>{});
  return handle;
}

template <int D>
void Simulator<D>::cancelEvent(int handle) {
  if (handle >= 0 && handle < static_cast<int>(modelCancelled_.size())) modelCancelled_[handle] = true;
  dropCancelledModelEvents();
}

// Keeps the heap's front a live event, so nextEventTime need not look further.
template <int D>
void Simulator<D>::dropCancelledModelEvents() {
  while (!modelHeap_.empty() && modelCancelled_[modelHeap_.front().handle]) {
    std::pop_heap(modelHeap_.begin(), modelHeap_.end(), std::greater<>{});
    modelHeap_.pop_back();
  }
}

template <int D>
bool Simulator<D>::modelEventDue() const {
  return !modelHeap_.empty() && (heap_.empty() || modelHeap_.front().t <= heap_.topTime());
}

template <int D>
void Simulator<D>::processModelEvent() {
  const ModelEvent m = modelHeap_.front();
  std::pop_heap(modelHeap_.begin(), modelHeap_.end(), std::greater<>{});
  modelHeap_.pop_back();
  modelCancelled_[m.handle] = true;  // happened: a later cancelEvent is a no-op
  dropCancelledModelEvents();
  now_ = std::max(now_, m.t);
  ++counters_.events[static_cast<int>(EventKind::Model)];
  last_ = EventRecord{m.t, EventKind::Model, -1, modelTags_[m.handle]};
}

template <int D>
void Simulator<D>::process(int i) {
  const Next n = next_[i];
  BallState<D>& bi = balls_[i];
  if (n.boundaryFirst()) {
    // membership follows the ball; its path is unchanged, so only its own prediction is redone
    now_ = std::max(now_, n.exit);
    if (lists_.enabled()) {
      // left its shell: a new list, and every pair on it predicted again
      rebuildList(i, n.exit);
      predict(i);
    } else if (!space_.reportsGainedNeighbors()) {
      refileGained(i);
    } else {
      space_.update(i, boxOf(i, n.exit), spaceMargin(i));
      // cells: only the cells entered can hold new neighbours
      if (accelerating(i)) predict(i);
      else predictGained(i);
    }
    settleSpace();
    ++counters_.events[static_cast<int>(EventKind::Boundary)];
    last_ = EventRecord{n.exit, EventKind::Boundary, i, -1};
    return;
  }
  now_ = std::max(now_, n.t);
  switch (n.kind) {
    case EventKind::BallBall: {
      BallState<D>& bj = balls_[n.other];
      if (!bj.active || bj.gen != n.otherGen) {
        ++counters_.staleEvents;
        predict(i);
        return;
      }
      advance(i, n.t);
      advance(n.other, n.t);
      const VelocityPair<D> out = resolveBalls<D>(bi.v, bi.mass, bj.v, bj.mass, bj.p - bi.p);
      bi.v = out.a;
      bj.v = out.b;
      syncMotion(i);
      syncMotion(n.other);
      ++bi.gen;
      ++bj.gen;
      spaceUpdate(i);
      spaceUpdate(n.other);
      predict(i);
      predict(n.other);
      break;
    }
    case EventKind::BallWall:
      advance(i, n.t);
      redirect(i, reflect<D>(bi.v, walls_[n.other].normal));
      break;
    case EventKind::BallSegment:
      if constexpr (D == 2) {
        advance(i, n.t);
        redirect(i, reflect<D>(bi.v, bi.p - closestPointOnSegment(segments_[n.other], bi.p)));
      }
      break;
    case EventKind::BallPoint:
      advance(i, n.t);
      redirect(i, reflect<D>(bi.v, bi.p - points_[n.other]));
      break;
    case EventKind::Sensor:
      deactivate(i);
      break;
    case EventKind::Rest:
      advance(i, n.t);
      redirect(i, Vec<D>::Zero());  // exactly, whatever the rounding of v + a t
      break;
    case EventKind::Boundary:  // boundaryFirst() above
    case EventKind::Model:     // never a ball's event: processModelEvent handles these
    case EventKind::Count:
      return;
  }
  settleSpace();
  ++counters_.events[static_cast<int>(n.kind)];
  last_ = EventRecord{n.t, n.kind, i, n.other};
}

template <int D>
double Simulator<D>::kineticEnergy() const {
  double e = 0.0;
  for (const auto& b : balls_)
    if (b.active) e += 0.5 * b.mass * b.velocityAt(now_).squaredNorm();
  return e;
}

template <int D>
Vec<D> Simulator<D>::momentum() const {
  Vec<D> m = Vec<D>::Zero();
  for (const auto& b : balls_)
    if (b.active) m += b.mass * b.velocityAt(now_);
  return m;
}

template class Simulator<2>;
template class Simulator<3>;

}  // namespace st
