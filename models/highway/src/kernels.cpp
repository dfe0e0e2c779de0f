#include "kernels.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace st::highway::detail
