#pragma once
// Vectors for stsim: Eigen fixed-size types in SI units (metres, seconds).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <numbers>

namespace st {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
using Vec2 = Vec<2>;
using Vec3 = Vec<3>;

// 2-D cross product (z of the 3-D cross product); positive when b is counter-clockwise of a.
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Angles: the one conversion every part uses (radians inside, degrees in outputs and inputs).
inline double toDegrees(double radians) { return radians * (180.0 / std::numbers::pi); }
inline double toRadians(double degrees) { return degrees * std::numbers::pi / 180.0; }

// Unit normal of a 2-D direction, rotated +90 degrees (left of travel).
inline Vec2 leftNormal(const Vec2& d) { return Vec2(-d.y(), d.x()).normalized(); }

}  // namespace st
