#include "kernels.hpp"

#include <algorithm>
#include <cmath>

#include <stcore/roots.hpp>
#include <stcore/toi.hpp>
#include <sthighway/tolerances.hpp>

namespace st::highway::detail {

Track trackOf(const Body& b, MotionModel motion) {
  Track t;
  t.p = b.position;
  t.v = b.velocity;
  if (motion != MotionModel::ConstantAcceleration || std::abs(b.acceleration) <= tol::kAccelerationEpsilon)
    return t;
  // longitudinal speed u changes at rate acc until it reaches zero; cars do not reverse
  const double u = b.velocity.dot(b.axis);
  const double acc = b.acceleration;
  if (u * acc < 0.0) {
    t.a = acc * b.axis;
    t.stop = -u / acc;
    t.vAfter = b.velocity - u * b.axis;
  } else if (u >= 0.0 && acc > 0.0) {
    t.a = acc * b.axis;  // speeding up forwards; a negative acceleration at rest does not reverse
  }
  return t;
}

namespace {

struct State {
  Vec2 p, v, a;
};

State stateAt(const Track& tr, double s) {
  if (s <= tr.stop) return {tr.p + tr.v * s + 0.5 * tr.a * s * s, tr.v + tr.a * s, tr.a};
  const double ts = tr.stop;
  const Vec2 pStop = tr.p + tr.v * ts + 0.5 * tr.a * ts * ts;
  return {pStop + tr.vAfter * (s - ts), tr.vAfter, Vec2::Zero()};
}

}  // namespace

int relativePieces(const Track& ego, const Track& foe, double horizon, std::array<Piece, 3>& out) {
  if (ego.stop == kInf && foe.stop == kInf) {
    // no stop inside: one piece (always so at constant velocity)
    out[0] = Piece{foe.p - ego.p, foe.v - ego.v, foe.a - ego.a, 0.0, horizon};
    return 1;
  }
  std::array<double, 4> cuts{0.0, horizon, horizon, horizon};
  int n = 1;
  for (double s : {ego.stop, foe.stop})
    if (s > 0.0 && s < horizon) cuts[n++] = s;
  std::sort(cuts.begin(), cuts.begin() + n);
  cuts[n] = horizon;
  int count = 0;
  for (int i = 0; i < n; ++i) {
    const double t0 = cuts[i], t1 = cuts[i + 1];
    if (t1 < t0 || (i > 0 && t1 == t0)) continue;
    // just after t0, so a piece that starts at a stop time sees the stopped phase
    const double probe = i == 0 ? t0 : std::nextafter(t0, kInf);
    const State e = stateAt(ego, t0), f = stateAt(foe, t0);
    const bool eStopped = probe > ego.stop, fStopped = probe > foe.stop;
    Piece pc;
    pc.p = f.p - e.p;
    pc.v = (fStopped ? foe.vAfter : f.v) - (eStopped ? ego.vAfter : e.v);
    pc.a = (fStopped ? Vec2::Zero() : foe.a) - (eStopped ? Vec2::Zero() : ego.a);
    pc.start = t0;
    pc.len = t1 - t0;
    out[count++] = pc;
  }
  return count;
}

double discEntryAccelerating(const Piece& pc, const Vec2& p, double radius) {
  // |p + v s + h s^2|^2 = R^2 with h = a / 2: a quartic in s
  const Vec2 h = 0.5 * pc.a;
  const PolynomialRoots roots = solveQuarticInInterval(h.dot(h), 2.0 * pc.v.dot(h), pc.v.dot(pc.v) + 2.0 * p.dot(h),
                                                       2.0 * p.dot(pc.v), p.dot(p) - radius * radius, 0.0, pc.len);
  return roots.count > 0 ? roots.root[0] : kInf;
}

double satEntry(const Piece& pc, const Axis* axes, int count) {
  // overlapping now?
  bool now = true;
  for (int k = 0; k < count && now; ++k)
    now = std::abs(axes[k].n.dot(pc.p) + axes[k].c) <= axes[k].e + tol::kContactSlop;
  if (now) return 0.0;
  if (!pc.accelerating()) {
    // slabs: each axis overlaps on one interval of time; the shapes overlap on their intersection
    double enter = 0.0, exit = pc.len;
    for (int k = 0; k < count; ++k) {
      const double s0 = axes[k].n.dot(pc.p) + axes[k].c;
      const double s1 = axes[k].n.dot(pc.v);
      const double e = axes[k].e;
      if (std::abs(s1) <= 1e-15) {
        if (std::abs(s0) > e) return kInf;
        continue;
      }
      double t1 = (-e - s0) / s1, t2 = (e - s0) / s1;
      if (t1 > t2) std::swap(t1, t2);
      enter = std::max(enter, t1);
      exit = std::min(exit, t2);
      if (enter > exit) return kInf;
    }
    return enter;
  }
  // quadratic motion: the first moment of overlap is a root of some axis' boundary equation
  double cand[32];
  int nc = 0;
  for (int k = 0; k < count; ++k) {
    const double s0 = axes[k].n.dot(pc.p) + axes[k].c;
    const double s1 = axes[k].n.dot(pc.v);
    const double s2 = 0.5 * axes[k].n.dot(pc.a);
    for (double sign : {-1.0, 1.0}) {
      const QuadraticRoots r = solveQuadratic(s2, s1, s0 - sign * axes[k].e);
      for (int i = 0; i < r.count; ++i)
        if (r.root[i] >= 0.0 && r.root[i] <= pc.len && nc < 32) cand[nc++] = r.root[i];
    }
  }
  std::sort(cand, cand + nc);
  for (int i = 0; i < nc; ++i) {
    const double s = cand[i];
    const Vec2 r = pc.p + pc.v * s + 0.5 * pc.a * s * s;
    bool all = true;
    for (int k = 0; k < count && all; ++k) {
      // relative slop: boundary roots carry roundoff proportional to the coordinates
      const double slop = tol::kContactSlop * (1.0 + std::abs(axes[k].e));
      all = std::abs(axes[k].n.dot(r) + axes[k].c) <= axes[k].e + slop;
    }
    if (all) return s;
  }
  return kInf;
}

}  // namespace st::highway::detail
