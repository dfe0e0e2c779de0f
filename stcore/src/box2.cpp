#include <stcore/box2.hpp>

#include <algorithm>
#include <limits>

#include <stcore/assert.hpp>
#include <stcore/roots.hpp>
#include <stcore/tolerances.hpp>

namespace st {

std::array<Vec2, 4> corners(const Box2& b) {
  const Vec2 hx = b.halfExtents.x() * b.axis, hy = b.halfExtents.y() * b.normal();
  return {b.center + hx + hy, b.center - hx + hy, b.center - hx - hy, b.center + hx - hy};
}

double distanceSq(const Vec2& p, const Box2& b) {
  const Vec2 d = p - b.center;
  const double u = std::max(0.0, std::abs(d.dot(b.axis)) - b.halfExtents.x());
  const double w = std::max(0.0, std::abs(d.dot(b.normal())) - b.halfExtents.y());
  return u * u + w * w;
}

double distance(const Box2& a, const Box2& b) { return separation(a, b) <= 0.0 ? 0.0 : distanceApart(a, b); }

double distanceApart(const Box2& a, const Box2& b) {
  // apart: the distance is reached at a corner of one against the other
  double best = std::numeric_limits<double>::infinity();
  for (const Vec2& c : corners(a)) best = std::min(best, distanceSq(c, b));
  for (const Vec2& c : corners(b)) best = std::min(best, distanceSq(c, a));
  return std::sqrt(best);
}

bool overlaps(const Segment& s, const Box2& b) {
  // separating axes: the box's two and the segment's normal
  const Vec2 axes[2] = {b.axis, b.normal()};
  for (int k = 0; k < 2; ++k) {
    const double pa = axes[k].dot(s.a - b.center), pb = axes[k].dot(s.b - b.center), h = b.halfExtents[k];
    if (std::min(pa, pb) > h || std::max(pa, pb) < -h) return false;
  }
  const Vec2 dir = s.b - s.a;
  if (dir.squaredNorm() == 0.0) return distanceSq(s.a, b) == 0.0;
  const Vec2 n = Vec2(-dir.y(), dir.x()).normalized();
  return std::abs(n.dot(b.center - s.a)) <= support(b, n);
}

bool overlapsOn(std::span<const SeparatingAxis> axes, const Vec2& p_rel, double slop) {
  for (const SeparatingAxis& ax : axes)
    if (!(std::abs(ax.n.dot(p_rel)) <= ax.extent + slop)) return false;
  return true;
}

Impact timeOfEntry(std::span<const SeparatingAxis> axes, const Vec2& p_rel, const Vec2& v_rel, double horizon,
                   double slop) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (overlapsOn(axes, p_rel, slop)) return {Outcome::Overlapping, 0.0};
  // slabs: each axis overlaps on one interval of time; the shapes overlap on their intersection
  double enter = 0.0, exit = horizon;
  for (const SeparatingAxis& ax : axes) {
    const double s0 = ax.n.dot(p_rel), s1 = ax.n.dot(v_rel), e = ax.extent;
    if (std::abs(s1) <= tol::kParallelSpeed) {
      if (std::abs(s0) > e) return {Outcome::Miss, kInf};
      continue;
    }
    double t1 = (-e - s0) / s1, t2 = (e - s0) / s1;
    if (t1 > t2) std::swap(t1, t2);
    enter = std::max(enter, t1);
    exit = std::min(exit, t2);
    if (enter > exit) return {Outcome::Miss, kInf};
  }
  return {Outcome::Hit, enter};
}

Impact timeOfEntryAccelerated(std::span<const SeparatingAxis> axes, const Vec2& p_rel, const Vec2& v_rel,
                              const Vec2& a_rel, double horizon, double slop) {
  STCORE_ASSERT(axes.size() <= kMaxEntryAxes);
  if (overlapsOn(axes, p_rel, slop)) return {Outcome::Overlapping, 0.0};
  // every boundary crossing in [0, horizon]: two roots per side, two sides per axis
  double cand[4 * kMaxEntryAxes];
  int nc = 0;
  for (const SeparatingAxis& ax : axes) {
    const double s0 = ax.n.dot(p_rel);
    const double s1 = ax.n.dot(v_rel);
    const double s2 = 0.5 * ax.n.dot(a_rel);
    for (double sign : {-1.0, 1.0}) {
      const QuadraticRoots r = solveQuadratic(s2, s1, s0 - sign * ax.extent);
      for (int i = 0; i < r.count; ++i)
        if (r.root[i] >= 0.0 && r.root[i] <= horizon && nc < 4 * int(kMaxEntryAxes)) cand[nc++] = r.root[i];
    }
  }
  std::sort(cand, cand + nc);
  for (int i = 0; i < nc; ++i) {
    const double t = cand[i];
    const Vec2 r = p_rel + v_rel * t + 0.5 * a_rel * t * t;
    bool all = true;
    for (std::size_t k = 0; k < axes.size() && all; ++k)
      all = std::abs(axes[k].n.dot(r)) <= axes[k].extent + slop * (1.0 + std::abs(axes[k].extent));
    if (all) return {Outcome::Hit, t};
  }
  return {Outcome::Miss, std::numeric_limits<double>::infinity()};
}

}  // namespace st
