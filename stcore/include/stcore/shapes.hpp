#pragma once
// Value-type shapes. Pair queries on them are free functions (toi.hpp, distance.hpp).
#include <stcore/vec.hpp>

namespace st {

// The report's `linear`: a segment from a to b. direction() and normal() are derived, not stored.
struct Segment {
  Vec2 a;
  Vec2 b;
  Vec2 direction() const { return b - a; }
  double length() const { return (b - a).norm(); }
  // Unit normal to the left of a->b.
  Vec2 normal() const { return leftNormal(b - a); }
};

struct Circle {
  Vec2 center;
  double radius = 0.0;
};

// Axis-aligned box in D dimensions (the report's rectangular; in 3-D the octree cell).
template <int D>
struct Aabb {
  Vec<D> min;
  Vec<D> max;
  Vec<D> center() const { return 0.5 * (min + max); }
  Vec<D> extent() const { return max - min; }
  bool contains(const Vec<D>& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  // Closed-interval overlap: boxes sharing a face overlap.
  bool overlaps(const Aabb& o) const {
    return (min.array() <= o.max.array()).all() && (o.min.array() <= max.array()).all();
  }
};
using Rect = Aabb<2>;
using Aabb3 = Aabb<3>;

struct Sphere {
  Vec3 center;
  double radius = 0.0;
};

// A segment swept by a sphere (Shaffer's "cylsphere").
struct Capsule {
  Vec3 a;
  Vec3 b;
  double radius = 0.0;
};

// Oriented box in the plane (a car's footprint): centre, unit axis (the box's x), half extents
// along the axis and across it, along normal() (the axis turned left). Queries: box2.hpp.
struct Box2 {
  Vec2 center;
  Vec2 axis = Vec2(1.0, 0.0);
  Vec2 halfExtents;
  Vec2 normal() const { return Vec2(-axis.y(), axis.x()); }
};

// Oriented box: centre, half extents along its own axes, and the rotation from box to world.
struct Box {
  Vec3 center;
  Vec3 halfExtents;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

// Ball of dimension D (circle in 2-D, sphere in 3-D), used by dimension-generic code.
template <int D>
struct Ball {
  Vec<D> center;
  double radius = 0.0;
};

template <int D>
inline Aabb<D> boundsOf(const Vec<D>& center, double radius) {
  return {center.array() - radius, center.array() + radius};
}
inline Aabb<3> boundsOf(const Capsule& c) {
  return {c.a.cwiseMin(c.b).array() - c.radius, c.a.cwiseMax(c.b).array() + c.radius};
}

}  // namespace st
