#pragma once
// Every tolerance of stcore, in one place. All lengths in metres, times in seconds.
// Derived from one linear slop, as in Box2D: change kLinearSlop and the rest follow.

namespace st::tol {

// Geometric slop: two shapes closer than this count as touching. The event-driven simulator
// allows overlaps up to this depth (roundoff when placing bodies at contact). Larger values
// hide real interpenetration in tests; smaller ones approach roundoff of positions ~1e3 m.
inline constexpr double kLinearSlop = 1e-9;

// A ball is listed in a region tree's leaves by its box grown by this, and leaves a leaf once
// 2 slops clear of it: the update at a region event then sees the change whatever the rounding
// of the ball's position (about 1e-16 relative: ample for coordinates up to 1e4 m).
inline constexpr double kRegionSlop = 10 * kLinearSlop;

// Squared speeds below this are "not moving" for time-of-impact purposes (m^2/s^2).
// Too large and slow approaches are missed; too small and 1/v blows up in the kernels.
inline constexpr double kSpeedSqEpsilon = 1e-24;

// Relative tolerance for a vanishing quadratic leading coefficient (dimensionless).
// Below it the quadratic is solved as linear; this guards parallel motion.
inline constexpr double kRelativeEpsilon = 1e-14;

// Polynomial root finding (roots.hpp, the decelerating-ball kernels), relative to max(1, |t|):
// the solver stops refining a root once its bracket or Newton step is this small. Smaller values
// cannot be met in double precision (the loop runs out its iterations); larger ones move event times.
inline constexpr double kRootResolution = 1e-15;
// Two roots closer than this (relative, as above) are one root: a double root (a grazing contact)
// found once from each side. Much smaller and a graze is reported as two contacts; larger and two
// real contacts that close together are merged.
inline constexpr double kRootMerge = 1e-13;

// Along a separating axis, a projection moving slower than this (m/s) is taken as fixed by the
// time of entry of two boxes (box2.hpp): larger values miss slow approaches along the axis,
// smaller ones only divide by speeds that are roundoff.
inline constexpr double kParallelSpeed = 1e-15;

// Events closer in time than this are treated as simultaneous when comparing event orders in tests (s).
inline constexpr double kTimeEpsilon = 1e-12;

// Conservative advancement (time to collision on exact distances) declares contact once the
// separation is below this (m), so a reported time is early by at most this over the closing
// speed. Smaller values cost iterations near grazing contacts; larger ones report early.
inline constexpr double kAdvanceSlop = 1e3 * kLinearSlop;

}  // namespace st::tol
