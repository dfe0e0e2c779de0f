#include "conflict_capture.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <stcore/toi.hpp>
#include <sthighway/tolerances.hpp>

namespace st::highway::detail {

namespace {
// SSAM's measures of a vehicle warning but the conflict point (monitor.hpp, Warning)
void describeSsam(const ConflictCapture& c, double egoMass, double foeMass, Warning& w) {
  const Body &a = c.ego, &b = c.foe;
  w.foeX = b.position.x();
  w.foeY = b.position.y();
  w.deltaSpeed = (a.velocity - b.velocity).norm();
  w.conflictAngle = conflictAngleDeg(a.axis, b.axis);
  w.clockAngle = clockPosition(w.conflictAngle);
  const Vec2 v = postCrashVelocity(egoMass, a.velocity, foeMass, b.velocity);
  w.postCrashSpeed = v.norm();
  w.postCrashHeading = v.squaredNorm() > 0.0 ? toDegrees(std::atan2(v.y(), v.x())) : std::numeric_limits<double>::quiet_NaN();
  const EpisodeTrack& k = c.track;
  w.maxSpeed = k.maxSpeed;
  w.dr = k.dr;
  w.maxDecel = k.maxD;
  w.startX = k.start.x();
  w.startY = k.start.y();
  w.endX = k.last.x();
  w.endY = k.last.y();
}

// the angle between two unit vectors (deg, 0..180), accurate near 0 and 180 as acos is not
double angleDeg(const Vec2& a, const Vec2& b) {
  return toDegrees(std::atan2(std::abs(cross(a, b)), a.dot(b)));
}
}  // namespace

double tickDrac(const VehicleTable& cars, const RoadFeatures& road, int e, const Threat& th) {
  const Vec2 a = cars.centre[e];
  if (th.kind == WarningKind::Vehicle) {
    const Vec2 p = cars.centre[th.foe] - a, v = cars.vel[th.foe] - cars.vel[e];
    const double dist = p.norm();
    return decelerationToAvoid(dist > 0.0 ? -p.dot(v) / dist : v.norm(), th.ttc);
  }
  const RoadFeature& f = road.features[th.feature];
  const Vec2 d = (f.kind == FeatureKind::Hazard ? f.segment.a : closestPointOnSegment(f.segment, a)) - a;
  const double dist = d.norm();
  return decelerationToAvoid(dist > 0.0 ? cars.vel[e].dot(d) / dist : cars.vel[e].norm(), th.ttc);
}

void describeConflict(const ConflictCapture& c, WarningKind kind, double egoMass, double foeMass, bool pedestrian, double ttc,
                      double safeTime, const DetectorConfig& detector, const RoadFeatures& road, const ConflictConfig& config,
                      Warning& w) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const Body &a = c.ego, &b = c.foe;
  w.x = a.position.x();
  w.y = a.position.y();
  w.egoSpeed = a.velocity.norm();
  if (kind == WarningKind::Vehicle) {
    w.foeSpeed = b.velocity.norm();
    w.headingAngle = angleDeg(a.axis, b.axis);
    w.maxDeltaV = maxDeltaV(egoMass, a.velocity, foeMass, b.velocity);
    w.lateralSpeed = kNaN;
    describeSsam(c, egoMass, foeMass, w);
    if (!onCollisionCourse(detector, a, b, safeTime)) {
      // only the zones meet: no angle class, and no deceleration avoids a crash not coming
      w.type = ConflictType::Proximity;
      w.drac = kNaN;
      return;
    }
    w.type = pedestrian ? ConflictType::Pedestrian : conflictType(w.headingAngle, config);
    // PET, of crossing and merging paths, once both have passed (else hindsight watches on)
    if (crossesPaths(w.type)) w.pet = c.pet.pet();
    // the predicted contact: the rectangles moved on in straight lines until they touch (the box
    // detector's TTC is theirs; the circles' zones reach beyond the bodies)
    const double tc = detector.kind == DetectorKind::Box ? ttc : boxTtc(a, b, detector.motion, safeTime);
    if (std::isfinite(tc)) {
      Body at = a, bt = b;
      at.position += tc * a.velocity;
      bt.position += tc * b.velocity;
      const Vec2 p = contactPoint(at.box(), bt.box(), tol::kContactPointTie);
      w.conflictX = p.x();
      w.conflictY = p.y();
    }
    // the rate the centre distance shrinks, as the safe time has it
    const Vec2 p = b.position - a.position, v = b.velocity - a.velocity;
    const double dist = p.norm();
    const double closing = dist > 0.0 ? -p.dot(v) / dist : v.norm();
    w.drac = decelerationToAvoid(closing, ttc);
    w.lateralSpeed = kNaN;
    return;
  }
  // a road feature: the speed towards its closest point, as the road search has it
  const RoadFeature& f = road.features[c.feature];
  const Vec2 closest = f.kind == FeatureKind::Hazard ? f.segment.a : closestPointOnSegment(f.segment, a.position);
  const Vec2 d = closest - a.position;
  const double dist = d.norm();
  w.lateralSpeed = dist > 0.0 ? a.velocity.dot(d) / dist : a.velocity.norm();
  w.drac = decelerationToAvoid(w.lateralSpeed, ttc);
  w.foeSpeed = kNaN;
  w.maxDeltaV = kNaN;
  const Vec2 along = f.segment.b - f.segment.a;
  if (f.kind == FeatureKind::Hazard || along.squaredNorm() == 0.0) {
    w.headingAngle = kNaN;
  } else {
    // a line has no direction: the angle to it is at most 90 degrees
    const double deg = angleDeg(a.axis, along.normalized());
    w.headingAngle = std::min(deg, 180.0 - deg);
  }
  w.type = ConflictType::Road;
}

}  // namespace st::highway::detail
