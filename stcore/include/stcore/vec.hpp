#pragma once
// Vectors for stsim: Eigen fixed-size types in SI units (metres, seconds).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace st {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
using Vec2 = Vec<2>;
using Vec3 = Vec<3>;

// 2-D cross product (z of the 3-D cross product); positive when b is counter-clockwise of a.
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Unit normal of a 2-D direction, rotated +90 degrees (left of travel).
inline Vec2 leftNormal(const Vec2& d) { return Vec2(-d.y(), d.x()).normalized(); }

}  // namespace st
