#include "conflict_capture.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <stcore/toi.hpp>
#include <sthighway/tolerances.hpp>

namespace st::highway::detail {

namespace {
// How far behind its front at the start a path's straight line runs (m): past any conflict area a
// vehicle can be in at the start (a long truck's length and a width).
constexpr double kPetLineBehind = 100.0;
// Paths crossing at an acute angle whose sine is below this have no crossing to time: SUMO's own
// floor for a junction conflict's width factor (MSLink), below which two paths run side by side.
constexpr double kMinCrossingSine = 0.2;
// How far ahead along its latest direction a path is looked along for the other's (m): a front
// enters a conflict area half a width before its point.
constexpr double kPetLineAhead = 30.0;

// Where segment p0-p1 meets q0-q1 (false: they do not): the fractions along each.
bool segmentsCross(const Vec2& p0, const Vec2& p1, const Vec2& q0, const Vec2& q1, double& f, double& g) {
  const Vec2 d = p1 - p0, e = q1 - q0, w = q0 - p0;
  const double den = cross(d, e);
  if (den == 0.0) return false;
  f = cross(w, e) / den;
  g = cross(w, d) / den;
  return f >= 0.0 && f <= 1.0 && g >= 0.0 && g <= 1.0;
}

// When path i's front passed arc `arc` (NaN: not yet; the watch's start: on the line behind it).
double passed(const PetWatch& w, int i, double arc) {
  const auto& path = w.path[static_cast<std::size_t>(i)];
  if (arc < 0.0) return path[1].t;  // behind the start: by then at the latest
  for (std::size_t k = 2; k < path.size(); ++k) {
    const PetWatch::Point &a = path[k - 1], &b = path[k];
    if (b.arc >= arc && b.arc > a.arc) return a.t + (b.t - a.t) * (arc - a.arc) / (b.arc - a.arc);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// The entry and exit of the area not timed yet, as far as the paths go.
void timePassages(PetWatch& w) {
  for (int i = 0; i < 2; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    if (std::isnan(w.enter[k])) w.enter[k] = passed(w, i, w.in[k]);
    // out once past the far end (strictly: a back standing on it is still in)
    if (std::isnan(w.exit[k]) && w.path[k].back().arc > w.out[k]) w.exit[k] = passed(w, i, w.out[k]);
  }
}

// The first segment of the other path that segment p0-p1 (arcs arc0, arc1 along path i) crosses:
// sets the crossing (true). One near parallel, either way, leaves a watch for good inactive (true),
// and is passed over for now.
bool crossAt(PetWatch& w, int i, const Vec2& p0, const Vec2& p1, double arc0, double arc1, bool forGood) {
  const auto& other = w.path[static_cast<std::size_t>(1 - i)];
  for (std::size_t k = 1; k < other.size(); ++k) {
    const PetWatch::Point &q0 = other[k - 1], &q1 = other[k];
    double f = 0.0, g = 0.0;
    if (!segmentsCross(p0, p1, q0.p, q1.p, f, g)) continue;
    const Vec2 d = (p1 - p0).normalized(), e = (q1.p - q0.p).normalized();
    const double sine = cross(d, e);
    // side by side, whichever way: no crossing to time
    if (std::abs(sine) < kMinCrossingSine) {
      if (!forGood) continue;
      w.active = false;
      return true;
    }
    const std::size_t a = static_cast<std::size_t>(i), b = 1 - a;
    w.x = p0 + f * (p1 - p0);
    const double at[2] = {arc0 + f * (arc1 - arc0), q0.arc + g * (q1.arc - q0.arc)};
    // SUMO's junction model (MSLink): the conflict on a lane crossing another of width W at the
    // acute angle a is W (2 / sin a - 1) long (sin a >= 0.2, above), centred on the crossing; SSM's area
    // begins half the lane's room beside the other vehicle (W - w) / 2 after its start
    const double s = std::abs(sine);
    for (std::size_t v : {a, b}) {
      const double lane = w.laneWidth[1 - v], foeWidth = w.width[1 - v];
      const double conflict = lane * (2.0 / s - 1.0);
      w.in[v] = at[v == a ? 0 : 1] - 0.5 * conflict + 0.5 * (lane - foeWidth);
      w.out[v] = w.in[v] + foeWidth + w.length[v];
    }
    return true;
  }
  return false;
}

// Where the paths cross: the newest segment of either against the other path (found for good), else
// for now where one's straight line ahead (kPetLineAhead) meets the other's path: a vehicle that
// enters the area and stops before the crossing has entered it. Every passage is timed again.
void findCrossing(PetWatch& w) {
  bool found = false;
  for (int i = 0; i < 2 && !found; ++i) {
    const auto& mine = w.path[static_cast<std::size_t>(i)];
    const PetWatch::Point &p0 = mine[mine.size() - 2], &p1 = mine.back();
    found = crossAt(w, i, p0.p, p1.p, p0.arc, p1.arc, true);
  }
  w.crossed = found;
  for (int i = 0; i < 2 && !found; ++i) {
    const auto& mine = w.path[static_cast<std::size_t>(i)];
    const PetWatch::Point &p0 = mine[mine.size() - 2], &p1 = mine.back();
    const Vec2 dir = (p1.p - p0.p).normalized();
    found = crossAt(w, i, p1.p, p1.p + kPetLineAhead * dir, p1.arc, p1.arc + kPetLineAhead, false);
  }
  if (!found || !w.active) return;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  w.enter = {nan, nan};
  w.exit = {nan, nan};
  timePassages(w);
}
}  // namespace

void startPet(const Body& a, const Body& b, double laneWidthA, double laneWidthB, double t, const PetAngles& angles,
              PetWatch& w) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  w.active = false;
  w.crossed = false;
  for (auto& path : w.path) path.clear();
  w.enter = {nan, nan};
  w.exit = {nan, nan};
  w.lastT = t;
  w.laneWidth = {laneWidthA, laneWidthB};
  // paths that start closer than the rear-end angle to parallel: a rear-end, its own PET
  if (std::abs(cross(a.axis, b.axis)) < angles.minSine && a.axis.dot(b.axis) > 0.0) return;
  w.active = true;
  const Body* bodies[2] = {&a, &b};
  for (std::size_t i = 0; i < 2; ++i) {
    const Body& v = *bodies[i];
    w.length[i] = v.length;
    w.width[i] = v.width;
    const Vec2 front = v.position + 0.5 * v.length * v.axis;
    w.path[i].push_back({front - kPetLineBehind * v.axis, -kPetLineBehind, nan});
    w.path[i].push_back({front, 0.0, t});
  }
  // the straight lines behind both may cross already (one or both is past the crossing), or one's
  // line ahead the other's behind
  findCrossing(w);
}

void observePet(const Vec2& fa, const Vec2& fb, double t, PetWatch& w) {
  if (!w.active || !(t > w.lastT)) return;
  const Vec2* c[2] = {&fa, &fb};
  for (int i = 0; i < 2 && w.active; ++i) {
    if (std::isnan(c[i]->x())) continue;
    auto& path = w.path[static_cast<std::size_t>(i)];
    const double step = (*c[i] - path.back().p).norm();
    if (step == 0.0) continue;  // standing: its last point holds
    path.push_back({*c[i], path.back().arc + step, t});
  }
  w.lastT = t;
  if (!w.active) return;
  if (w.crossed) timePassages(w);
  else findCrossing(w);
}


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
    const double tc = detector.kind == DetectorKind::Box ? ttc : boxTtc(a, b, detector.motion, safeTime).actTime();
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
