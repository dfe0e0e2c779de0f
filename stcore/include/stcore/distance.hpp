#pragma once
// Exact 3-D distance kernels: point-segment, segment-segment, segment-box, and the shape pairs
// built on them (capsule-capsule, capsule-sphere, capsule-box, sphere-sphere, sphere-box).
// Kernels work on plain points; the shape functions wrap them. Distances are separations in
// metres, clamped at zero when the shapes overlap (penetration depth is not computed here).
#include <stcore/shapes.hpp>

namespace st {

// Closest points of two segments p0-p1 and q0-q1: p = p0 + s (p1 - p0), q = q0 + t (q1 - q0).
struct SegmentPair {
  double s = 0.0;
  double t = 0.0;
  Vec3 p;
  Vec3 q;
  double distanceSq = 0.0;
};

// Parameter in [0, 1] of the point of segment a-b closest to x (0 for a degenerate segment).
double closestParameter(const Vec3& a, const Vec3& b, const Vec3& x);
double pointSegmentDistanceSq(const Vec3& x, const Vec3& a, const Vec3& b);

// Robust for parallel, collinear and zero-length segments: a parallel pair is solved as a
// one-parameter problem instead of dividing by a vanishing determinant.
SegmentPair closestSegmentSegment(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

// Squared distance from segment p0-p1, given in the box frame, to the axis-aligned box
// [-h, h]. Exact: the squared distance is a convex piecewise quadratic of the segment
// parameter with at most six breaks (where a coordinate crosses a face plane); each piece is
// minimised in closed form. Returns the minimising parameter in *s if s is not null.
double segmentAlignedBoxDistanceSq(const Vec3& p0, const Vec3& p1, const Vec3& h, double* s = nullptr);
double pointAlignedBoxDistanceSq(const Vec3& x, const Vec3& h);

// Shapes. Separation distance, 0 when touching or overlapping.
double distance(const Capsule& a, const Capsule& b);
double distance(const Capsule& c, const Sphere& s);
double distance(const Capsule& c, const Box& b);
double distance(const Sphere& a, const Sphere& b);
double distance(const Sphere& s, const Box& b);
inline double distance(const Sphere& s, const Capsule& c) { return distance(c, s); }
inline double distance(const Box& b, const Capsule& c) { return distance(c, b); }
inline double distance(const Box& b, const Sphere& s) { return distance(s, b); }

}  // namespace st
