#include <stcore/toi.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stcore/roots.hpp>
#include <stcore/tolerances.hpp>

namespace st {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Impact hitAt(double t) { return {Outcome::Hit, t}; }
Impact overlapping() { return {Outcome::Overlapping, 0.0}; }
Impact separating() { return {Outcome::Separating, kInf}; }
Impact miss() { return {Outcome::Miss, kInf}; }

using detail::contactAlongNormal;

// Earliest acting impact of several (actsBefore); the first on a tie.
void keepEarliest(SegmentImpact& best, const Impact& candidate, SegmentFeature feature) {
  if (actsBefore(candidate, best.impact)) best = {candidate, feature};
}

// Touching or overlapping now: the closest feature alone decides. Asked one by one, the features
// would report an end point approached, or struck later, by a ball moving out of the face.
std::optional<SegmentImpact> segmentContactNow(const Circle& c, const Vec2& v, const Segment& s) {
  const Vec2 dir = s.b - s.a;
  const double len2 = dir.squaredNorm();
  const double u0 = len2 > 0.0 ? std::clamp((c.center - s.a).dot(dir) / len2, 0.0, 1.0) : 0.0;
  const Vec2 out0 = c.center - (s.a + u0 * dir);
  const double dist0 = out0.norm();
  if (dist0 - c.radius > tol::kLinearSlop) return std::nullopt;
  const SegmentFeature f = u0 <= 0.0 ? SegmentFeature::EndA : u0 >= 1.0 ? SegmentFeature::EndB : SegmentFeature::Face;
  if (dist0 == 0.0) return SegmentImpact{separating(), f};  // centre on the segment: no normal to approach along
  return SegmentImpact{contactAlongNormal(dist0 - c.radius, -out0.dot(v) / dist0), f};
}

}  // namespace

SegmentImpact toiCircleSegment(const Circle& c, const Vec2& v, const Segment& s) {
  if (auto now = segmentContactNow(c, v, s)) return *now;
  SegmentImpact best{miss(), SegmentFeature::Face};
  const Vec2 dir = s.b - s.a;
  const double len2 = dir.squaredNorm();
  if (len2 > 0.0) {
    const Vec2 n = Vec2(-dir.y(), dir.x()) / std::sqrt(len2);
    const double d0 = n.dot(c.center - s.a);
    const double side = d0 >= 0.0 ? 1.0 : -1.0;
    const Impact face = contactAlongNormal(std::abs(d0) - c.radius, -side * n.dot(v));
    if (face.outcome != Outcome::Miss) {
      // the tangent point must lie on the segment's interior at the time of contact
      const double tAt = face.outcome == Outcome::Hit ? face.t : 0.0;
      const double u = (c.center + v * tAt - s.a).dot(dir) / len2;
      if (u >= 0.0 && u <= 1.0) keepEarliest(best, face, SegmentFeature::Face);
    }
  }
  keepEarliest(best, toiBalls<2>(s.a - c.center, -v, c.radius), SegmentFeature::EndA);
  keepEarliest(best, toiBalls<2>(s.b - c.center, -v, c.radius), SegmentFeature::EndB);
  return best;
}

Impact toiCircleLineIntersect(const Circle& c, const Vec2& v, const Segment& s) {
  const Vec2 n = s.normal();
  const double d0 = n.dot(c.center - s.a);
  if (std::abs(d0) <= c.radius) return overlapping();
  const double approach = -(d0 >= 0.0 ? 1.0 : -1.0) * n.dot(v);
  if (approach <= 0.0) return miss();
  return hitAt((std::abs(d0) - c.radius) / approach);
}

Impact toiCircleLineDepart(const Circle& c, const Vec2& v, const Segment& s) {
  const Vec2 n = s.normal();
  const double vn = n.dot(v);
  if (vn * vn <= tol::kSpeedSqEpsilon) return miss();
  const double d0 = n.dot(c.center - s.a);
  const double t = (std::copysign(c.radius, vn) - d0) / vn;
  return t >= 0.0 ? hitAt(t) : miss();
}

template <int D>
Impact toiBallAxisPlaneEnter(const Ball<D>& b, const Vec<D>& v, int axis, double coord) {
  const double offset = coord - b.center[axis];
  const double gap = std::abs(offset) - b.radius;
  if (gap <= 0.0) return overlapping();
  const double approach = std::copysign(1.0, offset) * v[axis];
  if (approach <= 0.0) return miss();
  return hitAt(gap / approach);
}

template <int D>
Impact toiBallAxisPlaneLeave(const Ball<D>& b, const Vec<D>& v, int axis, double coord) {
  const double vx = v[axis];
  if (vx == 0.0) return miss();
  const double t = (coord - b.center[axis] + std::copysign(b.radius, vx)) / vx;
  return t >= 0.0 ? hitAt(t) : miss();
}

template Impact toiBallAxisPlaneEnter<2>(const Ball<2>&, const Vec2&, int, double);
template Impact toiBallAxisPlaneEnter<3>(const Ball<3>&, const Vec3&, int, double);
template Impact toiBallAxisPlaneLeave<2>(const Ball<2>&, const Vec2&, int, double);
template Impact toiBallAxisPlaneLeave<3>(const Ball<3>&, const Vec3&, int, double);

namespace {

// First root of h(t) = h0 + hv t + ha t^2 / 2 in [0, tMax] where h is falling.
double firstFallingRoot(double h0, double hv, double ha, double tMax) {
  const QuadraticRoots q = solveQuadratic(0.5 * ha, hv, h0);
  for (int k = 0; k < q.count; ++k) {
    const double t = q.root[k];
    if (t >= 0.0 && t <= tMax && hv + ha * t < 0.0) return t;
  }
  return kInf;
}

}  // namespace

template <int D>
double polishBallsRoot(const Vec<D>& p_rel, const Vec<D>& v_rel, const Vec<D>& a_rel, double radiusSum, double t,
                       double tMax) {
  // the quartic's constant term cancels against the rest near a root; the distance's slope is
  // the closing speed
  for (int it = 0; it < 2; ++it) {
    const Vec<D> x = p_rel + t * v_rel + (0.5 * t * t) * a_rel;
    const double len = x.norm();
    const double slope = x.dot(v_rel + t * a_rel) / len;
    if (!(slope < 0.0)) break;
    const double step = (len - radiusSum) / slope;
    const double next = t - step;
    if (!(std::abs(step) <= 1e-6 * std::max(1.0, t)) || next < 0.0 || next > tMax) break;
    t = next;
  }
  return t;
}

template double polishBallsRoot<2>(const Vec2&, const Vec2&, const Vec2&, double, double, double);
template double polishBallsRoot<3>(const Vec3&, const Vec3&, const Vec3&, double, double, double);

namespace {

// The roots in [lo, hi] of |p + v t + a t^2/2|^2 = R^2, a quartic in t, its constant term as
// (|p| - R)(|p| + R), free of the cancellation p.p - R^2 suffers at small radii.
template <int D>
PolynomialRoots ballsQuarticRoots(const Vec<D>& p, const Vec<D>& v, const Vec<D>& a, double radius, double lo,
                                  double hi) {
  const double dist = p.norm();
  return solveQuarticInInterval(0.25 * a.squaredNorm(), v.dot(a), v.squaredNorm() + p.dot(a), 2.0 * p.dot(v),
                                (dist - radius) * (dist + radius), lo, hi);
}

}  // namespace

template <int D>
Impact toiBallsAccelerated(const Vec<D>& p_rel, const Vec<D>& v_rel, const Vec<D>& a_rel, double radiusSum,
                           double tMax) {
  const double dist = p_rel.norm();
  const double gap = dist - radiusSum;
  const double b = p_rel.dot(v_rel);
  if (gap <= tol::kLinearSlop) {  // in contact now: the current velocity decides, as in toiBalls
    if (gap < -tol::kLinearSlop) return b < 0.0 ? overlapping() : separating();
    return b < 0.0 ? hitAt(0.0) : separating();
  }
  if (!(tMax > 0.0)) return miss();
  const PolynomialRoots r = ballsQuarticRoots<D>(p_rel, v_rel, a_rel, radiusSum, 0.0, tMax);
  for (int k = 0; k < r.count; ++k) {
    double t = r.root[k];
    const Vec<D> d = p_rel + t * v_rel + (0.5 * t * t) * a_rel;
    // closing at the root; a double root (grazing, no momentum exchanged) is not a hit
    if (d.dot(v_rel + t * a_rel) < 0.0) return hitAt(polishBallsRoot<D>(p_rel, v_rel, a_rel, radiusSum, t, tMax));
  }
  return miss();
}

template Impact toiBallsAccelerated<2>(const Vec2&, const Vec2&, const Vec2&, double, double);
template Impact toiBallsAccelerated<3>(const Vec3&, const Vec3&, const Vec3&, double, double);

template <int D>
Impact toiBallsEntryAccelerated(const Vec<D>& p_rel, const Vec<D>& v_rel, const Vec<D>& a_rel, double radius,
                                double tMax) {
  if (p_rel.squaredNorm() <= radius * radius) return overlapping();
  const PolynomialRoots first = ballsQuarticRoots<D>(p_rel, v_rel, a_rel, radius, 0.0, tMax);
  if (first.count == 0) return miss();
  // the same quartic about its first root resolves a near double root; then the distance polishes it
  const double t0 = first.root[0];
  const Vec<D> p0 = p_rel + v_rel * t0 + (0.5 * t0 * t0) * a_rel, v0 = v_rel + a_rel * t0;
  const PolynomialRoots near = ballsQuarticRoots<D>(p0, v0, a_rel, radius, -t0, tMax - t0);
  const double t = near.count > 0 ? std::clamp(t0 + near.root[0], 0.0, tMax) : t0;
  return hitAt(polishBallsRoot<D>(p_rel, v_rel, a_rel, radius, t, tMax));
}

template Impact toiBallsEntryAccelerated<2>(const Vec2&, const Vec2&, const Vec2&, double, double);
template Impact toiBallsEntryAccelerated<3>(const Vec3&, const Vec3&, const Vec3&, double, double);

template <int D>
Impact toiBallPlaneAccelerated(const Ball<D>& b, const Vec<D>& v, const Vec<D>& a, const Vec<D>& n, double offset,
                               double tMax) {
  const double d0 = n.dot(b.center) - offset;
  const double side = d0 >= 0.0 ? 1.0 : -1.0;
  const double gap = std::abs(d0) - b.radius;
  if (gap <= tol::kLinearSlop) return contactAlongNormal(gap, -side * n.dot(v));
  const double t = firstFallingRoot(gap, side * n.dot(v), side * n.dot(a), tMax);
  return t < kInf ? hitAt(t) : miss();
}

template Impact toiBallPlaneAccelerated<2>(const Ball<2>&, const Vec2&, const Vec2&, const Vec2&, double, double);
template Impact toiBallPlaneAccelerated<3>(const Ball<3>&, const Vec3&, const Vec3&, const Vec3&, double, double);

SegmentImpact toiCircleSegmentAccelerated(const Circle& c, const Vec2& v, const Vec2& a, const Segment& s,
                                          double tMax) {
  if (auto now = segmentContactNow(c, v, s)) return *now;
  SegmentImpact best{miss(), SegmentFeature::Face};
  const Vec2 dir = s.b - s.a;
  const double len2 = dir.squaredNorm();
  if (len2 > 0.0) {
    const Vec2 n = Vec2(-dir.y(), dir.x()) / std::sqrt(len2);
    const double d0 = n.dot(c.center - s.a);
    // A curved path can pass the line beyond an end and come back at the face from the other
    // side, so both sides are tried. Each side's clearance is a quadratic with one falling root
    // at most: the near side's first root, the far side's second (after the path crosses). (Not
    // in contact now, so a ball already within r of the line is beyond an end.)
    for (const double side : {1.0, -1.0}) {
      const double t = firstFallingRoot(side * d0 - c.radius, side * n.dot(v), side * n.dot(a), tMax);
      if (t == kInf) continue;
      // the tangent point must lie on the segment's interior at the time of contact
      const double u = (c.center + v * t + (0.5 * t * t) * a - s.a).dot(dir) / len2;
      if (u >= 0.0 && u <= 1.0) keepEarliest(best, hitAt(t), SegmentFeature::Face);
    }
  }
  keepEarliest(best, toiBallsAccelerated<2>(s.a - c.center, -v, -a, c.radius, tMax), SegmentFeature::EndA);
  keepEarliest(best, toiBallsAccelerated<2>(s.b - c.center, -v, -a, c.radius, tMax), SegmentFeature::EndB);
  return best;
}

Vec2 closestPointOnSegment(const Segment& s, const Vec2& p) {
  const Vec2 dir = s.b - s.a;
  const double len2 = dir.squaredNorm();
  if (len2 == 0.0) return s.a;
  const double u = std::clamp((p - s.a).dot(dir) / len2, 0.0, 1.0);
  return s.a + u * dir;
}

}  // namespace st
