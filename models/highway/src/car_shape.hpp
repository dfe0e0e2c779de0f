#pragma once
// What the monitor caches per car for the detectors (detector.cpp implements it): the shapes that
// depend only on a car's size and heading, kept while they stay, and the bounds its prunes read.
// Internal: the detector's own interface is sthighway/detector.hpp.
#include <array>

#include <sthighway/detector.hpp>

namespace st::highway {

// A bound on roadSupport in every unit direction n, in a form cheap enough to evaluate for every
// nearby feature: roadSupport(cfg, ego, n) <= base + along |axis . n| + across |normal . n|
// (equal for the circles about the centre and for the rectangle, up to rounding).
struct SupportBound {
  double base = 0.0;
  double along = 0.0;
  double across = 0.0;
};
SupportBound roadSupportBound(const DetectorConfig& cfg, const Body& ego);

// What the detectors need of one car that depends only on its size and heading (and the
// config), as ego and as foe: computed once while they stay (the monitor keeps one per car) with
// the same expressions vehicleTtc uses, so a TTC from shapes is bit for bit the one without.
// Cache-line aligned, the fields every detector reads first.
struct alignas(64) CarShape {
  double outer = 0.0;                  // Concentric: outer radius (m)
  SupportBound road;                   // roadSupportBound
  // FiveCircle as ego: the four car-checking zone circles (radius, world offset of the centre),
  // a disc about the centre holding them and the rectangle, and a lower bound of its radius
  std::array<double, 4> zoneRadius{};
  std::array<Vec2, 4> zoneOffset{};
  double egoEnvelope = 0.0, egoLow = 0.0;
  // FiveCircle as foe: `circles` body circles of `circleRadius`, `slice` apart along the axis,
  // the first at firstX; a disc about the centre holding them (or the rectangle), and one holding
  // just the circles (|firstX| (1 + |axis|^2) / 2 + circleRadius)
  int circles = 0;
  double circleRadius = 0.0, slice = 0.0, firstX = 0.0, foeEnvelope = 0.0, foeDisc = 0.0;
};
CarShape carShape(const DetectorConfig& cfg, const Body& b);
// vehicleTtc with the shapes of both cars given (carShape of bodies of the same size and heading).
Ttc vehicleTtc(const DetectorConfig& cfg, const Body& ego, const CarShape& egoShape, const Body& foe, const CarShape& foeShape,
               double horizon);

// True when vehicleTtc is the same for both roles and any horizon that holds it: for bodies and
// shapes A, B and horizons h1, h2, vehicleTtc(A, B, h1) and vehicleTtc(B, A, h2) are each the
// same time bit for bit, found exactly when that time is <= the horizon. A pair's two
// directions then take one evaluation at the larger horizon. Concentric at constant velocity
// (two discs; the kernel is unchanged by negating the relative position and velocity). Not the
// five-circle zones (the roles differ) nor constant acceleration (roots found per interval).
bool vehicleTtcSymmetric(const DetectorConfig& cfg);

}  // namespace st::highway
