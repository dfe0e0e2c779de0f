#pragma once
// Time-of-entry kernels on plain numbers for bodies whose relative motion is piecewise
// quadratic (constant velocity, or constant acceleration until a car stops). The detectors
// (detector.cpp) are wrappers over these; tests reach them directly. Nothing here knows a car.
#include <array>
#include <limits>
#include <span>

#include <stcore/box2.hpp>
#include <stcore/toi.hpp>
#include <sthighway/tolerances.hpp>

namespace st::highway::detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// One body's motion: p(t) = p + v t + a t^2 / 2 for t <= stop, then straight on at vAfter.
struct Track {
  Vec2 p = Vec2::Zero();
  Vec2 v = Vec2::Zero();
  Vec2 a = Vec2::Zero();
  double stop = kInf;
  Vec2 vAfter = Vec2::Zero();
};
inline Track staticTrack(const Vec2& p) {
  Track t;
  t.p = p;
  return t;
}

// Relative motion of foe with respect to ego on [start, start + len]:
// r(s) = p + v s + a s^2 / 2 for s in [0, len].
struct Piece {
  Vec2 p = Vec2::Zero();
  Vec2 v = Vec2::Zero();
  Vec2 a = Vec2::Zero();
  double start = 0.0;
  double len = 0.0;
  bool accelerating() const { return a.squaredNorm() > tol::kAccelerationEpsilon * tol::kAccelerationEpsilon; }
};
// Splits [0, horizon] at the stop times; returns the number of pieces (1..3).
int relativePieces(const Track& ego, const Track& foe, double horizon, std::array<Piece, 3>& out);
// First s in [0, len] with |r(s) + offset| <= radius (0 if already so); kInf if none.
// Inline: the detectors' innermost call, mostly steady.
inline double discEntry(const Piece& pc, const Vec2& offset, double radius) {
  const Vec2 p = pc.p + offset;
  if (p.squaredNorm() <= radius * radius) return 0.0;
  // stcore's kernels: the quartic (out of line) when accelerating, else constant velocity
  if (pc.accelerating()) {
    const Impact entry = toiBallsEntryAccelerated<2>(p, pc.v, pc.a, radius, pc.len);
    return entry.acts() ? entry.actTime() : kInf;
  }
  const Impact hit = toiBalls<2>(p, pc.v, radius);
  return hit.acts() && hit.actTime() <= pc.len ? hit.actTime() : kInf;
}

// First s in [0, len] at which the shapes overlap on every separating axis (stcore/box2.hpp: along
// n when |n . r(s)| <= extent), 0 if they already do (within tol::kContactSlop); kInf if none.
// A steady piece is stcore's timeOfEntry; an accelerating one solves each axis' quadratic.
double satEntry(const Piece& pc, std::span<const SeparatingAxis> axes);

// The unit normal (left) of a unit axis.
inline Vec2 normalOf(const Vec2& axis) { return {-axis.y(), axis.x()}; }

}  // namespace st::highway::detail
