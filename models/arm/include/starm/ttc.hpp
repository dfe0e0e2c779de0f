#pragma once
// Time to collision by conservative advancement on exact distances.
// Shapes move affinely: each capsule end point at its own constant velocity (an arm link
// extrapolated from qdot), spheres and boxes translating. Every point of such a capsule moves
// at a convex combination of its end velocities, so no point is faster than the faster end:
// the separation of two shapes shrinks at most at V = (fastest end of one) + (fastest end of
// the other). Advancing by separation / V therefore never steps over a contact.
#include <algorithm>
#include <cmath>
#include <limits>

#include <stcore/distance.hpp>
#include <stcore/tolerances.hpp>

namespace st::arm {

enum class Approach {
  Touching,  // already within the clearance now
  Hit,       // comes within the clearance at t (a lower bound, early by at most kAdvanceSlop / V)
  Clear,     // stays outside the clearance for the whole horizon
};

struct TimeToCollision {
  Approach outcome = Approach::Clear;
  double t = std::numeric_limits<double>::infinity();
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
TimeToCollision advance(SepAt&& sepAt, double clearance, double speedBound, double horizon) {
  TimeToCollision out;
  double gap = sepAt(0.0);
  out.distance = gap;
  out.steps = 1;
  gap -= clearance;
  if (gap <= tol::kAdvanceSlop) {
    out.outcome = Approach::Touching;
    out.t = 0.0;
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
  out.outcome = Approach::Hit;
  out.t = t;
  return out;
}

// An arm capsule extrapolated from its end-point velocities.
struct MovingCapsule {
  Capsule c;
  Vec3 va = Vec3::Zero();
  Vec3 vb = Vec3::Zero();
  Capsule at(double t) const { return {c.a + t * va, c.b + t * vb, c.radius}; }
  double maxSpeed() const { return std::sqrt(std::max(va.squaredNorm(), vb.squaredNorm())); }
};

struct MovingSphere {
  Sphere s;
  Vec3 v = Vec3::Zero();
  Sphere at(double t) const { return {s.center + t * v, s.radius}; }
  double maxSpeed() const { return v.norm(); }
};

struct MovingBox {
  Box b;
  Vec3 v = Vec3::Zero();
  Box at(double t) const { return {b.center + t * v, b.halfExtents, b.rotation}; }
  double maxSpeed() const { return v.norm(); }
};

template <class Other>
TimeToCollision timeToCollision(const MovingCapsule& a, const Other& b, double clearance, double horizon) {
  return advance([&](double t) { return distance(a.at(t), b.at(t)); }, clearance, a.maxSpeed() + b.maxSpeed(),
                 horizon);
}

}  // namespace st::arm
