#pragma once
// Independent truth for the highway tests: rectangles as corner lists, overlap by edge crossings
// and point containment (not by separating axes), motion integrated by its own formulas, and TTC
// by sampling plus bisection. Slow, simple, and sharing no code with the model.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <sthighway/detector.hpp>

namespace st::highway::ref {

using Poly = std::array<Vec2, 4>;

// Where a body is at time t: constant velocity, or constant longitudinal acceleration until the
// longitudinal speed reaches zero (then only the sideways velocity remains).
inline Vec2 positionAt(const Body& b, double t, bool accel) {
  if (!accel || b.acceleration == 0.0) return b.position + b.velocity * t;
  const double u = b.velocity.dot(b.axis);
  const Vec2 side = b.velocity - u * b.axis;
  double tl = t;
  if (u * b.acceleration < 0.0) tl = std::min(t, -u / b.acceleration);
  else if (u < 0.0 || (u == 0.0 && b.acceleration < 0.0)) return b.position + b.velocity * t;
  const double along = u * tl + 0.5 * b.acceleration * tl * tl;
  return b.position + along * b.axis + side * t;
}

inline Poly corners(const Body& b, const Vec2& centre) {
  const Vec2 n(-b.axis.y(), b.axis.x());
  const Vec2 a = 0.5 * b.length * b.axis, w = 0.5 * b.width * n;
  return {centre + a + w, centre - a + w, centre - a - w, centre + a - w};
}

inline double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

inline bool segmentsCross(const Vec2& p, const Vec2& q, const Vec2& r, const Vec2& s) {
  const double d1 = cross2(q - p, r - p), d2 = cross2(q - p, s - p);
  const double d3 = cross2(s - r, p - r), d4 = cross2(s - r, q - r);
  return ((d1 <= 0 && d2 >= 0) || (d1 >= 0 && d2 <= 0)) && ((d3 <= 0 && d4 >= 0) || (d3 >= 0 && d4 <= 0));
}

inline bool inside(const Poly& p, const Vec2& x) {
  // convex, counter-clockwise or clockwise: all cross products of one sign
  int pos = 0, neg = 0;
  for (int i = 0; i < 4; ++i) {
    const double c = cross2(p[(i + 1) % 4] - p[i], x - p[i]);
    pos += c > 0;
    neg += c < 0;
  }
  return pos == 0 || neg == 0;
}

inline bool overlap(const Poly& a, const Poly& b) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (segmentsCross(a[i], a[(i + 1) % 4], b[j], b[(j + 1) % 4])) return true;
  return inside(a, b[0]) || inside(b, a[0]);
}

inline double pointSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double u = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (a + u * d - p).norm();
}

inline double distance(const Poly& a, const Poly& b) {
  if (overlap(a, b)) return 0.0;
  double d = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      d = std::min(d, pointSegment(a[i], b[j], b[(j + 1) % 4]));
      d = std::min(d, pointSegment(b[j], a[i], a[(i + 1) % 4]));
    }
  return d;
}

inline bool overlapAt(const Body& a, const Body& b, double t, bool accel) {
  return overlap(corners(a, positionAt(a, t, accel)), corners(b, positionAt(b, t, accel)));
}
inline double distanceAt(const Body& a, const Body& b, double t, bool accel) {
  return distance(corners(a, positionAt(a, t, accel)), corners(b, positionAt(b, t, accel)));
}

// First overlap in [0, horizon] by sampling (n steps) and bisection; infinity if none seen.
inline double sampledTtc(const Body& a, const Body& b, double horizon, bool accel, int n = 4000) {
  if (overlapAt(a, b, 0.0, accel)) return 0.0;
  double prev = 0.0;
  for (int i = 1; i <= n; ++i) {
    const double t = horizon * i / n;
    if (overlapAt(a, b, t, accel)) {
      double lo = prev, hi = t;
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (overlapAt(a, b, mid, accel) ? hi : lo) = mid;
      }
      return hi;
    }
    prev = t;
  }
  return std::numeric_limits<double>::infinity();
}

// How far a circle (body frame centre c, radius r) reaches beyond the rectangle: the largest
// distance from a point of the circle to the rectangle, by sampling the boundary finely.
inline double overshoot(const Vec2& c, double r, double length, double width) {
  double worst = 0.0;
  for (int i = 0; i < 3600; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * i / 3600.0;
    const Vec2 p = c + r * Vec2(std::cos(a), std::sin(a));
    const double dx = std::max(0.0, std::abs(p.x()) - 0.5 * length);
    const double dy = std::max(0.0, std::abs(p.y()) - 0.5 * width);
    worst = std::max(worst, std::hypot(dx, dy));
  }
  return worst;
}

}  // namespace st::highway::ref
