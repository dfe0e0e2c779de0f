#pragma once
// The car-car test both pair searches share: the reach (where a foe must lie to meet an ego
// within its safe time), the cheap bound on a pair, and the exact test that gives a threat.
// Inline: the searches' innermost calls.
#include <cmath>
#include <cstdint>
#include <vector>

#include <stcore/toi.hpp>
#include <sthighway/tolerances.hpp>

#include "kernels.hpp"
#include "lane_prediction.hpp"
#include "vehicle_table.hpp"

namespace st::highway::detail {

// A threat an ego found this tick: against a vehicle (key: the foe's serial) or a road feature
// group (key: kFeatureBit | group).
struct Threat {
  std::uint64_t key = 0;
  WarningKind kind = WarningKind::Vehicle;
  Zone zone = Zone::Body;
  double ttc = 0.0;
  double safe = 0.0;
  int foe = -1;      // slot, or feature group
  int feature = -1;  // road: the feature that fired (in the padding: the struct stays 40 bytes)
};
static_assert(sizeof(Threat) == 40, "the threat lists are sorted every tick: keep them small");
inline constexpr std::uint64_t kFeatureBit = std::uint64_t{1} << 63;

// How far behind and ahead of an ego a foe's centre can lie and still meet it within the safe
// time of brake ratio k. Per axis, with its sign: a foe moving at v relative to the ego reaches it
// within the look-ahead h only from where v carries it towards the ego, so it lies within the
// shapes' extents (extSum), further only behind by its fastest relative velocity forwards (up)
// times h and ahead by its fastest backwards (down) times h; h from the largest relative speed.
// accelSum: both cars' |acceleration| bounds (0 at constant velocity). Every caller (one car, a
// bin of cars, all bins) passes bounds of its own; each operation is monotone in its operands, so
// a reach from larger bounds holds a reach from smaller ones in floating point too.
struct Reach {
  Vec2 behind, ahead;
};
inline Reach reachOf(double reactionTime, double k, const Vec2& up, const Vec2& down, const Vec2& extSum, double accelSum,
                     double slop) {
  const double dx = std::max(up.x(), down.x()), dy = std::max(up.y(), down.y());
  const double h = SafeTimeConfig::safeTimeBound(reactionTime, k, std::sqrt(dx * dx + dy * dy));
  const Vec2 r0 = extSum + Vec2::Constant(0.5 * accelSum * h * h + slop);
  return {up * h + r0, down * h + r0};
}
// The reach of one ego (centre pe, velocity ve, envelope extent exe, |acceleration| accE) against
// foes with velocities in [vmin, vmax], extents up to extMax, |acceleration| up to amax: the box
// their centres must lie in.
template <bool kAccel>
Aabb<2> reachBoxOf(double reactionTime, const Vec2& pe, const Vec2& ve, const Vec2& exe, double accE, double k,
                   const Vec2& vmin, const Vec2& vmax, const Vec2& extMax, double amax) {
  const Vec2 up = (vmax - ve).cwiseMax(0.0), down = (ve - vmin).cwiseMax(0.0);
  const Reach r = reachOf(reactionTime, k, up, down, exe + extMax, kAccel ? accE + amax : 0.0, tol::kPruneSlop);
  return {pe - r.behind, pe + r.ahead};
}

// 1 if the centre q lies in the box b, else 0: without a branch (walks use it on every member)
inline int inside(const Vec2& q, const Aabb<2>& b) {
  return static_cast<int>(q.x() >= b.min.x()) & static_cast<int>(q.x() <= b.max.x()) &
         static_cast<int>(q.y() >= b.min.y()) & static_cast<int>(q.y() <= b.max.y());
}

// The cheap bound on a pair. The closing speed is at most |v_x| + |v_y|, and not positive when
// the pair separates (p . v > 0, then the safe time is exactly the reaction time), so the safe
// time is at most the one at that bound; the exact per-axis test is monotone in the horizon, so
// at the bound it prunes only pairs it prunes at the exact safe time, without a sqrt or a
// division. p, v: the foe's centre and velocity relative to the ego's; extSum: both envelope
// extents; k: the ego's m / (2 F_brake). Without branches: an int, 1 if the pair may warn.
// kAccel false: accel is 0 and the growth term is the slop alone (0.5 * 0 * t^2 == 0 exactly).
template <bool kAccel>
inline int pairMayWarn(double tr, double k, const Vec2& p, const Vec2& v, const Vec2& extSum, double accel) {
  const double ax = std::abs(v.x()), ay = std::abs(v.y());
  const double closingBound = p.dot(v) > 0.0 ? 0.0 : (ax + ay) * (1.0 + tol::kBoundRelativeSlop);
  const double safeBound = SafeTimeConfig::safeTimeBound(tr, k, closingBound);
  const double grow = kAccel ? 0.5 * accel * safeBound * safeBound + tol::kPruneSlop : tol::kPruneSlop;
  return static_cast<int>(std::abs(p.x()) <= extSum.x() + ax * safeBound + grow) &
         static_cast<int>(std::abs(p.y()) <= extSum.y() + ay * safeBound + grow);
}

// The exact test of a pair, with the table it reads and the counters it keeps.
struct PairTest {
  const MonitorConfig* cfg;
  const VehicleTable* cars;
  MonitorCounters* counters;
  const LanePrediction* paths;  // the cars' predicted paths (straight lines, or along their lanes)

  Ttc ttcOf(int a, int b, double horizon) const { return paths->vehicleTtc(a, b, horizon); }

  double reactionTime() const { return cfg->safeTime.vehicleReactionTime; }

  // The exact pair test in the directions asked: ego e against foe f (p, v: f's centre and
  // velocity relative to e's) and f against e. What the two share is computed once: distance
  // and closing speed (the same expressions either way round: negating p and v changes no
  // product), the envelopes' impact, and for a symmetric detector (vehicleTtcSymmetric) the TTC
  // itself, once. Each direction has its own safe time (and, but for the symmetric detector,
  // its own prunes). Returns bit 0 if e warns (outE), bit 1 if f does (outF): the threats each
  // would give alone, bit for bit.
  [[gnu::flatten]] int pairThreats(int e, int f, const PairState& stateE, const PairState& stateF, const Vec2& p,
                                   const Vec2& v, double accel, bool askE, bool askF, Threat& outE, Threat& outF) const {
    const DetectorConfig& dc = cfg->detector;
    const double dist = p.norm();
    const double closing = dist > 0.0 ? -p.dot(v) / dist : v.norm();
    const int ego[2] = {e, f};
    const bool ask[2] = {askE, askF};
    double safe[2] = {0.0, 0.0};
    const PairState* state[2] = {&stateE, &stateF};
    Threat* out[2] = {&outE, &outF};
    int warns = 0;
    // (a car braking to its stop line: each direction on its own, to its own safe time, as the
    // braking's pieces end at the horizon)
    if (vehicleTtcSymmetric(dc) && !(cars->body[e].stopAcceleration < 0.0) && !(cars->body[f].stopAcceleration < 0.0)) {
      // concentric at constant velocity: the envelopes are the outer circles, so the prunes below
      // would be bounds on the detector's own test: its kernel once (vehicleTtc's concentric
      // case: the outer circles' disc entry, already touching is 0), unbounded, against each
      // direction's safe time
      // (along the paths: the same kernel piece by piece, symmetric too, to the larger safe time)
      for (int d = 0; d < 2; ++d)
        if (ask[d]) safe[d] = SafeTimeConfig::safeTimeOf(reactionTime(), state[d]->mass, closing, state[d]->twiceBrakeForce);
      const double t =
          paths->straight(e) && paths->straight(f)
              ? discEntry(Piece{p, v, Vec2::Zero(), 0.0, kInf}, Vec2::Zero(), state[0]->outer + state[1]->outer).actTime()
              : paths->vehicleTtc(e, f, std::max(ask[0] ? safe[0] : 0.0, ask[1] ? safe[1] : 0.0)).t();
      for (int d = 0; d < 2; ++d) {
        if (!ask[d]) continue;
        ++counters->toiChecks;
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
      safe[d] = SafeTimeConfig::safeTimeOf(reactionTime(), a.mass, closing, a.twiceBrakeForce);
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
      if (!ttc.found() || ttc.t() > safe[d]) return;
      const int b = ego[1 - d];
      *out[d] = {state[1 - d]->serial, WarningKind::Vehicle, ttc.zone, ttc.t(), safe[d], b};
      warns |= 1 << d;
    };
    for (int d = 0; d < 2; ++d) {
      if (!near[d]) continue;
      ++counters->toiChecks;
      const int a = ego[d], b = ego[1 - d];
      record(d, ttcOf(a, b, safe[d]));
    }
    return warns;
  }

  // The exact test of ego e against foe f; its threat, if it warns, joins out.
  void checkPair(int e, int f, const Vec2& p, const Vec2& v, double accel, std::vector<Threat>& out) const {
    Threat th, unused;
    if (pairThreats(e, f, cars->pairState[e], cars->pairState[f], p, v, accel, true, false, th, unused) & 1)
      out.push_back(th);
  }

  // A candidate foe by slot: counted, then the cheap bound, then the exact test (pe, ve, exe, k:
  // the ego's centre, velocity, envelope extent and brake ratio, held by the caller's loop).
  template <bool kAccel>
  void considerFoe(int e, int f, const Vec2& pe, const Vec2& ve, const Vec2& exe, double k, std::vector<Threat>& out) const {
    ++counters->candidatePairs;
    const Vec2 p = cars->centre[f] - pe, v = cars->vel[f] - ve;
    const double accel = kAccel ? cars->accelAbs[e] + cars->accelAbs[f] : 0.0;
    // most candidates fail the bound: the exact test kept out of the loop's way
    if (pairMayWarn<kAccel>(reactionTime(), k, p, v, exe + cars->ext[f], accel)) [[unlikely]]
      checkPair(e, f, p, v, accel, out);
  }
};

}  // namespace st::highway::detail
