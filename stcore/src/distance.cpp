#include <stcore/distance.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <stcore/tolerances.hpp>

namespace st {

namespace {

double clamp01(double x) { return std::clamp(x, 0.0, 1.0); }

}  // namespace

double closestParameter(const Vec3& a, const Vec3& b, const Vec3& x) {
  const Vec3 d = b - a;
  const double dd = d.squaredNorm();
  if (!(dd > 0.0)) return 0.0;
  return clamp01((x - a).dot(d) / dd);
}

double pointSegmentDistanceSq(const Vec3& x, const Vec3& a, const Vec3& b) {
  const double s = closestParameter(a, b, x);
  return (a + s * (b - a) - x).squaredNorm();
}

SegmentPair closestSegmentSegment(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  // minimise |p0 + s d1 - q0 - t d2|^2 over the unit square: a convex quadratic, so clamping
  // the free optimum of one parameter and re-optimising the other is exact (Ericson 5.1.9)
  const Vec3 d1 = p1 - p0;
  const Vec3 d2 = q1 - q0;
  const Vec3 r = p0 - q0;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  double s = 0.0;
  double t = 0.0;
  if (a <= 0.0 && e <= 0.0) {
    // two points
  } else if (a <= 0.0) {
    t = clamp01(f / e);
  } else {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      s = clamp01(-c / a);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;  // a e sin^2(angle), >= 0 up to roundoff
      // parallel (relative to the lengths): dividing would amplify roundoff; start from s = 0
      // and let the clamping below pick the right end (every s on the overlap is optimal)
      const bool parallel = !(denom > tol::kRelativeEpsilon * a * e);
      if (!parallel) s = clamp01((b * f - c * e) / denom);
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = clamp01(-c / a);
      } else if (t > 1.0) {
        t = 1.0;
        s = clamp01((b - c) / a);
      }
      if (parallel) {
        // only nearly parallel (up to 1e-7 rad), the distance still changes along the overlap,
        // at first order where the tilt is towards the other segment, so s = 0 may be the far
        // end: the minimum is on the unit square's boundary (to second order in the angle), so
        // take the nearest of the four edges' minima, each a clamped 1-D optimum
        const auto dist2 = [&](double si, double ti) { return (r + si * d1 - ti * d2).squaredNorm(); };
        double best = dist2(s, t);
        const double edges[4][2] = {{0.0, clamp01(f / e)}, {1.0, clamp01((b + f) / e)},
                                    {clamp01(-c / a), 0.0}, {clamp01((b - c) / a), 1.0}};
        for (const auto& st : edges) {
          const double d2st = dist2(st[0], st[1]);
          if (d2st < best) best = d2st, s = st[0], t = st[1];
        }
      }
    }
  }
  SegmentPair out;
  out.s = s;
  out.t = t;
  out.p = p0 + s * d1;
  out.q = q0 + t * d2;
  out.distanceSq = (out.p - out.q).squaredNorm();
  return out;
}

double pointAlignedBoxDistanceSq(const Vec3& x, const Vec3& h) {
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double excess = std::abs(x[i]) - h[i];
    if (excess > 0.0) sum += excess * excess;
  }
  return sum;
}

double segmentAlignedBoxDistanceSq(const Vec3& p0, const Vec3& p1, const Vec3& h, double* sOut) {
  const Vec3 d = p1 - p0;
  // parameters where a coordinate crosses a face plane split [0, 1] into pieces on which
  // each axis is entirely below, inside or above the slab
  double breaks[8];
  int n = 0;
  breaks[n++] = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) continue;
    for (double plane : {-h[i], h[i]}) {
      const double tb = (plane - p0[i]) / d[i];
      if (tb > 0.0 && tb < 1.0) breaks[n++] = tb;
    }
  }
  breaks[n++] = 1.0;
  // at most eight entries: insertion sort
  for (int i = 1; i < n; ++i)
    for (int j = i; j > 0 && breaks[j] < breaks[j - 1]; --j) std::swap(breaks[j], breaks[j - 1]);

  double best = std::numeric_limits<double>::infinity();
  double bestS = 0.0;
  for (int k = 0; k + 1 < n; ++k) {
    const double lo = breaks[k];
    const double hi = breaks[k + 1];
    // on this piece f(s) = sum over outside axes of (p0_i + s d_i - bound_i)^2 = A s^2 + B s + C
    const double mid = 0.5 * (lo + hi);
    double qa = 0.0;
    double qb = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double x = p0[i] + mid * d[i];
      double bound;
      if (x > h[i]) bound = h[i];
      else if (x < -h[i]) bound = -h[i];
      else continue;
      qa += d[i] * d[i];
      qb += 2.0 * d[i] * (p0[i] - bound);
    }
    // convex piece: its minimiser is the vertex clamped to the piece (constant if qa == 0)
    const double s = qa > 0.0 ? std::clamp(-qb / (2.0 * qa), lo, hi) : lo;
    // evaluate the distance itself rather than the expanded quadratic (no cancellation)
    const double val = pointAlignedBoxDistanceSq(p0 + s * d, h);
    if (val < best) {
      best = val;
      bestS = s;
    }
  }
  if (sOut) *sOut = bestS;
  return best;
}

double distance(const Capsule& a, const Capsule& b) {
  const SegmentPair sp = closestSegmentSegment(a.a, a.b, b.a, b.b);
  return std::max(0.0, std::sqrt(sp.distanceSq) - a.radius - b.radius);
}

double distance(const Capsule& c, const Sphere& s) {
  return std::max(0.0, std::sqrt(pointSegmentDistanceSq(s.center, c.a, c.b)) - c.radius - s.radius);
}

double distance(const Capsule& c, const Box& b) {
  // the segment in the box frame
  const Vec3 p0 = b.rotation.transpose() * (c.a - b.center);
  const Vec3 p1 = b.rotation.transpose() * (c.b - b.center);
  return std::max(0.0, std::sqrt(segmentAlignedBoxDistanceSq(p0, p1, b.halfExtents)) - c.radius);
}

double distance(const Sphere& a, const Sphere& b) {
  return std::max(0.0, (a.center - b.center).norm() - a.radius - b.radius);
}

double distance(const Sphere& s, const Box& b) {
  const Vec3 x = b.rotation.transpose() * (s.center - b.center);
  return std::max(0.0, std::sqrt(pointAlignedBoxDistanceSq(x, b.halfExtents)) - s.radius);
}

}  // namespace st
