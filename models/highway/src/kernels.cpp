#include "kernels.hpp"

#include <algorithm>
#include <cmath>

#include <stcore/box2.hpp>
#include <stcore/roots.hpp>
#include <stcore/toi.hpp>
#include <sthighway/tolerances.hpp>

namespace st::highway::detail {

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

double satEntry(const Piece& pc, std::span<const SeparatingAxis> axes) {
  if (!pc.accelerating()) {
    const Impact hit = timeOfEntry(axes, pc.p, pc.v, pc.len, tol::kContactSlop);
    return hit.acts() ? hit.actTime() : kInf;
  }
  if (overlapsOn(axes, pc.p, tol::kContactSlop)) return 0.0;
  // quadratic motion: the first moment of overlap is a root of some axis' boundary equation
  double cand[32];
  int nc = 0;
  for (const SeparatingAxis& ax : axes) {
    const double s0 = ax.n.dot(pc.p);
    const double s1 = ax.n.dot(pc.v);
    const double s2 = 0.5 * ax.n.dot(pc.a);
    for (double sign : {-1.0, 1.0}) {
      const QuadraticRoots r = solveQuadratic(s2, s1, s0 - sign * ax.extent);
      for (int i = 0; i < r.count; ++i)
        if (r.root[i] >= 0.0 && r.root[i] <= pc.len && nc < 32) cand[nc++] = r.root[i];
    }
  }
  std::sort(cand, cand + nc);
  for (int i = 0; i < nc; ++i) {
    const double s = cand[i];
    const Vec2 r = pc.p + pc.v * s + 0.5 * pc.a * s * s;
    bool all = true;
    for (std::size_t k = 0; k < axes.size() && all; ++k) {
      // relative slop: boundary roots carry roundoff proportional to the coordinates
      const double slop = tol::kContactSlop * (1.0 + std::abs(axes[k].extent));
      all = std::abs(axes[k].n.dot(r)) <= axes[k].extent + slop;
    }
    if (all) return s;
  }
  return kInf;
}

}  // namespace st::highway::detail
