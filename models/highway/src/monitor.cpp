#include <sthighway/monitor.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <unordered_map>

#include <stcore/toi.hpp>

#include <sthighway/tolerances.hpp>

#include "kernels.hpp"

namespace st::highway {

using detail::kInf;

const char* toString(Broadphase b) { return b == Broadphase::Cells ? "cells" : "all-pairs"; }
bool parseBroadphase(const std::string& text, Broadphase& out) {
  if (text == "cells") out = Broadphase::Cells;
  else if (text == "all-pairs" || text == "allpairs") out = Broadphase::AllPairs;
  else return false;
  return true;
}

const char* toString(WarningKind k) {
  switch (k) {
    case WarningKind::Vehicle: return "vehicle";
    case WarningKind::Curb: return "curb";
    case WarningKind::LaneMarker: return "lane_marker";
    case WarningKind::Hazard: return "hazard";
  }
  return "vehicle";
}

namespace {

constexpr std::uint64_t kFeatureBit = std::uint64_t{1} << 63;

WarningKind kindOf(FeatureKind k) {
  switch (k) {
    case FeatureKind::Curb: return WarningKind::Curb;
    case FeatureKind::LaneMarker: return WarningKind::LaneMarker;
    case FeatureKind::Hazard: return WarningKind::Hazard;
  }
  return WarningKind::Curb;
}

Aabb<2> boxOf(const Body& b) {
  const double c = std::abs(b.axis.x()), s = std::abs(b.axis.y());
  const Vec2 h(c * 0.5 * b.length + s * 0.5 * b.width, s * 0.5 * b.length + c * 0.5 * b.width);
  return {b.position - h, b.position + h};
}

void checkFinite(const VehicleState& v) {
  auto bad = [&](const char* field) {
    return std::invalid_argument("vehicle '" + v.id + "': " + field + " must be finite" +
                                 (std::string(field) == "length" || std::string(field) == "width" || std::string(field) == "mass"
                                      ? " and positive" : ""));
  };
  if (!v.position.allFinite()) throw bad("position");
  if (!std::isfinite(v.heading)) throw bad("heading");
  if (!std::isfinite(v.speed)) throw bad("speed");
  if (!std::isfinite(v.lateralSpeed)) throw bad("lateralSpeed");
  if (!std::isfinite(v.acceleration)) throw bad("acceleration");
  if (!(v.length > 0.0) || !std::isfinite(v.length)) throw bad("length");
  if (!(v.width > 0.0) || !std::isfinite(v.width)) throw bad("width");
  if (!(v.mass > 0.0) || !std::isfinite(v.mass)) throw bad("mass");
}

}  // namespace

struct HighwayMonitor::Impl {
  // An open warning, compact (no strings: the pool is rewritten every tick): the names are
  // looked up when it ends, while the foe's slot still holds it (a slot is reused no earlier
  // than the tick after its car left, and every episode against that car ends on that tick).
  struct Episode {
    std::uint64_t key = 0;
    int foe = -1;  // slot, or feature group
    WarningKind kind = WarningKind::Vehicle;
    Zone zone = Zone::Body;
    double begin = 0.0, end = 0.0, minTtc = 0.0, minTtcTime = 0.0, safeTimeAtMin = 0.0;
  };
  struct Threat {
    std::uint64_t key = 0;
    WarningKind kind = WarningKind::Vehicle;
    Zone zone = Zone::Body;
    double ttc = 0.0;
    double safe = 0.0;
    int foe = -1;  // slot, or feature group
  };
  struct Slot {
    std::string id;
    std::uint64_t serial = 0;
    bool present = false;
    Vec2 prev = Vec2::Zero();
    double length = -1.0, width = -1.0, heading = 0.0;  // of the cached axis and envelopes
    Vec2 axis = Vec2(1.0, 0.0);                          // (cos, sin) of heading
  };
  // what the exposure counters need of a car's threats at its last tick
  struct Exposure {
    std::array<double, kWarningKindCount> deficit{};
    std::array<bool, kWarningKindCount> exposed{};
  };

  MonitorConfig cfg;
  RoadFeatures features;
  std::vector<int> groupOf;                 // feature -> group (one polyline or hazard)
  std::vector<std::string> groupName;
  std::vector<FeatureKind> groupKind;
  // a segment feature's line: its first point and unit normal (left of a -> b); line is 0 for
  // hazards and zero-length segments (no line to prune with)
  struct FeatureLine {
    Vec2 a = Vec2::Zero();
    Vec2 b = Vec2::Zero();  // the other end
    Vec2 n = Vec2::Zero();
    int line = 0;
  };
  std::vector<FeatureLine> featureLine;
  // Road features an ego may reach, as its prune reads them: the lines grouped by their normal
  // (up to its sign), so the ego's support, centre and velocity along a normal are computed once
  // per group (a straight road's lines share one), and a line costs a subtraction and a
  // comparison; the features without a line (hazards, zero-length segments) are always checked.
  struct RoadList {
    struct Group {
      Vec2 n;          // unit normal, its sign chosen so the first nonzero component is positive
      int begin, end;  // its lines
    };
    struct Line {
      double c;       // n . (a point of the line)
      double lo, hi;  // the segment along the group's tangent (n.y, -n.x)
      int feature;
    };
    std::vector<Group> groups;
    std::vector<Line> lines;
    std::vector<int> always;
    std::size_t size() const { return lines.size() + always.size(); }
    void clear() {
      groups.clear();
      lines.clear();
      always.clear();
    }
    std::vector<int> source;  // the features it was built from, in the order given
    // from features in any order (scratch: reused storage); kept if they are the last ones
    void build(std::span<const int> features, const std::vector<FeatureLine>& featureLine,
               std::vector<std::pair<Vec2, Line>>& scratch) {
      if (std::equal(features.begin(), features.end(), source.begin(), source.end())) return;
      source.assign(features.begin(), features.end());
      clear();
      scratch.clear();
      for (int fi : features) {
        const FeatureLine& l = featureLine[fi];
        if (!l.line) {
          always.push_back(fi);
          continue;
        }
        const bool flip = l.n.x() < 0.0 || (l.n.x() == 0.0 && l.n.y() < 0.0);
        const Vec2 n = flip ? Vec2(-l.n) : l.n;
        const Vec2 u(n.y(), -n.x());
        const double ua = u.dot(l.a), ub = u.dot(l.b);
        scratch.push_back({n, {n.dot(l.a), std::min(ua, ub), std::max(ua, ub), fi}});
      }
      std::sort(scratch.begin(), scratch.end(), [](const auto& a, const auto& b) {
        if (a.first.x() != b.first.x()) return a.first.x() < b.first.x();
        if (a.first.y() != b.first.y()) return a.first.y() < b.first.y();
        return a.second.feature < b.second.feature;
      });
      for (const auto& [n, line] : scratch) {
        if (groups.empty() || groups.back().n != n) groups.push_back({n, static_cast<int>(lines.size()), 0});
        lines.push_back(line);
        groups.back().end = static_cast<int>(lines.size());
      }
    }
  };
  RoadList allRoad;                         // every feature (all-pairs)
  std::vector<int> roadFound;               // scratch: a bin's features before grouping
  std::vector<std::pair<Vec2, RoadList::Line>> roadScratch;
  std::vector<int> featureNear;             // scratch: the features an ego may reach
  std::optional<Space<2>> featureIndex;
  std::optional<CellNetwork> cells;

  std::unordered_map<std::string, int> slotOf;
  std::vector<Slot> slots;
  std::vector<int> freeSlots;
  std::uint64_t nextSerial = 1;
  std::vector<int> activeSlots;              // present slots, in input order
  std::vector<int> nextActive;               // scratch for the next tick's

  // hot state, struct of arrays by slot
  std::vector<Body> body;
  std::vector<Vec2> centre;                  // body[].position, compact for the pair tests
  std::vector<Vec2> vel;                     // body[].velocity
  std::vector<double> mass, env, accelAbs;
  std::vector<Vec2> ext;                     // envelopeExtent per slot
  std::vector<CarShape> shape;               // carShape per slot
  std::vector<double> brakeRatio;            // m / (2 F_brake) per slot (s per m/s)
  std::vector<VehicleClass> vclass;
  std::vector<std::uint8_t> signals;
  std::vector<char> equipped;
  // what the exact pair test reads of a car, together (copies of the arrays above: the test
  // meets its two cars in no order, and the arrays would be a cache miss each); kept by slot and,
  // for the walks, in member order (memberPairState)
  struct PairState {
    Vec2 ext = Vec2::Zero();        // envelopeExtent
    double env = 0.0;               // envelopeRadius
    double mass = 0.0;
    double twiceBrakeForce = 1.0;   // 2 F_brake of its class
    double outer = 0.0;             // concentric: the outer radius
    std::uint64_t serial = 0;
  };
  std::vector<PairState> pairState;
  // The cells broad phase groups each cell's cars in two bins: 2 c + 0 for its compact cars (light,
  // small, keeping their lane), 2 c + 1 for the rest (heavy or large ones, lane changers). The reach
  // of a walk into a bin grows with the bin's largest brake ratio, envelope and lateral speed, so
  // the few trucks and lane changers no longer widen every walk into their cell: the opposing
  // carriageway's compact bin lies beyond a compact car's reach. Any split gives the same
  // warnings (the bounds hold per bin); a subdivided cell keeps all its cars in bin 2 c.
  std::vector<int> binOf;                    // the car's bin (cells broad phase)
  std::vector<int> wideOf;                   // 1 if the car goes in its cell's second bin
  std::vector<int> inputOf;                  // index in the current span, -1 if absent
  std::vector<Exposure> exposure;
  // Open episodes of every car, contiguous in the order the cars were processed at the last
  // tick (keys ascending per car): a tick reads them in that order and writes the next pool in
  // the same order, so the bookkeeping streams through memory instead of chasing per-car lists.
  std::vector<Episode> pool, poolNext;
  std::vector<int> openBegin, openCount;     // per slot, into pool

  // per-bin bounds of the members' velocities, accelerations and envelopes (cells broad phase)
  struct BinStats {
    Vec2 vmin = Vec2::Zero(), vmax = Vec2::Zero();
    double amax = 0.0, envMax = 0.0;
    Vec2 extMax = Vec2::Zero();
    double kMax = 0.0;          // largest m / (2 F_brake) of its equipped cars (s per m/s)
    double kLight = 0.0;        // the largest below kMax (0 if none): the lighter cars' own list
    double kAll = 0.0;          // largest m / (2 F_brake) of all its cars, equipped or not
    Aabb<2> centres{Vec2::Zero(), Vec2::Zero()};
    int count = 0;
    int equipped = 0;
    bool subdivided = false;
    int axis = 0;               // the long axis of its members' centres

    // an equipped car's brake ratio into kMax and kLight, without a branch (the trucks come in no
    // order): kLight stays the largest ratio below kMax
    void takeRatio(double k) {
      const double lo = std::min(k, kMax), hi = std::max(k, kMax);
      kLight = lo < hi ? std::max(kLight, lo) : kLight;
      kMax = hi;
    }
    // takes in another bin's cars (the bounds as if they had been taken one by one)
    void absorb(const BinStats& o) {
      if (o.count == 0) return;
      if (count == 0) {
        *this = o;
        return;
      }
      vmin = vmin.cwiseMin(o.vmin);
      vmax = vmax.cwiseMax(o.vmax);
      centres.min = centres.min.cwiseMin(o.centres.min);
      centres.max = centres.max.cwiseMax(o.centres.max);
      amax = std::max(amax, o.amax);
      envMax = std::max(envMax, o.envMax);
      extMax = extMax.cwiseMax(o.extMax);
      kAll = std::max(kAll, o.kAll);
      // the two largest distinct ratios of the union are among each side's two (0: none)
      takeRatio(o.kMax);
      takeRatio(o.kLight);
      count += o.count;
      equipped += o.equipped;
    }
  };
  std::vector<BinStats> binStats;

  MonitorCounters counters;
  std::vector<Warning> finished;
  std::vector<Alert> alerts;
  std::vector<Threat> threats;  // scratch
  double lastT = -std::numeric_limits<double>::infinity();
  bool started = false;

  // Time exposed (TET) and integrated deficit (TIT) over the interval dt that just ended, from
  // the threats of its first tick.
  void accumulateExposure(double dt) {
    for (int s : activeSlots)
      for (int k = 0; k < kWarningKindCount; ++k)
        if (exposure[s].exposed[k]) {
          counters.tet[k] += dt;
          counters.tit[k] += dt * exposure[s].deficit[k];
        }
  }

  void ensureSlotArrays(std::size_t n) {
    if (body.size() >= n) return;
    body.resize(n);
    centre.resize(n);
    vel.resize(n);
    mass.resize(n);
    env.resize(n);
    ext.resize(n);
    shape.resize(n);
    brakeRatio.resize(n);
    accelAbs.resize(n);
    vclass.resize(n);
    signals.resize(n);
    equipped.resize(n);
    pairState.resize(n);
    binOf.resize(n);
    wideOf.resize(n);
    inputOf.resize(n, -1);
    exposure.resize(n);
    openBegin.resize(n);
    openCount.resize(n);
  }

  // Slot s's hot state from its vehicle this tick (while the ids are mapped: one pass over the
  // input). Sizes rarely change, headings only on curves and lane changes: the axis (cos, sin)
  // and the envelopes are kept until they do.
  void takeState(int s, const VehicleState& v) {
    Slot& sl = slots[s];
    const DetectorConfig& dc = cfg.detector;
    const bool reshaped = v.length != sl.length || v.width != sl.width || v.heading != sl.heading;
    if (reshaped) sl.axis = v.direction();
    body[s] = bodyOf(v, sl.axis);
    centre[s] = v.position;
    vel[s] = body[s].velocity;
    mass[s] = v.mass;
    if (reshaped) {
      env[s] = envelopeRadius(dc, v.length, v.width);
      ext[s] = envelopeExtent(dc, body[s]);
      shape[s] = carShape(dc, body[s]);
      sl.length = v.length;
      sl.width = v.width;
      sl.heading = v.heading;
    }
    brakeRatio[s] = v.mass / (2.0 * cfg.safeTime.brakeForce[static_cast<int>(v.vehicleClass)]);
    wideOf[s] = static_cast<int>(!(brakeRatio[s] <= tol::kCompactBrakeRatio && ext[s].maxCoeff() <= tol::kCompactExtent &&
                                   std::abs(v.lateralSpeed) <= tol::kCompactLateralSpeed));
    accelAbs[s] = std::abs(v.acceleration);
    vclass[s] = v.vehicleClass;
    pairState[s] = {ext[s], env[s], v.mass, 2.0 * cfg.safeTime.brakeForce[static_cast<int>(v.vehicleClass)], shape[s].outer,
                    sl.serial};
    signals[s] = v.signals;
    equipped[s] = v.equipped ? 1 : 0;
    if (sl.present) counters.vehicleMeters += (v.position - sl.prev).norm();
    sl.prev = v.position;
    sl.present = true;
  }

  Warning warningOf(int e, const Episode& ep, bool open) const {
    return {slots[e].id, ep.kind == WarningKind::Vehicle ? slots[ep.foe].id : groupName[ep.foe], ep.kind, ep.zone, ep.begin,
            ep.end, ep.minTtc, ep.minTtcTime, ep.safeTimeAtMin, open};
  }

  // Ends every open episode of slot s at endTime.
  void close(int s, double endTime) {
    Episode* open = pool.data() + openBegin[s];
    for (int k = 0; k < openCount[s]; ++k) {
      open[k].end = endTime;
      finished.push_back(warningOf(s, open[k], false));
    }
    openCount[s] = 0;
    exposure[s].exposed.fill(false);
  }

  // The pair test, the same for both broad phases (the callers count the candidate pair).
  // First a cheap bound: the closing speed is at most |v_x| + |v_y|, and not positive when the
  // pair separates (p . v > 0, then the safe time is exactly the reaction time), so the safe
  // time is at most the one at that bound; the exact per-axis test is monotone in the horizon,
  // so at the bound it prunes only pairs it prunes at the exact safe time, without a sqrt or a
  // division. p, v: the foe's centre and velocity relative to the ego's; extSum: both envelope
  // extents; k: the ego's m / (2 F_brake). Without branches: an int, 1 if the pair may warn.
  // kAccel false: accel is 0 and the growth term is the slop alone (0.5 * 0 * t^2 == 0 exactly).
  template <bool kAccel>
  static int pairMayWarn(double tr, double k, const Vec2& p, const Vec2& v, const Vec2& extSum, double accel) {
    const double ax = std::abs(v.x()), ay = std::abs(v.y());
    const double closingBound = p.dot(v) > 0.0 ? 0.0 : (ax + ay) * (1.0 + tol::kBoundRelativeSlop);
    const double safeBound = tr + k * closingBound;
    const double grow = kAccel ? 0.5 * accel * safeBound * safeBound + tol::kPruneSlop : tol::kPruneSlop;
    return static_cast<int>(std::abs(p.x()) <= extSum.x() + ax * safeBound + grow) &
           static_cast<int>(std::abs(p.y()) <= extSum.y() + ay * safeBound + grow);
  }

  // The exact test of ego e against foe f; its threat, if it warns, joins the ego's.
  void checkPair(int e, int f, const Vec2& p, const Vec2& v, double accel) {
    Threat th, unused;
    if (pairThreats(e, f, pairState[e], pairState[f], p, v, accel, true, false, th, unused) & 1) threats.push_back(th);
  }

  // The exact pair test in the directions asked: ego e against foe f (p, v: f's centre and
  // velocity relative to e's) and f against e. What the two share is computed once: distance
  // and closing speed (the same expressions either way round: negating p and v changes no
  // product), the envelopes' impact, and for a symmetric detector (vehicleTtcSymmetric) the TTC
  // itself, once. Each direction has its own safe time (and, but for the symmetric detector,
  // its own prunes). Returns bit 0 if e warns (outE), bit 1 if f does (outF): the threats each
  // would give alone, bit for bit.
  [[gnu::flatten]] int pairThreats(int e, int f, const PairState& stateE, const PairState& stateF, const Vec2& p, const Vec2& v,
                  double accel, bool askE, bool askF, Threat& outE, Threat& outF) {
    const double dist = p.norm();
    const double closing = dist > 0.0 ? -p.dot(v) / dist : v.norm();
    const int ego[2] = {e, f};
    const bool ask[2] = {askE, askF};
    double safe[2] = {0.0, 0.0};
    const PairState* state[2] = {&stateE, &stateF};
    Threat* out[2] = {&outE, &outF};
    int warns = 0;
    if (vehicleTtcSymmetric(cfg.detector)) {
      // concentric at constant velocity: the envelopes are the outer circles, so the prunes below
      // would be bounds on the detector's own test: its kernel once (vehicleTtc's concentric
      // case: the outer circles' disc entry, already touching is 0), unbounded, against each
      // direction's safe time
      const double t = detail::discEntry(detail::Piece{p, v, Vec2::Zero(), 0.0, kInf}, Vec2::Zero(),
                                         state[0]->outer + state[1]->outer);
      for (int d = 0; d < 2; ++d) {
        if (!ask[d]) continue;
        ++counters.toiChecks;
        safe[d] = SafeTimeConfig::safeTimeOf(cfg.safeTime.vehicleReactionTime, state[d]->mass, closing,
                                             state[d]->twiceBrakeForce);
        if (!(t <= safe[d])) continue;
        *out[d] = {state[1 - d]->serial, WarningKind::Vehicle, Zone::Outer, t, safe[d], ego[1 - d]};
        warns |= 1 << d;
      }
      return warns;
    }
    bool near[2] = {false, false};
    // exact prune: the envelopes cannot meet within the safe time
    const double envSum = state[0]->env + state[1]->env + tol::kPruneSlop;
    for (int d = 0; d < 2; ++d) {
      if (!ask[d]) continue;
      const PairState &a = *state[d], &b = *state[1 - d];
      safe[d] = SafeTimeConfig::safeTimeOf(cfg.safeTime.vehicleReactionTime, a.mass, closing, a.twiceBrakeForce);
      const double grow = 0.5 * accel * safe[d] * safe[d] + tol::kPruneSlop;
      // per axis, then as discs
      near[d] = std::abs(p.x()) <= a.ext.x() + b.ext.x() + std::abs(v.x()) * safe[d] + grow &&
                std::abs(p.y()) <= a.ext.y() + b.ext.y() + std::abs(v.y()) * safe[d] + grow &&
                !(dist > envSum + v.norm() * safe[d] + grow);
    }
    if (!near[0] && !near[1]) return 0;
    if (accel == 0.0 && dist > envSum) {
      // the envelopes (circles holding every shape a detector uses) do not meet in time
      const Impact hit = toiBalls<2>(p, v, envSum);
      for (int d = 0; d < 2; ++d) near[d] = near[d] && hit.acts() && !(hit.actTime() > safe[d]);
    }
    auto record = [&](int d, const Ttc& ttc) {
      if (!ttc.found() || ttc.t > safe[d]) return;
      const int b = ego[1 - d];
      *out[d] = {state[1 - d]->serial, WarningKind::Vehicle, ttc.zone, ttc.t, safe[d], b};
      warns |= 1 << d;
    };
    for (int d = 0; d < 2; ++d) {
      if (!near[d]) continue;
      ++counters.toiChecks;
      const int a = ego[d], b = ego[1 - d];
      record(d, vehicleTtc(cfg.detector, body[a], shape[a], body[b], shape[b], safe[d]));
    }
    return warns;
  }

  // Exact prune of a segment feature: to touch the segment the shape must first reach its
  // line, which it approaches at most at the normal speed, within at most the largest road safe
  // time hMax (the ego's at its full speed); `support` is how far the shape reaches along the
  // normal. Monotone in the support. Returns an int, 1 if the feature may be reached.
  static int lineReachable(const FeatureLine& l, const Body& a, double support, double hMax, double accel) {
    const double s = l.n.dot(a.position - l.a);
    const Vec2 toward = s > 0.0 ? Vec2(-l.n) : l.n;
    const double approach = std::max(0.0, a.velocity.dot(toward));
    return static_cast<int>(std::abs(s) <= support + approach * hMax + 0.5 * accel * hMax * hMax + tol::kPruneSlop);
  }

  // hMax: at least the ego's largest road safe time (the one at its full speed)
  void checkFeature(int e, int fi, double hMax) {
    const RoadFeature& f = features.features[fi];
    const Body& a = body[e];
    const double accel = cfg.detector.motion == MotionModel::ConstantAcceleration ? accelAbs[e] : 0.0;
    if (featureLine[fi].line) {
      const double s = featureLine[fi].n.dot(a.position - f.segment.a);
      const Vec2 toward = s > 0.0 ? Vec2(-featureLine[fi].n) : featureLine[fi].n;
      if (!lineReachable(featureLine[fi], a, roadSupport(cfg.detector, a, toward), hMax, accel)) return;
    }
    const Vec2 closest = f.kind == FeatureKind::Hazard ? f.segment.a : closestPointOnSegment(f.segment, a.position);
    const Vec2 d = closest - a.position;
    const double dist = d.norm();
    const double closing = dist > 0.0 ? a.velocity.dot(d) / dist : a.velocity.norm();
    const double safe = cfg.safeTime.roadSafeTime(mass[e], closing, vclass[e]);
    if (dist > env[e] + f.radius + a.velocity.norm() * safe + 0.5 * accel * safe * safe + tol::kPruneSlop) return;
    const Ttc ttc = featureTtc(cfg.detector, a, f, safe);
    if (!ttc.found() || ttc.t > safe) return;
    if (f.kind == FeatureKind::LaneMarker) {
      // crossing with the matching turn signal on is a lane change, not a warning
      double side = cross(a.axis, d);
      if (std::abs(side) < 1e-9) side = cross(a.axis, a.velocity);
      const std::uint8_t need = side > 0.0 ? kSignalLeft : kSignalRight;
      if (signals[e] & need) return;
    }
    const int g = groupOf[fi];
    threats.push_back({kFeatureBit | static_cast<std::uint64_t>(g), kindOf(f.kind), ttc.zone, ttc.t, safe, g});
  }

  // The first index in [begin, end) where pred turns false (pred true on a prefix), as
  // std::partition_point, without a branch in its loop
  template <class Pred>
  static int partitionPoint(int begin, int end, Pred pred) {
    if (begin == end || !pred(begin)) return begin;
    int base = begin;  // pred(base) holds
    for (int n = end - begin; n > 1;) {
      const int half = n / 2;
      base = pred(base + half) ? base + half : base;
      n -= half;
    }
    return base + 1;
  }

  // First index in [begin, end) with key[i] >= value (end if none) of sorted keys, as
  // std::lower_bound
  static int lowerBound(const double* key, int begin, int end, double value) {
    return partitionPoint(begin, end, [&](int i) { return key[i] < value; });
  }

  void candidatesVehicles(int e) {
    if (cfg.detector.motion == MotionModel::ConstantAcceleration) candidatesVehiclesFor<true>(e);
    else candidatesVehiclesFor<false>(e);
  }

  // Where the centre of a foe moving with a velocity in [vmin, vmax] (extent up to extMax,
  // |acceleration| up to amax) must lie to meet ego e within the safe time of brake ratio k.
  // Symmetric in the roles but for k: with the larger of the two cars' k it holds for both
  // directions of the pair.
  template <bool kAccel>
  Aabb<2> reachBox(int e, double k, const Vec2& vmin, const Vec2& vmax, const Vec2& extMax, double amax) const {
    return reachBoxOf<kAccel>(centre[e], vel[e], ext[e], accelAbs[e], k, vmin, vmax, extMax, amax);
  }
  // the same for an ego given by its centre, velocity, envelope extent and |acceleration|
  template <bool kAccel>
  Aabb<2> reachBoxOf(const Vec2& pe, const Vec2& ve, const Vec2& exe, double accE, double k, const Vec2& vmin,
                     const Vec2& vmax, const Vec2& extMax, double amax) const {
    const Vec2 up = (vmax - ve).cwiseMax(0.0), down = (ve - vmin).cwiseMax(0.0);
    const double dx = std::max(up.x(), down.x()), dy = std::max(up.y(), down.y());
    const double ac = kAccel ? accE + amax : 0.0;
    const double h = cfg.safeTime.vehicleReactionTime + k * std::sqrt(dx * dx + dy * dy);
    const Vec2 r0 = exe + extMax + Vec2::Constant(0.5 * ac * h * h + tol::kPruneSlop);
    return {pe - (up * h + r0), pe + (down * h + r0)};
  }

  // How far behind and ahead of any car of cell a a member of cell b can lie to meet it within
  // the safe time of brake ratio k: reachBox with every term at its bound over a's cars (the same
  // expressions with larger operands, so the rounding keeps the order; slop: the grown margin).
  struct CellReach {
    Vec2 behind, ahead;
  };
  CellReach cellReach(const BinStats& a, const BinStats& b, double k, bool accel, double slop) const {
    const Vec2 up = (b.vmax - a.vmin).cwiseMax(0.0), down = (a.vmax - b.vmin).cwiseMax(0.0);
    const double dx = std::max(up.x(), down.x()), dy = std::max(up.y(), down.y());
    const double ac = accel ? a.amax + b.amax : 0.0;
    const double h = cfg.safeTime.vehicleReactionTime + k * std::sqrt(dx * dx + dy * dy);
    const Vec2 r0 = a.extMax + b.extMax + Vec2::Constant(0.5 * ac * h * h + slop);
    return {up * h + r0, down * h + r0};
  }

  // The member arrays' data for a walk's locals: through the vectors, every store in the walk
  // (an int) could alias their bounds, and the compiler would reload them each iteration.
  struct MemberView {
    const double* key;
    const Vec2* pos;
    const Vec2* vel;
    const Vec2* ext;
    const double* acc;
    const int* slot;
    const double* brake;
    const int* equipped;
  };
  MemberView memberView() const {
    return {memberKey.data(), memberPos.data(), memberVel.data(), memberExt.data(),
            memberAcc.data(), memberSlot.data(), memberBrake.data(), memberEquipped.data()};
  }
  // 1 if the centre q lies in the box b, else 0: without a branch (walks use it on every member)
  static int inside(const Vec2& q, const Aabb<2>& b) {
    return static_cast<int>(q.x() >= b.min.x()) & static_cast<int>(q.x() <= b.max.x()) &
           static_cast<int>(q.y() >= b.min.y()) & static_cast<int>(q.y() <= b.max.y());
  }

  template <bool kAccel>
  void candidatesVehiclesFor(int e) {
    const Vec2 pe = centre[e];
    const Vec2 ve = vel[e];
    const Vec2 exe = ext[e];
    const double tr = cfg.safeTime.vehicleReactionTime, k = brakeRatio[e];
    if (cfg.broadphase == Broadphase::AllPairs) {
      for (int f : activeSlots)
        if (f != e) considerFoe<kAccel>(e, f, pe, ve, exe, k);
      return;
    }
    const int own = binOf[e];
    for (const Neighbour& c : k <= binStats[own].kLight ? neighboursLight[own] : neighbours[own]) {
      // per axis, with its sign: a member moving at v relative to the ego reaches it within
      // the look-ahead h only from where v carries it towards the ego, so a foe's centre lies
      // within the shapes' extents of the ego, further only behind by (fastest relative
      // velocity forwards) * h and ahead by (fastest backwards) * h; h from the largest speed
      const Aabb<2> cb = reachBox<kAccel>(e, k, c.vmin, c.vmax, c.extMax, c.amax);
      // the reach bounds foe centres: skip a cell none of whose members' centres is inside
      if (!c.centres.overlaps(cb)) continue;
      // a congested (subdivided) cell is searched through its space; a small one through its
      // members sorted along the cell's long axis (from the first inside the reach's range)
      if (c.subdivided) {
        searchSubdivided<kAccel>(e, c.bin / 2, cb);
        continue;
      }
      // the member arrays hold the foes' state in walk order (no slot indirection); the
      // containment and the pair bound are evaluated without branches (their outcomes are
      // unpredictable) and without a call (the loop's state stays in registers): the walk
      // collects the few pairs that pass both, the exact test follows for those, in walk order
      const MemberView mv = memberView();
      const double accE = kAccel ? accelAbs[e] : 0.0;
      const double lo = cb.min[c.axis], hi = cb.max[c.axis];
      const int end = c.end;
      int i = lowerBound(mv.key, c.begin, end, lo);
      if (static_cast<int>(passed.size()) < end - c.begin) passed.resize(end - c.begin);
      int* pass = passed.data();
      int npass = 0;
      std::uint64_t candidates = 0;
      for (; i < end && mv.key[i] <= hi; ++i) {
        const Vec2& q = mv.pos[i];
        const int in = inside(q, cb) & static_cast<int>(mv.slot[i] != e);
        candidates += static_cast<unsigned>(in);
        const Vec2 p = q - pe, v = mv.vel[i] - ve;
        const double accel = kAccel ? accE + mv.acc[i] : 0.0;
        pass[npass] = i;
        npass += in & pairMayWarn<kAccel>(tr, k, p, v, exe + mv.ext[i], accel);
      }
      counters.candidatePairs += candidates;
      for (int j = 0; j < npass; ++j) {
        const int m = pass[j];
        checkPair(e, mv.slot[m], mv.pos[m] - pe, mv.vel[m] - ve, kAccel ? accE + mv.acc[m] : 0.0);
      }
    }
  }

  // Each pair of cars in small (undivided) bins is walked once: within a bin by the car earlier
  // in the member arrays, between two bins by the cars of the bin with fewer of them (pairBins);
  // each pair is tested in each direction whose ego is equipped: half the walks of a search per
  // ego. The reach and the bound use the larger brake ratio of the two (the bin's largest for its
  // members), so they hold for both directions; that widens them, yet it measured faster than
  // leaving each pair to its heavier car (reach at the walker's own ratio, but the trucks walk
  // the other bins too), and the bins keep most trucks out of the compact cars' reach. The
  // threats are grouped by ego (pairFound, a counting sort) for its turn (vehicleThreatsOfPairs).
  struct PairThreat {
    int ego;
    Threat threat;
  };
  std::vector<PairThreat> pairFound;
  std::vector<Threat> pairFoundByEgo;
  std::vector<int> pairFoundStart;       // per slot, into pairFoundByEgo (a counting sort)
  std::vector<std::vector<int>> pairBins;  // per bin A: the bins its cars walk (buildPairBins)

  void findPairsOnce() {
    pairFound.clear();
    if (cfg.detector.motion == MotionModel::ConstantAcceleration) findPairsOnceFor<true>();
    else findPairsOnceFor<false>();
    // by ego (slot), a counting sort
    pairFoundStart.assign(slots.size() + 1, 0);
    for (const PairThreat& pt : pairFound) ++pairFoundStart[pt.ego + 1];
    for (std::size_t s = 0; s < slots.size(); ++s) pairFoundStart[s + 1] += pairFoundStart[s];
    pairFoundByEgo.resize(pairFound.size());
    memberNext.assign(pairFoundStart.begin(), pairFoundStart.end() - 1);
    for (const PairThreat& pt : pairFound) pairFoundByEgo[memberNext[pt.ego]++] = pt.threat;
  }

  template <bool kAccel>
  void findPairsOnceFor() {
    for (int A = 0; A < static_cast<int>(binStats.size()); ++A) {
      const BinStats& ca = binStats[A];
      if (ca.count == 0 || ca.subdivided) continue;
      const int first = memberStart[A], last = memberStart[A + 1];
      if (ca.equipped > 0)
        for (int i = first; i < last; ++i) walkPairsOnce<kAccel, true>(i, A, i + 1);
      for (int B : pairBins[A]) {
        const BinStats& cb = binStats[B];
        // the cars of A whose reach box (walkPairsOnce's) may meet B's centres: a run along A's
        // sorted axis; the rest are skipped without computing their reach
        const auto [behind, ahead] = cellReach(ca, cb, std::max(ca.kAll, cb.kMax), kAccel, tol::kPruneSlop);
        const int a = ca.axis, o = 1 - a;
        // (each test is monotone along the sorted keys: a binary search for where it turns)
        const double* key = memberKey.data();
        const int lo = partitionPoint(first, last, [&](int i) { return !(key[i] + ahead[a] >= cb.centres.min[a]); });
        const int hi = partitionPoint(first, last, [&](int i) { return key[i] - behind[a] <= cb.centres.max[a]; });
        const bool anyEgo = cb.equipped > 0;
        for (int i = lo; i < hi; ++i) {
          const double q = memberPos[i][o];
          if (q - behind[o] <= cb.centres.max[o] && q + ahead[o] >= cb.centres.min[o] && (anyEgo || memberEquipped[i]))
            walkPairsOnce<kAccel, false>(i, B, memberStart[B]);
        }
      }
    }
  }

  // The car at member index ie against cell B's members from index `from` on.
  // kOwn: B is the car's own cell, `from` the next member: its reach holds the car's centre
  // and starts before it along the sorted axis (no overlap test, no search)
  template <bool kAccel, bool kOwn>
  [[gnu::always_inline]] inline void walkPairsOnce(int ie, int B, int from) {
    const BinStats& c = binStats[B];
    // the car's state from the member arrays (copies of its slot's, in walk order: the slot
    // arrays in this order would be a cache miss a car)
    const MemberView mv = memberView();
    const int e = mv.slot[ie];
    const int equippedE = mv.equipped[ie];
    const double kE = mv.brake[ie];
    const Vec2 pe = mv.pos[ie], ve = mv.vel[ie], exe = mv.ext[ie];
    const double accE = kAccel ? mv.acc[ie] : 0.0;
    const Aabb<2> cb = reachBoxOf<kAccel>(pe, ve, exe, accE, std::max(kE, c.kMax), c.vmin, c.vmax, c.extMax, c.amax);
    if (!kOwn && !c.centres.overlaps(cb)) return;
    const double tr = cfg.safeTime.vehicleReactionTime;
    const int end = memberStart[B + 1];
    int i = kOwn ? from : lowerBound(mv.key, from, end, cb.min[c.axis]);
    const double hi = cb.max[c.axis];
    if (static_cast<int>(passed.size()) < end - from) passed.resize(end - from);
    int* pass = passed.data();
    int npass = 0;
    std::uint64_t candidates = 0;
    // as the per-ego walk, without branches; a pair counts once per equipped ego
    for (; i < end && mv.key[i] <= hi; ++i) {
      const Vec2& q = mv.pos[i];
      const int in = inside(q, cb) & (equippedE | mv.equipped[i]);
      candidates += static_cast<unsigned>(in * (equippedE + mv.equipped[i]));
      const Vec2 p = q - pe, v = mv.vel[i] - ve;
      const double accel = kAccel ? accE + mv.acc[i] : 0.0;
      pass[npass] = i;
      npass += in & pairMayWarn<kAccel>(tr, std::max(kE, mv.brake[i]), p, v, exe + mv.ext[i], accel);
    }
    counters.candidatePairs += candidates;
    // each direction with its own ego's bound, then the exact test (the same arithmetic as
    // the per-ego search: p and v from the ego's side)
    for (int j = 0; j < npass; ++j) {
      const int m = pass[j];
      const Vec2 p = mv.pos[m] - pe, v = mv.vel[m] - ve;
      const double accel = kAccel ? accE + mv.acc[m] : 0.0;
      const bool askE = equippedE && pairMayWarn<kAccel>(tr, kE, p, v, exe + mv.ext[m], accel);
      const bool askF = mv.equipped[m] && pairMayWarn<kAccel>(tr, mv.brake[m], p, v, exe + mv.ext[m], accel);
      if (!askE && !askF) continue;
      const int f = mv.slot[m];
      Threat te, tf;
      const int warns = pairThreats(e, f, memberPairState[ie], memberPairState[m], p, v, accel, askE, askF, te, tf);
      if (warns & 1) pairFound.push_back({e, te});
      if (warns & 2) pairFound.push_back({f, tf});
    }
  }

  // Ego e's vehicle threats (its cell undivided): those its pairs walked once found, then the
  // foes in subdivided neighbour cells, searched per ego. The order does not matter: merge
  // orders the threats totally.
  void vehicleThreatsOfPairs(int e) {
    const int own = binOf[e];
    threats.insert(threats.end(), pairFoundByEgo.begin() + pairFoundStart[e], pairFoundByEgo.begin() + pairFoundStart[e + 1]);
    if (neighbours[own].empty()) return;  // no subdivided neighbour
    if (cfg.detector.motion == MotionModel::ConstantAcceleration) searchSubdividedNeighbours<true>(e);
    else searchSubdividedNeighbours<false>(e);
  }
  // (an undivided cell's neighbour entries are its subdivided neighbours')
  template <bool kAccel>
  void searchSubdividedNeighbours(int e) {
    const int own = binOf[e];
    const double k = brakeRatio[e];
    for (const Neighbour& c : k <= binStats[own].kLight ? neighboursLight[own] : neighbours[own]) {
      const Aabb<2> cb = reachBox<kAccel>(e, k, c.vmin, c.vmax, c.extMax, c.amax);
      if (c.centres.overlaps(cb)) searchSubdivided<kAccel>(e, c.bin / 2, cb);
    }
  }

  // Ego e against the members of a congested (subdivided) cell whose centres lie in its reach
  // box cb, found through the cell's space.
  template <bool kAccel>
  void searchSubdivided(int e, int cell, const Aabb<2>& cb) {
    cells->forEachInCellBox(cell, cb, [&](int f) {
      if (f != e && cb.contains(centre[f])) considerFoe<kAccel>(e, f, centre[e], vel[e], ext[e], brakeRatio[e]);
    });
  }
  // A candidate foe by slot: counted, then the cheap bound, then the exact test (pe, ve, exe, k:
  // the ego's centre, velocity, envelope extent and brake ratio, held by the caller's loop).
  template <bool kAccel>
  void considerFoe(int e, int f, const Vec2& pe, const Vec2& ve, const Vec2& exe, double k) {
    ++counters.candidatePairs;
    const Vec2 p = centre[f] - pe, v = vel[f] - ve;
    const double accel = kAccel ? accelAbs[e] + accelAbs[f] : 0.0;
    // most candidates fail the bound: the exact test kept out of the loop's way
    if (pairMayWarn<kAccel>(cfg.safeTime.vehicleReactionTime, k, p, v, exe + ext[f], accel)) [[unlikely]]
      checkPair(e, f, p, v, accel);
  }

  // For every bin with equipped cars, the bins whose members any of them could reach within
  // its largest safe time: bounds over the two bins' velocities, sizes, accelerations, masses.
  void buildNeighbourLists() {
    const bool accel = cfg.detector.motion == MotionModel::ConstantAcceleration;
    const double tr = cfg.safeTime.vehicleReactionTime;
    neighbours.resize(binStats.size());
    neighboursLight.resize(binStats.size());
    nearBins.resize(binStats.size());
    roadNear.resize(binStats.size());
    featureVisits.resize(binStats.size());
    cellsVisits.resize(binStats.size());
    // the signed velocity bounds over all cells with cars, for the box below
    Vec2 vHi = Vec2::Constant(-std::numeric_limits<double>::infinity());
    Vec2 vLo = Vec2::Constant(std::numeric_limits<double>::infinity());
    for (const BinStats& c : binStats)
      if (c.count > 0) {
        vHi = vHi.cwiseMax(c.vmax);
        vLo = vLo.cwiseMin(c.vmin);
      }
    for (int A = 0; A < static_cast<int>(binStats.size()); ++A) {
      neighbours[A].clear();
      neighboursLight[A].clear();
      nearBins[A].clear();
      roadFound.clear();
      const BinStats& ca = binStats[A];
      if (ca.equipped == 0) continue;
      const Vec2 va = ca.vmin.cwiseAbs().cwiseMax(ca.vmax.cwiseAbs());
      // A box holding every cell's reach below, computed as it is but with every operand at its
      // bound over all cells (the fastest of them behind A, the slowest ahead, the largest
      // deceleration term and extent): each operation is monotone, so it holds each reach in
      // floating point too (one more slop for contracted or reordered roundoff). It picks the
      // cells to test from the index and rejects most of them without a square root; the
      // neighbours' order differs from the symmetric box's, and nothing depends on it (merge
      // orders threats totally).
      const Vec2 upG = (vHi - ca.vmin).cwiseMax(0.0), downG = (ca.vmax - vLo).cwiseMax(0.0);
      const double gx = std::max(upG.x(), downG.x()), gy = std::max(upG.y(), downG.y());
      const double ag = accel ? ca.amax + globalAmax : 0.0;
      const double hg = tr + ca.kMax * std::sqrt(gx * gx + gy * gy);
      const Vec2 rg = ca.extMax + globalExtMax + Vec2::Constant(0.5 * ag * hg * hg + 3 * tol::kPruneSlop);
      const Aabb<2> box{ca.centres.min - (upG * hg + rg), ca.centres.max + (downG * hg + rg)};
      for (int cellB : cachedVisit(cells->networkIndex(), box, cellsVisits[A]))
        for (int B = 2 * cellB; B < 2 * cellB + 2; ++B) {
          const BinStats& cb = binStats[B];
          if (cb.count == 0 || !box.overlaps(cb.centres)) continue;
          // signed per axis, as the per-ego reach: B's members lie behind A's by at most their
          // fastest relative velocity forwards times h, ahead by the fastest backwards. The reach
          // grows with the brake ratio k: with kMax for every car of A, with kLight for the cars at
          // or below it (the list they walk is then a subsequence of the full one)
          auto reaches = [&](double k) {
            const CellReach r = cellReach(ca, cb, k, accel, 2 * tol::kPruneSlop);
            return Aabb<2>{ca.centres.min - r.behind, ca.centres.max + r.ahead}.overlaps(cb.centres);
          };
          if (!reaches(ca.kMax)) continue;
          if (!ca.subdivided && !cb.subdivided) {
            nearBins[A].push_back(B);  // its pairs are walked once
            continue;
          }
          const Neighbour nb{cb.vmin, cb.vmax, cb.extMax, cb.centres, cb.amax, memberStart[B], memberStart[B + 1], B,
                             cb.axis, cb.subdivided};
          neighbours[A].push_back(nb);
          if (ca.kLight > 0.0 && reaches(ca.kLight)) neighboursLight[A].push_back(nb);
        }
      // road features any member could reach within its largest road safe time
      if (featureIndex && cfg.checkRoad) {
        const double speed = va.norm();
        const double h = cfg.safeTime.roadReactionTime + ca.kMax * speed;
        const double rr = ca.envMax + speed * h + 0.5 * (accel ? ca.amax : 0.0) * h * h + 2 * tol::kPruneSlop;
        const Aabb<2> rb{ca.centres.min.array() - rr, ca.centres.max.array() + rr};
        // and of those a line only if some member could reach it at its fastest normal speed (a
        // corner of the velocity box), from the nearest of its centres (a corner of the box,
        // or on it): the per-ego prune with every term at the cell's bound
        const double ah = 0.5 * (accel ? ca.amax : 0.0) * h * h + 2 * tol::kPruneSlop;
        for (int fi : cachedVisit(*featureIndex, rb, featureVisits[A])) {
          const FeatureLine& l = featureLine[fi];
          if (l.line) {
            const double s0 = l.n.dot(ca.centres.min - l.a), s1 = l.n.dot(Vec2(ca.centres.max.x(), ca.centres.min.y()) - l.a),
                         s2 = l.n.dot(Vec2(ca.centres.min.x(), ca.centres.max.y()) - l.a), s3 = l.n.dot(ca.centres.max - l.a);
            const double sMin = std::min({s0, s1, s2, s3}), sMax = std::max({s0, s1, s2, s3});
            const double nearest = sMin > 0.0 ? sMin : sMax < 0.0 ? -sMax : 0.0;
            const double approach = std::max({std::abs(l.n.dot(ca.vmin)), std::abs(l.n.dot(ca.vmax)),
                                              std::abs(l.n.dot(Vec2(ca.vmin.x(), ca.vmax.y()))),
                                              std::abs(l.n.dot(Vec2(ca.vmax.x(), ca.vmin.y())))});
            if (nearest > ca.envMax + approach * h + ah) continue;
          }
          roadFound.push_back(fi);
        }
        roadNear[A].build(roadFound, featureLine, roadScratch);
      }
    }
  }
  // The bin pairs walked once (both undivided): those where either bin's cars may reach the
  // other's (the reach is symmetric but for the brake ratio). The bin with fewer cars walks the
  // other (the lower on a tie): a walk's fixed cost (its reach, its search) is paid per walking
  // car, so a cell's few wide cars walk its many compact ones rather than the other way round.
  void buildPairBins() {
    const int nb = static_cast<int>(binStats.size());
    pairBins.resize(nb);
    for (int A = 0; A < nb; ++A) pairBins[A].clear();
    for (int A = 0; A < nb; ++A)
      for (int B : nearBins[A]) {
        if (B == A) continue;
        const int countA = binStats[A].count, countB = binStats[B].count;
        const bool aWalks = countA < countB || (countA == countB && A < B);
        std::vector<int>& list = pairBins[aWalks ? A : B];
        const int other = aWalks ? B : A;
        if (std::find(list.begin(), list.end(), other) == list.end()) list.push_back(other);
      }
  }

  // Per bin, this tick: the bins its cars may meet and the road features they may reach. A
  // neighbour entry holds what the per-ego reach needs, copied so an ego's search reads one array.
  // Only the searches per ego read them: a subdivided cell's bin lists every bin its cars may
  // meet, an undivided cell's bin only the subdivided ones (the undivided ones are in nearBins,
  // their pairs walked once).
  struct Neighbour {
    Vec2 vmin, vmax, extMax;
    Aabb<2> centres;
    double amax;
    int begin, end;  // its members in the member arrays
    int bin;
    int axis;
    bool subdivided;
  };
  std::vector<std::vector<Neighbour>> neighbours;
  std::vector<std::vector<Neighbour>> neighboursLight;  // for the cars with k <= the bin's kLight
  std::vector<std::vector<int>> nearBins;  // per undivided bin: the undivided bins its cars may meet
  std::vector<RoadList> roadNear;
  // What an index's forEachInBox found for a box grown by a tenth of its size, kept while the
  // index is unchanged (its revision) and later boxes lie inside the grown one: a superset of
  // each later box's visit, which every caller filters by its own box (the cells by their
  // centres, the features by the line prune; a hazard is checked exactly per ego). A bin's box
  // drifts metres a tick: it is recomputed every few hundred metres, or when the network index
  // changes (a cell's extent outgrowing its indexed box; the feature index never changes).
  struct IndexVisit {
    Aabb<2> covered{Vec2::Constant(kInf), Vec2::Constant(-kInf)};  // empty: nothing kept
    std::uint64_t revision = ~std::uint64_t{0};
    std::vector<int> ids;
  };
  static const std::vector<int>& cachedVisit(const Space<2>& index, const Aabb<2>& box, IndexVisit& visit) {
    if (index.revision() != visit.revision || !visit.covered.contains(box.min) || !visit.covered.contains(box.max)) {
      const double margin = 0.1 * box.extent().maxCoeff();
      visit.covered = {box.min.array() - margin, box.max.array() + margin};
      visit.revision = index.revision();
      visit.ids.clear();
      index.forEachInBox(visit.covered, [&](int id) { visit.ids.push_back(id); });
    }
    return visit.ids;
  }
  std::vector<IndexVisit> cellsVisits;    // per bin: the network index's cells near it
  std::vector<IndexVisit> featureVisits;  // per bin: the feature index's features near it
  // the cars of every bin, contiguous by bin (memberStart[b] .. memberStart[b + 1]), each bin's
  // sorted by (coordinate along its long axis, slot): key, centre, velocity, envelope extent,
  // |acceleration|, slot
  std::vector<int> memberStart;
  std::vector<int> memberNext;                      // scratch for the counting sort
  std::vector<std::pair<double, int>> memberOrder;  // scratch for the sort
  std::vector<double> memberKey;
  std::vector<Vec2> memberPos;
  std::vector<Vec2> memberVel;
  std::vector<Vec2> memberExt;
  std::vector<double> memberAcc;
  std::vector<int> memberSlot;
  std::vector<int> memberSlotBefore;        // memberSlot at the last tick
  std::vector<std::uint64_t> gathered;      // per slot: the gathering it was placed in
  std::uint64_t gatherStamp = 0;
  std::vector<double> memberBrake;   // m / (2 F_brake)
  std::vector<PairState> memberPairState;
  std::vector<int> memberEquipped;   // 1 or 0
  std::vector<int> passed;  // scratch: member indices whose pair passed the bound
  double globalAmax = 0.0;
  Vec2 globalExtMax = Vec2::Zero();

  void candidatesFeatures(int e) {
    if (!featureIndex) return;
    // a bound on the ego's road safe times (the one at its full speed, grown by the relative
    // slop over the rounding), from the cached brake ratio without roadSafeTime's division: it
    // only prunes, and a larger one prunes less
    const double hMax =
        (cfg.safeTime.roadReactionTime + brakeRatio[e] * vel[e].norm()) * (1.0 + tol::kBoundRelativeSlop);
    const RoadList& list = cfg.broadphase == Broadphase::AllPairs ? allRoad : roadNear[binOf[e]];
    counters.featureChecks += list.size();
    // first every line against a bound on the shape's support towards it (no wider than the
    // envelope, and most lines are further off than that), without branches and without a call:
    // lineReachable with the line's offset from the ego as n . centre - n . a (rounded otherwise,
    // by far less than the prune's slop); checkFeature then prunes with the support itself. The
    // few lines within that reach are pruned again with a tighter horizon: while the ego's
    // centre projects inside the segment, the closest point is the foot of the normal, so the
    // road safe time's closing speed is exactly the approach speed towards the line (tr + k
    // approach, a fraction of hMax for a car keeping its lane); near or beyond an end it may be
    // the full speed (hMax)
    const Body& a = body[e];
    const double accel = cfg.detector.motion == MotionModel::ConstantAcceleration ? accelAbs[e] : 0.0;
    const SupportBound& sb = shape[e].road;
    const Vec2 normal(-a.axis.y(), a.axis.x());
    if (featureNear.size() < list.size()) featureNear.resize(list.size());
    const double tr = cfg.safeTime.roadReactionTime, brake = brakeRatio[e];
    const double grow = 0.5 * accel * hMax * hMax + tol::kPruneSlop;
    int near = 0;
    for (const RoadList::Group& g : list.groups) {
      const double support = (sb.base + sb.along * std::abs(a.axis.dot(g.n)) + sb.across * std::abs(normal.dot(g.n))) *
                             (1.0 + tol::kBoundRelativeSlop);
      const double along = g.n.dot(a.position), speed = g.n.dot(a.velocity);
      for (int j = g.begin; j < g.end; ++j) {
        const RoadList::Line& l = list.lines[j];
        const double offset = along - l.c;
        const double approach = std::max(0.0, offset > 0.0 ? -speed : speed);
        if (!(std::abs(offset) <= support + approach * hMax + grow)) continue;  // most lines
        const double tangent = g.n.y() * a.position.x() - g.n.x() * a.position.y();  // (n.y, -n.x) . centre
        if (tangent > l.lo + tol::kPruneSlop && tangent < l.hi - tol::kPruneSlop) {
          const double h = (tr + brake * approach) * (1.0 + tol::kBoundRelativeSlop);
          if (!(std::abs(offset) <= support + approach * h + 0.5 * accel * h * h + tol::kPruneSlop)) continue;
        }
        featureNear[near++] = l.feature;
      }
    }
    for (int fi : list.always) featureNear[near++] = fi;
    for (int k = 0; k < near; ++k) checkFeature(e, featureNear[k], hMax);
  }

  // Merges ego e's threats of this tick (at time t) into its episodes, from pool to poolNext.
  void merge(int e, double t) {
    Episode* open = pool.data() + openBegin[e];
    const int nOpen = openCount[e];
    openBegin[e] = static_cast<int>(poolNext.size());
    Exposure& x = exposure[e];
    x.exposed.fill(false);
    x.deficit.fill(0.0);
    if (threats.empty() && nOpen == 0) return;  // the common case: nothing now, nothing before
    // the worst threat per key, keys ascending: the smallest TTC, on a tie the longer safe time
    // (the larger deficit), then the zone. A total order, so the episodes and the alert do not
    // depend on the order the broad phase found the threats in.
    if (threats.size() > 1) std::sort(threats.begin(), threats.end(), [](const Threat& a, const Threat& b) {
      if (a.key != b.key) return a.key < b.key;
      if (a.ttc != b.ttc) return a.ttc < b.ttc;
      if (a.safe != b.safe) return a.safe > b.safe;
      return a.zone < b.zone;
    });
    threats.erase(std::unique(threats.begin(), threats.end(), [](const Threat& a, const Threat& b) { return a.key == b.key; }),
                  threats.end());
    // episodes without a threat end, those with one go on, new keys begin
    const int nThreats = static_cast<int>(threats.size());
    int i = 0, j = 0;
    while (i < nOpen || j < nThreats) {
      if (j == nThreats || (i < nOpen && open[i].key < threats[j].key)) {
        Episode& ep = open[i++];
        ep.end = t;
        finished.push_back(warningOf(e, ep, false));
        continue;
      }
      const Threat& th = threats[j++];
      if (i < nOpen && open[i].key == th.key) {
        // copied whole, then updated in the copy (updating the old one first stalls the copy's
        // loads on the stores just made)
        Episode& ep = poolNext.emplace_back(open[i++]);
        ep.end = t;
        if (th.ttc < ep.minTtc) {
          ep.minTtc = th.ttc;
          ep.minTtcTime = t;
          ep.safeTimeAtMin = th.safe;
        }
        continue;
      }
      poolNext.push_back({th.key, th.foe, th.kind, th.zone, t, t, th.ttc, t, th.safe});
      ++counters.warningsBegun;
      ++counters.warningsByKind[static_cast<int>(th.kind)];
      ++counters.warningsByZone[static_cast<int>(th.zone)];
    }
    openCount[e] = static_cast<int>(poolNext.size()) - openBegin[e];
    // exposure and the alert
    const Threat* worst = nullptr;
    for (const Threat& th : threats) {
      const int k = static_cast<int>(th.kind);
      x.exposed[k] = true;
      x.deficit[k] = std::max(x.deficit[k], th.safe - th.ttc);
      if (!worst || th.ttc * worst->safe < worst->ttc * th.safe) worst = &th;
    }
    if (worst)
      alerts.push_back({inputOf[e], worst->kind, worst->zone, worst->ttc, worst->safe,
                        worst->kind == WarningKind::Vehicle ? inputOf[worst->foe] : -1});
  }
};

HighwayMonitor::HighwayMonitor(const RoadGeometry& road, const MonitorConfig& config) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.cfg = config;
  const SafeTimeConfig& st = config.safeTime;
  if (!(st.vehicleReactionTime >= 0.0) || !(st.roadReactionTime >= 0.0))
    throw std::invalid_argument("safe time: reaction times must be non-negative");
  for (double f : st.brakeForce)
    if (!(f > 0.0)) throw std::invalid_argument("safe time: every brake force must be positive");
  if (config.detector.kind == DetectorKind::FiveCircle) {
    // the zones must cover the car or the five-circle TTC is not a conservative envelope
    for (double aspect : {1.0, 2.0, 2.78, 4.7, 8.0})
      if (!layoutCoversBody(config.detector.five, aspect, 1.0))
        throw std::invalid_argument("five-circle layout: front/rear/left/right zones do not cover the car");
  }
  m.features = deriveFeatures(road);
  std::map<std::string, int> groups;
  for (const RoadFeature& f : m.features.features) {
    auto [it, inserted] = groups.emplace(std::string(toString(f.kind)) + "/" + f.name, static_cast<int>(m.groupName.size()));
    if (inserted) {
      m.groupName.push_back(f.name);
      m.groupKind.push_back(f.kind);
    }
    m.groupOf.push_back(it->second);
  }
  for (const RoadFeature& f : m.features.features) {
    const Vec2 dir = f.segment.b - f.segment.a;
    const double len = dir.norm();
    const bool line = f.kind != FeatureKind::Hazard && len > 0.0;
    m.featureLine.push_back(
        {f.segment.a, f.segment.b, line ? Vec2(-dir.y() / len, dir.x() / len) : Vec2(0.0, 0.0), line ? 1 : 0});
  }
  std::vector<int> every(m.featureLine.size());
  for (int i = 0; i < static_cast<int>(every.size()); ++i) every[i] = i;
  m.allRoad.build(every, m.featureLine, m.roadScratch);
  if (!m.features.features.empty()) {
    const Aabb<2> b{m.features.bounds.min.array() - 10.0, m.features.bounds.max.array() + 10.0};
    const double cell = std::max(25.0, b.extent().maxCoeff() / 2048.0);
    m.featureIndex.emplace(SpaceKind::Cells, b, SpaceRule{8, false, 0, 1, cell});
    for (int i = 0; i < static_cast<int>(m.features.features.size()); ++i) {
      const RoadFeature& f = m.features.features[i];
      const Vec2 lo = f.segment.a.cwiseMin(f.segment.b).array() - f.radius;
      const Vec2 hi = f.segment.a.cwiseMax(f.segment.b).array() + f.radius;
      m.featureIndex->insert(i, {lo, hi});
    }
  }
  RoadFeatures forCells = m.features;
  if (forCells.bounds.extent().minCoeff() <= 0.0)
    forCells.bounds = {forCells.bounds.min.array() - 100.0, forCells.bounds.max.array() + 100.0};
  m.cells.emplace(road, forCells, config.cells);
}

HighwayMonitor::~HighwayMonitor() = default;
HighwayMonitor::HighwayMonitor(HighwayMonitor&&) noexcept = default;
HighwayMonitor& HighwayMonitor::operator=(HighwayMonitor&&) noexcept = default;

void HighwayMonitor::step(double t, std::span<const VehicleState> vehicles) {
  Impl& m = *impl_;
  if (!std::isfinite(t)) throw std::invalid_argument("step time must be finite");
  if (m.started && !(t > m.lastT)) throw std::invalid_argument("step times must increase strictly");
  if (m.started) m.accumulateExposure(t - m.lastT);
  // who is here: map ids to slots
  for (int s : m.activeSlots) m.inputOf[s] = -1;
  std::vector<int>& now = m.nextActive;
  now.resize(vehicles.size());  // now[i]: the slot of vehicles[i]
  for (int i = 0; i < static_cast<int>(vehicles.size()); ++i) {
    const VehicleState& v = vehicles[i];
    checkFinite(v);
    if (i < static_cast<int>(m.activeSlots.size())) {
      // the common case: the same vehicle at the same place in the input as at the last tick
      // (no hash of its id); a duplicate id falls through to the lookup, which reports it
      const int s = m.activeSlots[i];
      if (m.inputOf[s] < 0 && m.slots[s].id == v.id) {
        m.inputOf[s] = i;
        now[i] = s;
        m.takeState(s, v);
        continue;
      }
    }
    auto [it, inserted] = m.slotOf.try_emplace(v.id, -1);  // no node built for a known id
    if (inserted) {
      int s;
      if (!m.freeSlots.empty()) {
        s = m.freeSlots.back();
        m.freeSlots.pop_back();
      } else {
        s = static_cast<int>(m.slots.size());
        m.slots.emplace_back();
      }
      it->second = s;
      Impl::Slot& sl = m.slots[s];
      sl = Impl::Slot{};
      sl.id = v.id;
      sl.serial = m.nextSerial++;
      m.ensureSlotArrays(m.slots.size());
      m.openCount[s] = 0;
      m.exposure[s] = Impl::Exposure{};
      sl.prev = v.position;
      ++m.counters.vehiclesSeen;
    }
    const int s = it->second;
    if (m.inputOf[s] >= 0) throw std::invalid_argument("vehicle '" + v.id + "' appears twice at t=" + std::to_string(t));
    m.inputOf[s] = i;
    now[i] = s;
    m.takeState(s, v);
  }
  // vehicles that left: their episodes end at their last tick
  for (int s : m.activeSlots) {
    if (m.inputOf[s] >= 0) continue;
    Impl::Slot& sl = m.slots[s];
    m.close(s, m.lastT);
    sl.present = false;
    if (m.cells) m.cells->remove(s);
    m.slotOf.erase(sl.id);
    m.freeSlots.push_back(s);
  }
  std::swap(m.activeSlots, now);
  m.counters.vehicleUpdates += m.activeSlots.size();
  ++m.counters.ticks;
  // cells: every car measures its sites, hand-offs happen, then the cells' extents are known
  if (m.cfg.broadphase == Broadphase::Cells) {
    // each car placed, and its bin's statistics taken, in one pass; the spaces change cell by
    // cell at the commit (in refreshExtents): in input order consecutive cars are in different
    // cells, and each space's tree would be a cache miss
    const int nc = m.cells->cellCount();
    const int nb = 2 * nc;
    m.binStats.assign(nb, Impl::BinStats{});
    m.memberStart.assign(nb + 1, 0);
    m.globalAmax = 0.0;
    m.globalExtMax = Vec2::Zero();
    for (int s : m.activeSlots) {
      const int bin = 2 * m.cells->placeDeferred(s, m.body[s].position, boxOf(m.body[s]), m.vel[s]) + m.wideOf[s];
      m.binOf[s] = bin;
      Impl::BinStats& c = m.binStats[bin];
      const Vec2& v = m.body[s].velocity;
      if (c.count++ == 0) {
        c.vmin = c.vmax = v;
        c.centres = {m.centre[s], m.centre[s]};
      } else {
        c.vmin = c.vmin.cwiseMin(v);
        c.vmax = c.vmax.cwiseMax(v);
        c.centres.min = c.centres.min.cwiseMin(m.centre[s]);
        c.centres.max = c.centres.max.cwiseMax(m.centre[s]);
      }
      ++m.memberStart[bin + 1];
      c.amax = std::max(c.amax, m.accelAbs[s]);
      c.envMax = std::max(c.envMax, m.env[s]);
      c.extMax = c.extMax.cwiseMax(m.ext[s]);
      c.kAll = std::max(c.kAll, m.brakeRatio[s]);
      if (m.equipped[s]) {
        ++c.equipped;
        c.takeRatio(m.brakeRatio[s]);
      }
      m.globalAmax = std::max(m.globalAmax, m.accelAbs[s]);
      m.globalExtMax = m.globalExtMax.cwiseMax(m.ext[s]);
    }
    m.cells->refreshExtents();
    m.cells->takeHandoffs();
    const CellCounters& cc = m.cells->counters();
    m.counters.handoffs = cc.handoffs;
    m.counters.subdivisions = cc.subdivisions;
    m.counters.reunions = cc.reunions;
    // a subdivided cell's cars all in its first bin (searched through its space)
    for (int c = 0; c < nc; ++c) {
      const SpaceCounters& sc = m.cells->cellSpace(c).counters();
      if (sc.subdivisions <= sc.reunions) continue;
      m.binStats[2 * c].absorb(m.binStats[2 * c + 1]);
      m.binStats[2 * c + 1] = Impl::BinStats{};
      m.binStats[2 * c].subdivided = m.binStats[2 * c + 1].subdivided = true;
      m.memberStart[2 * c + 1] += m.memberStart[2 * c + 2];
      m.memberStart[2 * c + 2] = 0;
    }
    // members contiguous by bin (a counting sort), then each bin's sorted along its long axis
    for (int b = 0; b < nb; ++b) m.memberStart[b + 1] += m.memberStart[b];
    const std::size_t na = m.activeSlots.size();
    m.memberOrder.resize(na);
    m.memberKey.resize(na);
    m.memberPos.resize(na);
    m.memberVel.resize(na);
    m.memberExt.resize(na);
    m.memberAcc.resize(na);
    std::swap(m.memberSlot, m.memberSlotBefore);  // last tick's order, for the gathering below
    m.memberSlot.resize(na);
    m.memberBrake.resize(na);
    m.memberEquipped.resize(na);
    m.memberPairState.resize(na);
    for (Impl::BinStats& cs : m.binStats) {
      if (cs.count == 0) continue;
      const Vec2 ext = cs.centres.extent();
      cs.axis = ext.y() > ext.x() ? 1 : 0;
    }
    // gathered in last tick's member order, then the cars new to it: cars keep their order
    // along the road from tick to tick, so each bin's sort (an insertion sort for a few dozen)
    // finds its run nearly in order; the sort's total order decides the result either way
    m.memberNext.assign(m.memberStart.begin(), m.memberStart.end() - 1);
    ++m.gatherStamp;
    auto gather = [&](int s) {
      if (m.gathered[s] == m.gatherStamp) return;
      m.gathered[s] = m.gatherStamp;
      int bin = m.binOf[s];
      if (m.binStats[bin].subdivided) m.binOf[s] = bin &= ~1;
      m.memberOrder[m.memberNext[bin]++] = {m.centre[s][m.binStats[bin].axis], s};
    };
    m.gathered.resize(m.slots.size());
    for (int s : m.memberSlotBefore)
      if (m.inputOf[s] >= 0) gather(s);
    for (int s : m.activeSlots) gather(s);
    for (int c = 0; c < nb; ++c) {
      // an insertion sort: the run is nearly in order (std::sort partitions a run past 16 first)
      std::pair<double, int>* run = m.memberOrder.data() + m.memberStart[c];
      const int count = m.memberStart[c + 1] - m.memberStart[c];
      for (int i = 1; i < count; ++i) {
        const std::pair<double, int> x = run[i];
        int j = i;
        for (; j > 0 && x < run[j - 1]; --j) run[j] = run[j - 1];
        run[j] = x;
      }
    }
    for (std::size_t i = 0; i < na; ++i) {
      const auto [key, slot] = m.memberOrder[i];
      m.memberKey[i] = key;
      m.memberPos[i] = m.centre[slot];
      m.memberVel[i] = m.vel[slot];
      m.memberExt[i] = m.ext[slot];
      m.memberAcc[i] = m.accelAbs[slot];
      m.memberSlot[i] = slot;
      m.memberBrake[i] = m.brakeRatio[slot];
      m.memberEquipped[i] = m.equipped[slot];
      m.memberPairState[i] = m.pairState[slot];
    }
    m.buildNeighbourLists();
    m.buildPairBins();
    m.findPairsOnce();
  }
  // detection, ego by ego in input order
  m.alerts.clear();
  m.poolNext.clear();
  for (int s : m.activeSlots) {
    if (!m.equipped[s]) {
      m.close(s, t);
      continue;
    }
    m.threats.clear();
    if (m.cfg.broadphase == Broadphase::Cells && !m.binStats[m.binOf[s]].subdivided) m.vehicleThreatsOfPairs(s);
    else m.candidatesVehicles(s);
    if (m.cfg.checkRoad) m.candidatesFeatures(s);
    m.merge(s, t);
  }
  std::swap(m.pool, m.poolNext);
  m.lastT = t;
  m.started = true;
}

void HighwayMonitor::finish(double t) {
  Impl& m = *impl_;
  if (m.started && t > m.lastT) m.accumulateExposure(t - m.lastT);
  for (int s : m.activeSlots) m.close(s, std::max(t, m.lastT));
  m.alerts.clear();
}

std::vector<Warning> HighwayMonitor::takeFinished() {
  std::vector<Warning> out;
  takeFinished(out);
  return out;
}
void HighwayMonitor::takeFinished(std::vector<Warning>& out) {
  out.clear();
  out.swap(impl_->finished);
}

std::vector<Warning> HighwayMonitor::openWarnings() const {
  std::vector<Warning> out;
  const Impl& m = *impl_;
  for (int s : m.activeSlots)
    for (int k = 0; k < m.openCount[s]; ++k) out.push_back(m.warningOf(s, m.pool[m.openBegin[s] + k], true));
  return out;
}

std::span<const Alert> HighwayMonitor::alerts() const { return impl_->alerts; }
const MonitorCounters& HighwayMonitor::counters() const { return impl_->counters; }
const MonitorConfig& HighwayMonitor::config() const { return impl_->cfg; }
const RoadFeatures& HighwayMonitor::features() const { return impl_->features; }
const CellNetwork& HighwayMonitor::cells() const { return *impl_->cells; }
double HighwayMonitor::lastTime() const { return impl_->lastT; }

}  // namespace st::highway
