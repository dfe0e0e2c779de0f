#include "conflict_capture.hpp"

#include <cmath>
#include <limits>

#include <algorithm>

#include <stcore/toi.hpp>

namespace st::highway::detail {

ConflictCapture captureConflict(const VehicleTable& cars, const RoadSearch& road, const ConflictConfig& config, int e,
                                const Threat& th) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const Body& a = cars.body[e];
  ConflictCapture c;
  c.position = a.position;
  c.egoSpeed = a.velocity.norm();
  c.lane = cars.lane[e];
  if (th.kind == WarningKind::Vehicle) {
    const Body& b = cars.body[th.foe];
    c.foeSpeed = b.velocity.norm();
    c.headingAngle = relativeHeadingDeg(cars.slots[e].heading, cars.slots[th.foe].heading);
    c.type = conflictType(c.headingAngle, config);
    // the rate the centre distance shrinks, as the safe time has it
    const Vec2 p = b.position - a.position, v = b.velocity - a.velocity;
    const double dist = p.norm();
    const double closing = dist > 0.0 ? -p.dot(v) / dist : v.norm();
    c.drac = decelerationToAvoid(closing, th.ttc);
    c.maxDeltaV = maxDeltaV(cars.mass[e], a.velocity, cars.mass[th.foe], b.velocity);
    c.lateralSpeed = kNaN;
    return c;
  }
  // a road feature: the speed towards its closest point, as the road search has it
  const RoadFeature& f = road.features().features[th.feature];
  const Vec2 closest = f.kind == FeatureKind::Hazard ? f.segment.a : closestPointOnSegment(f.segment, a.position);
  const Vec2 d = closest - a.position;
  const double dist = d.norm();
  c.lateralSpeed = dist > 0.0 ? a.velocity.dot(d) / dist : a.velocity.norm();
  c.drac = decelerationToAvoid(c.lateralSpeed, th.ttc);
  c.feature = th.feature;
  c.foeSpeed = kNaN;
  c.maxDeltaV = kNaN;
  const Vec2 along = f.segment.b - f.segment.a;
  if (f.kind == FeatureKind::Hazard || along.squaredNorm() == 0.0) {
    c.headingAngle = kNaN;
  } else {
    // a line has no direction: the angle to it is at most 90 degrees
    const double deg = relativeHeadingDeg(cars.slots[e].heading, std::atan2(along.y(), along.x()));
    c.headingAngle = std::min(deg, 180.0 - deg);
  }
  c.type = ConflictType::Road;
  return c;
}

}  // namespace st::highway::detail
