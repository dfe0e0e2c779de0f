#pragma once
// Time of impact by conservative advancement on exact distances, for shapes whose motion no
// closed form covers (toi.hpp's kernels solve constant-velocity balls and planes exactly).
// Shapes move affinely: each capsule end point at its own constant velocity (a robot link
// extrapolated from its joint rates), spheres and boxes translating. A point of such a capsule
// moves at a convex combination of its end velocities, so the relative velocity of any two points
// is bilinear in their parameters; its norm is convex in each parameter and so peaks at a pair of
// end points: the separation shrinks at most at V = max over end pairs |v_i - w_j|. (Links of
// one arm share the motion of the joints below both, so this is far tighter than the sum of
// speeds.) Advancing by separation / V therefore never steps over a contact.
//
// The result is toi.hpp's Impact, read against a clearance (the separation counted as contact):
//   Hit         comes within the clearance at t, a lower bound early by at most
//               tol::kAdvanceSlop / V (also when the step budget ran out: see `capped`);
//   Overlapping within the clearance now (t = 0), whichever way the shapes move;
//   Miss        stays outside the clearance for the whole horizon (t = infinity).
#include <algorithm>
#include <cmath>
#include <limits>

#include <stcore/distance.hpp>
#include <stcore/toi.hpp>
#include <stcore/tolerances.hpp>

namespace st {

struct AdvanceImpact {
  Impact impact;          // Hit, Overlapping or Miss, as above
  double distance = 0.0;  // separation now (m), before subtracting the clearance
  int steps = 0;          // distance evaluations
  bool capped = false;    // step budget ran out: t is still a sound lower bound, reported as Hit
};

// Budget of advancement steps for one pair. Linear approaches converge geometrically (tens of
// steps); grazing ones slowly, and are then reported early rather than late.
inline constexpr int kMaxAdvanceSteps = 200;

// sepAt(t): exact separation of the shapes at time t. clearance: the separation counted as
// contact (the objects grown by half of it each). speedBound: bound on d(separation)/dt.
template <class SepAt>
AdvanceImpact toiAdvanceSeparation(SepAt&& sepAt, double clearance, double speedBound, double horizon) {
  AdvanceImpact out;
  double gap = sepAt(0.0);
  out.distance = gap;
  out.steps = 1;
  gap -= clearance;
  if (gap <= tol::kAdvanceSlop) {
    out.impact = {Outcome::Overlapping, 0.0};
    return out;
  }
  if (!(speedBound > 0.0) || gap >= speedBound * horizon) return out;  // cannot close in time
  double t = 0.0;
  while (true) {
    t += gap / speedBound;
    if (t > horizon) return out;
    if (out.steps >= kMaxAdvanceSteps) {
      out.capped = true;
      break;
    }
    gap = sepAt(t) - clearance;
    ++out.steps;
    if (gap <= tol::kAdvanceSlop) break;
  }
  out.impact = {Outcome::Hit, t};
  return out;
}

// A capsule whose end points move at their own constant velocities.
struct MovingCapsule {
  Capsule c;
  Vec3 va = Vec3::Zero();
  Vec3 vb = Vec3::Zero();
  Capsule at(double t) const { return {c.a + t * va, c.b + t * vb, c.radius}; }
  const Vec3& endVelocity(int i) const { return i == 0 ? va : vb; }
  static constexpr int kEnds = 2;
};

struct MovingSphere {
  Sphere s;
  Vec3 v = Vec3::Zero();
  Sphere at(double t) const { return {s.center + t * v, s.radius}; }
  const Vec3& endVelocity(int) const { return v; }
  static constexpr int kEnds = 1;
};

struct MovingBox {
  Box b;
  Vec3 v = Vec3::Zero();
  Box at(double t) const { return {b.center + t * v, b.halfExtents, b.rotation}; }
  const Vec3& endVelocity(int) const { return v; }
  static constexpr int kEnds = 1;
};

// Bound on how fast the separation of a and b can shrink.
template <class A, class B>
double closingSpeedBound(const A& a, const B& b) {
  double v2 = 0.0;
  for (int i = 0; i < A::kEnds; ++i)
    for (int j = 0; j < B::kEnds; ++j) v2 = std::max(v2, (a.endVelocity(i) - b.endVelocity(j)).squaredNorm());
  return std::sqrt(v2);
}

// A moving capsule against a moving capsule, sphere or box: when they first come within `clearance`
// in [0, horizon].
template <class Other>
AdvanceImpact toiAdvance(const MovingCapsule& a, const Other& b, double clearance, double horizon) {
  return toiAdvanceSeparation([&](double t) { return distance(a.at(t), b.at(t)); }, clearance, closingSpeedBound(a, b), horizon);
}

}  // namespace st
