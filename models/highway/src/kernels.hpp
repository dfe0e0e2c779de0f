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
// Entries are stcore's Impact read as an overlap query: Overlapping (s = 0) when the shapes
// overlap at the piece's start, Hit at the first s in [0, len] at which they do, else Miss.

// |r(s) + offset| <= radius. Inline: the detectors' innermost call, mostly steady.
inline Impact discEntry(const Piece& pc, const Vec2& offset, double radius) {
  const Vec2 p = pc.p + offset;
  if (p.squaredNorm() <= radius * radius) return {Outcome::Overlapping, 0.0};
  // stcore's kernels: the quartic (out of line) when accelerating, else constant velocity
  if (pc.accelerating()) return toiBallsEntryAccelerated<2>(p, pc.v, pc.a, radius, pc.len);
  const Impact hit = toiBalls<2>(p, pc.v, radius);
  // a contact that separates is no entry
  return hit.acts() && hit.actTime() <= pc.len ? hit : Impact{};
}

// Overlap on every separating axis (stcore/box2.hpp: along n when |n . r(s)| <= extent), within
// tol::kContactSlop: stcore's timeOfEntry for a steady piece, timeOfEntryAccelerated otherwise.
inline Impact satEntry(const Piece& pc, std::span<const SeparatingAxis> axes) {
  if (!pc.accelerating()) return timeOfEntry(axes, pc.p, pc.v, pc.len, tol::kContactSlop);
  return timeOfEntryAccelerated(axes, pc.p, pc.v, pc.a, pc.len, tol::kContactSlop);
}

// The first entry over consecutive pieces, in time from the first piece's start: entry(pc) on
// each in turn until one acts. An overlap at the start of a later piece is a hit then.
template <class Entry>
Impact firstEntry(std::span<const Piece> pcs, Entry&& entry) {
  for (const Piece& pc : pcs) {
    const Impact e = entry(pc);
    if (e.acts()) return delayed(e, pc.start);
  }
  return {};
}

// The unit normal (left) of a unit axis.
inline Vec2 normalOf(const Vec2& axis) { return {-axis.y(), axis.x()}; }

}  // namespace st::highway::detail
