#pragma once
// Exact time-of-impact kernels for bodies moving at constant velocity.
// Each returns what happened, never a magic time:
//   Hit         first contact at t >= 0 while approaching;
//   Miss        no contact in the future (moving apart, passing by, or at rest);
//   Overlapping already interpenetrating deeper than tol::kLinearSlop and approaching: resolve now;
//   Separating  touching or overlapping but moving apart: nothing to do.
// Times are relative to the moment the inputs describe.
#include <cmath>
#include <limits>
#include <stcore/shapes.hpp>
#include <stcore/tolerances.hpp>

namespace st {

enum class Outcome { Hit, Miss, Overlapping, Separating };

struct Impact {
  Outcome outcome = Outcome::Miss;
  double t = std::numeric_limits<double>::infinity();
  bool hit() const { return outcome == Outcome::Hit; }
  // True when the caller must act: a hit at t, or an overlap to resolve at once.
  bool acts() const { return outcome == Outcome::Hit || outcome == Outcome::Overlapping; }
  // When to act: 0 for an overlap, t for a hit, infinity otherwise (a result that does not act
  // carries t = infinity, so callers merge and compare times without testing the outcome).
  double actTime() const { return outcome == Outcome::Overlapping ? 0.0 : t; }
};

// True when a calls for action strictly before b: overlaps first, then hits by time, then
// separating, then misses. Parts of one shape or pieces of one motion are merged with it.
inline bool actsBefore(const Impact& a, const Impact& b) {
  auto rank = [](Outcome o) {
    switch (o) {
      case Outcome::Overlapping: return 0;
      case Outcome::Hit: return 1;
      case Outcome::Separating: return 2;
      case Outcome::Miss: return 3;
    }
    return 3;
  };
  const int ra = rank(a.outcome), rb = rank(b.outcome);
  return ra < rb || (ra == rb && ra == 1 && a.t < b.t);
}
// The earlier of two results (actsBefore); a on a tie.
inline Impact earliest(const Impact& a, const Impact& b) { return actsBefore(b, a) ? b : a; }
// A result for a motion that begins `start` s from now, in time from now (a later piece of a
// piecewise motion): its hit start later; its overlap, at the piece's start, is a hit then.
inline Impact delayed(const Impact& e, double start) {
  if (!e.acts() || start == 0.0) return e;
  return {Outcome::Hit, start + e.actTime()};
}

namespace detail {
// A contact along a line of approach: gap is the signed clearance (negative when overlapping),
// approach the closing speed along the normal (positive when closing).
inline Impact contactAlongNormal(double gap, double approach) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (gap < -tol::kLinearSlop) return approach > 0.0 ? Impact{Outcome::Overlapping, 0.0} : Impact{Outcome::Separating, kInf};
  if (gap <= tol::kLinearSlop) return approach > 0.0 ? Impact{Outcome::Hit, 0.0} : Impact{Outcome::Separating, kInf};
  if (approach <= 0.0) return {Outcome::Miss, kInf};
  return {Outcome::Hit, gap / approach};
}
}  // namespace detail

// Two balls of any dimension, given relative position p_rel = p_b - p_a and relative velocity
// v_rel = v_b - v_a, touching when |p_rel| == radiusSum. Covers circle-circle, sphere-sphere,
// and circle-point (radiusSum = circle radius). Inline: the simulator's innermost loop.
template <int D>
inline Impact toiBalls(const Vec<D>& p_rel, const Vec<D>& v_rel, double radiusSum) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double dist = p_rel.norm();
  const double gap = dist - radiusSum;
  const double b = p_rel.dot(v_rel);  // negative when closing
  if (gap <= tol::kLinearSlop) {
    if (gap < -tol::kLinearSlop) return b < 0.0 ? Impact{Outcome::Overlapping, 0.0} : Impact{Outcome::Separating, kInf};
    return b < 0.0 ? Impact{Outcome::Hit, 0.0} : Impact{Outcome::Separating, kInf};
  }
  if (b >= 0.0) return {Outcome::Miss, kInf};
  const double a = v_rel.squaredNorm();
  if (a <= tol::kSpeedSqEpsilon) return {Outcome::Miss, kInf};
  // |p + v t|^2 = R^2  ->  a t^2 + 2 b t + c = 0 with c = (dist - R)(dist + R), free of the
  // cancellation in dist^2 - R^2; the smaller root is c / (-b + sqrt(b^2 - a c)), stable for b < 0.
  // b^2 - a c is evaluated as a R^2 - |p x v|^2 (Lagrange's identity): b^2 - a |p|^2 cancels when
  // the pair is far apart for its size, costing relative error eps |p|^2 / R^2 in the hit time.
  const double c = gap * (dist + radiusSum);
  double cross2 = 0.0;
  for (int i = 0; i < D; ++i)
    for (int j = i + 1; j < D; ++j) {
      const double m = p_rel[i] * v_rel[j] - p_rel[j] * v_rel[i];
      cross2 += m * m;
    }
  const double disc = a * radiusSum * radiusSum - cross2;
  if (disc <= 0.0) return {Outcome::Miss, kInf};  // passes by, or grazes without exchanging momentum
  return {Outcome::Hit, c / (-b + std::sqrt(disc))};
}

inline Impact toiCircleCircle(const Circle& a, const Vec2& va, const Circle& b, const Vec2& vb) {
  return toiBalls<2>(b.center - a.center, vb - va, a.radius + b.radius);
}
inline Impact toiSphereSphere(const Sphere& a, const Vec3& va, const Sphere& b, const Vec3& vb) {
  return toiBalls<3>(b.center - a.center, vb - va, a.radius + b.radius);
}
// A moving circle and a fixed point (a pocket jaw, a segment end).
inline Impact toiCirclePoint(const Circle& c, const Vec2& v, const Vec2& point) {
  return toiBalls<2>(point - c.center, -v, c.radius);
}

// Which part of a segment a circle meets.
enum class SegmentFeature { Face, EndA, EndB };

struct SegmentImpact {
  Impact impact;
  SegmentFeature feature = SegmentFeature::Face;
};

// A moving circle against a fixed segment, including its end points (the report's Limitation 1):
// the earliest of a tangent contact with the segment's interior and a contact with either end.
SegmentImpact toiCircleSegment(const Circle& c, const Vec2& v, const Segment& s);

// The report's LineIntersect: when the circle's leading edge first touches the infinite line
// through s, passing through it (a space boundary, not an obstacle). Miss if moving parallel or away.
Impact toiCircleLineIntersect(const Circle& c, const Vec2& v, const Segment& s);

// The report's LineDepart: when the circle's trailing edge leaves the infinite line through s,
// i.e. the circle has crossed entirely to the side it is moving to.
Impact toiCircleLineDepart(const Circle& c, const Vec2& v, const Segment& s);

// A ball against the axis-aligned plane x[axis] == coord (3-D cells, 2-D grid lines).
// Entering: the leading surface reaches the plane. Leaving: the trailing surface passes it.
template <int D>
Impact toiBallAxisPlaneEnter(const Ball<D>& b, const Vec<D>& v, int axis, double coord);
template <int D>
Impact toiBallAxisPlaneLeave(const Ball<D>& b, const Vec<D>& v, int axis, double coord);

// A ball against the infinite plane n.x == offset (n unit), approaching from its current side
// (a wall of a box; a line in 2-D).
template <int D>
inline Impact toiBallPlane(const Ball<D>& b, const Vec<D>& v, const Vec<D>& n, double offset) {
  const double d0 = n.dot(b.center) - offset;
  const double side = d0 >= 0.0 ? 1.0 : -1.0;
  return detail::contactAlongNormal(std::abs(d0) - b.radius, -side * n.dot(v));
}
inline Impact toiSpherePlane(const Sphere& s, const Vec3& v, const Vec3& n, double offset) {
  return toiBallPlane<3>({s.center, s.radius}, v, n, offset);
}

// Closest point of a segment to p.
Vec2 closestPointOnSegment(const Segment& s, const Vec2& p);

// ---- accelerated motion (balls decelerating under rolling resistance) ----------------------------
// The same queries when positions are quadratic in time, p(t) = p + v t + a t^2 / 2, valid for
// t in [0, tMax] (until a ball comes to rest). Contacts now are decided as in the kernels above;
// later ones are the first approaching root of a quartic (ball-ball, ball-point) or quadratic
// (plane, segment face) in [0, tMax]. Miss if none.
// A root t in [0, tMax] of |p + v t + a t^2/2| = radiusSum found from the quartic, given back
// the digits the quartic loses when the radii are small against the distance: Newton on the
// distance itself while it is closing (its slope), in small steps only (near a grazing double
// root the slope vanishes and either root is right). Unchanged where the pair is not closing.
template <int D>
double polishBallsRoot(const Vec<D>& p_rel, const Vec<D>& v_rel, const Vec<D>& a_rel, double radiusSum, double t,
                       double tMax);
template <int D>
Impact toiBallsAccelerated(const Vec<D>& p_rel, const Vec<D>& v_rel, const Vec<D>& a_rel, double radiusSum,
                           double tMax);
// The first moment in [0, tMax] the path p_rel + v_rel t + a_rel t^2/2 lies in the closed ball
// |x| <= radius (a warning's question, not a collision's: touching counts, a graze included, and
// the velocity now does not matter): Overlapping (t = 0) if it already does, Hit at the first root
// of the same quartic as toiBallsAccelerated, else Miss. A small ball passed almost through its
// centre makes two roots radius / |v| apart, a near double root the quartic about t = 0 resolves
// only to about the square root of its roundoff; the root is re-solved from the quartic about
// itself, where the relative position is about radius long, then polished (polishBallsRoot).
template <int D>
Impact toiBallsEntryAccelerated(const Vec<D>& p_rel, const Vec<D>& v_rel, const Vec<D>& a_rel, double radius,
                                double tMax);
template <int D>
Impact toiBallPlaneAccelerated(const Ball<D>& b, const Vec<D>& v, const Vec<D>& a, const Vec<D>& n, double offset,
                               double tMax);
SegmentImpact toiCircleSegmentAccelerated(const Circle& c, const Vec2& v, const Vec2& a, const Segment& s,
                                          double tMax);

}  // namespace st
