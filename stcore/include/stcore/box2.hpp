#pragma once
// The oriented box in the plane (Box2 in shapes.hpp; a car's footprint) and its pair queries.
// Kernels on plain numbers (separating axes, a relative position and velocity) are wrapped by the
// Box2 functions, so a caller with its own motion (the highway's braking cars) reuses the axes:
//   separatingAxes  the four axes of a box pair, each with the sum of the projections' radii;
//   separation      the largest gap between the projections: > 0 when apart, never above the distance;
//   overlaps        closed: touching boxes overlap;
//   distance        separation distance, 0 when touching or overlapping;
//   distanceApart   the same for two boxes whose separation is > 0 (a caller that has it);
//   timeOfEntry     the first time two boxes overlap under straight relative motion;
//   timeOfEntryAccelerated  the same under constant relative acceleration (a braking car).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>

#include <stcore/shapes.hpp>
#include <stcore/toi.hpp>

namespace st {

// One separating axis of two convex shapes: along the unit direction n their projections overlap
// when |n . p_rel| <= extent (p_rel = centre of b - centre of a).
struct SeparatingAxis {
  Vec2 n;
  double extent = 0.0;
};

// Corners counter-clockwise from (+x, +y) of the box frame.
std::array<Vec2, 4> corners(const Box2& b);
// How far the box reaches from its centre along the unit direction n.
inline double support(const Box2& b, const Vec2& n) {
  return b.halfExtents.x() * std::abs(b.axis.dot(n)) + b.halfExtents.y() * std::abs(b.normal().dot(n));
}

// a's axis and normal, then b's; each extent is support(a, n) + support(b, n) in full (a box's
// own axes included, not taken as exactly orthonormal). Inline, as separation: the box
// detector's and hindsight's per-pair calls.
inline std::array<SeparatingAxis, 4> separatingAxes(const Box2& a, const Box2& b) {
  const Vec2 dirs[4] = {a.axis, a.normal(), b.axis, b.normal()};
  std::array<SeparatingAxis, 4> axes;
  for (int k = 0; k < 4; ++k) axes[k] = {dirs[k], support(a, dirs[k]) + support(b, dirs[k])};
  return axes;
}
inline double separation(const Box2& a, const Box2& b) {
  // on a box's own axes its projection is its half extent
  const Vec2 d = b.center - a.center;
  const Vec2 an = a.normal(), bn = b.normal();
  const double ca = std::abs(a.axis.dot(b.axis)), cb = std::abs(a.axis.dot(bn)), cc = std::abs(an.dot(b.axis)),
               cd = std::abs(an.dot(bn));
  const double la = a.halfExtents.x(), wa = a.halfExtents.y(), lb = b.halfExtents.x(), wb = b.halfExtents.y();
  return std::max({std::abs(d.dot(a.axis)) - la - lb * ca - wb * cb, std::abs(d.dot(an)) - wa - lb * cc - wb * cd,
                   std::abs(d.dot(b.axis)) - lb - la * ca - wa * cc, std::abs(d.dot(bn)) - wb - la * cb - wa * cd});
}
inline bool overlaps(const Box2& a, const Box2& b) { return separation(a, b) <= 0.0; }
// True when the segment touches the box (closed).
bool overlaps(const Segment& s, const Box2& b);

double distanceSq(const Vec2& p, const Box2& b);
inline double distance(const Vec2& p, const Box2& b) { return std::sqrt(distanceSq(p, b)); }
// Two boxes whose separation is > 0: the distance, corner to box (what distance() returns for
// them, bit for bit, without taking the separation again).
double distanceApart(const Box2& a, const Box2& b);
double distance(const Box2& a, const Box2& b);

// Time of entry is an overlap query, not a contact: Overlapping (t = 0) when the shapes overlap
// now on every axis within slop (m), whatever their motion; Hit at the first t in [0, horizon]
// at which they overlap on every axis; Miss if there is none. Exact for convex polygons when the
// axes are all their edge normals.
bool overlapsOn(std::span<const SeparatingAxis> axes, const Vec2& p_rel, double slop);
Impact timeOfEntry(std::span<const SeparatingAxis> axes, const Vec2& p_rel, const Vec2& v_rel, double horizon,
                   double slop);
// The same when p_rel(t) = p_rel + v_rel t + a_rel t^2 / 2. Each axis overlaps on at most two
// intervals, so the first moment of overlap is a root of some axis' boundary equation
// n . p_rel(t) = +-extent: the earliest root in [0, horizon] at which every axis overlaps within
// slop (1 + extent / 1 m), a slop relative to the coordinates because the roots carry roundoff
// proportional to them. At most kMaxEntryAxes axes.
inline constexpr std::size_t kMaxEntryAxes = 8;
Impact timeOfEntryAccelerated(std::span<const SeparatingAxis> axes, const Vec2& p_rel, const Vec2& v_rel,
                              const Vec2& a_rel, double horizon, double slop);
// b moving at v_rel relative to a.
inline Impact timeOfEntry(const Box2& a, const Box2& b, const Vec2& v_rel, double horizon,
                          double slop = tol::kLinearSlop) {
  const std::array<SeparatingAxis, 4> axes = separatingAxes(a, b);
  return timeOfEntry(axes, b.center - a.center, v_rel, horizon, slop);
}

}  // namespace st
