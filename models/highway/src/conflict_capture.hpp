#pragma once
// What an episode keeps of its tick of minimum TTC for the analyst (sthighway/conflict.hpp): the
// two bodies' positions, velocities and axes, copied when an episode's minimum improves (often:
// an approach improves it every tick) and turned into speeds, angle, type and severity only
// when the episode ends. Kept apart from the episode pool so the pool stays small.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <sthighway/conflict.hpp>
#include <sthighway/monitor.hpp>

#include "pair_test.hpp"
#include "road_search.hpp"
#include "vehicle_table.hpp"

namespace st::highway::detail {

// What an episode gathers over all its ticks (SSAM's MaxS, DR, MaxD, start and end points),
// beside the state at its minimum TTC; capture() leaves it alone.
struct EpisodeTrack {
  Vec2 start = Vec2::Zero(), last = Vec2::Zero();  // the ego's centre at begin, at its latest tick
  double maxSpeed = 0.0;                           // either vehicle's (m/s)
  double dr = std::numeric_limits<double>::quiet_NaN();    // the ego's DR (m/s^2); NaN: no tick after begin yet
  double maxD = std::numeric_limits<double>::quiet_NaN();  // its lowest acceleration (m/s^2)
  bool braked = false;                                     // dr is its first braking
};

// PET, post-encroachment time, of two crossing or merging paths: the time from the first vehicle
// leaving the conflict area to the second entering it (SUMO's SSM device; Allen et al. 1978). The
// paths are the two vehicles' straight lines at the tick of the minimum TTC, their conflict area
// the part both bodies sweep: a vehicle is in it while its centre lies within `r` of the lines'
// crossing along its own line (half its length, and the other's half width and its own half width
// across, over the sine of the angle). Measured from the positions the vehicles then take, each
// crossing of the area's ends timed between ticks by linear interpolation. Paths closer than
// SSAM's rear-end angle to parallel have no crossing to speak of (SSAM's rear-ends): inactive.
struct PetWatch {
  bool active = false;
  Vec2 x = Vec2::Zero();                      // the lines' crossing
  std::array<Vec2, 2> dir{};                  // unit path directions: ego, foe
  std::array<double, 2> r{}, s{};             // the area's half length along each path; the last position on it
  std::array<double, 2> enter{}, exit{};      // s, NaN until seen
  double lastT = 0.0;
  // PET (s) once known, else NaN: entry of the later-entering minus exit of the earlier
  double pet() const {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (!active || std::isnan(enter[0]) || std::isnan(enter[1])) return nan;
    const int first = enter[0] <= enter[1] ? 0 : 1;
    return std::isnan(exit[first]) ? nan : enter[1 - first] - exit[first];
  }
};

// The paths a PET is measured for: at least the rear-end angle from parallel and from head-on,
// as sine and cosine (worked out once: a watch starts at every new minimum TTC).
struct PetAngles {
  double minSine = 0.0, maxNegCosine = 0.0;
  static PetAngles of(double minAngleDeg) {
    return {std::sin(toRadians(minAngleDeg)), std::cos(toRadians(minAngleDeg))};
  }
};

// A PET watch on the two bodies at time t (the tick of a new minimum TTC).
inline void startPet(const Body& a, const Body& b, double t, const PetAngles& angles, PetWatch& w) {
  w = PetWatch{};
  const double sine = cross(a.axis, b.axis), cosine = a.axis.dot(b.axis);
  if (std::abs(sine) < angles.minSine || cosine < -angles.maxNegCosine) return;
  w.active = true;
  // the crossing: a + s a_axis = b + u b_axis
  const double sa = cross(b.position - a.position, b.axis) / sine;
  w.x = a.position + sa * a.axis;
  w.dir = {a.axis, b.axis};
  w.r[0] = 0.5 * a.length + (0.5 * b.width + 0.5 * a.width * std::abs(cosine)) / std::abs(sine);
  w.r[1] = 0.5 * b.length + (0.5 * a.width + 0.5 * b.width * std::abs(cosine)) / std::abs(sine);
  const Body* bodies[2] = {&a, &b};
  for (int i = 0; i < 2; ++i) {
    w.s[i] = (bodies[i]->position - w.x).dot(w.dir[i]);
    // already in the area (or past it): entered (and left) by now, at the latest
    w.enter[i] = w.s[i] >= -w.r[i] ? t : std::numeric_limits<double>::quiet_NaN();
    w.exit[i] = w.s[i] > w.r[i] ? t : std::numeric_limits<double>::quiet_NaN();
  }
  w.lastT = t;
}
inline void startPet(const Body& a, const Body& b, double t, double minAngleDeg, PetWatch& w) {
  startPet(a, b, t, PetAngles::of(minAngleDeg), w);
}

// The vehicles' centres at a later tick t (NaN: that one is gone): the area's ends each has passed.
inline void observePet(const Vec2& ca, const Vec2& cb, double t, PetWatch& w) {
  if (!w.active || !(t > w.lastT)) return;
  const Vec2* c[2] = {&ca, &cb};
  for (int i = 0; i < 2; ++i) {
    if (std::isnan(c[i]->x())) continue;
    const double s = (*c[i] - w.x).dot(w.dir[i]), s0 = w.s[i];
    // when it passed position `at` between the ticks
    auto when = [&](double at) { return s == s0 ? t : w.lastT + (t - w.lastT) * (at - s0) / (s - s0); };
    if (std::isnan(w.enter[i]) && s >= -w.r[i]) w.enter[i] = when(-w.r[i]);
    if (std::isnan(w.exit[i]) && s > w.r[i]) w.exit[i] = when(w.r[i]);
    w.s[i] = s;
  }
  w.lastT = t;
}

struct ConflictCapture {
  Body ego, foe;     // foe: vehicle threats
  int lane = -1;     // the ego's lane (index into the road's lanes)
  int feature = -1;  // road threats: the feature that fired
  EpisodeTrack track;
  PetWatch pet;  // from the tick of the minimum TTC on
};

// The DRAC of ego e's threat th at this tick, as describeConflict has it at the minimum TTC: the
// closing speed of the centres (vehicles), or the speed towards the feature's closest point.
double tickDrac(const VehicleTable& cars, const RoadFeatures& road, int e, const Threat& th);

// A new episode of ego e (against slot foe, or -1 for a road feature): the track starts.
inline void beginTrack(const VehicleTable& cars, int e, int foe, EpisodeTrack& k) {
  k = EpisodeTrack{};
  k.start = k.last = cars.centre[e];
  k.maxSpeed = cars.vel[e].norm();
  if (foe >= 0) k.maxSpeed = std::max(k.maxSpeed, cars.vel[foe].norm());
}
// A later tick of the episode (its ego here; the foe, if a slot, counted while here): MaxS, the
// ego's acceleration since its last tick (wholly after begin) into DR and MaxD, its latest centre.
inline void advanceTrack(const VehicleTable& cars, int e, int foe, EpisodeTrack& k) {
  k.last = cars.centre[e];
  k.maxSpeed = std::max(k.maxSpeed, cars.vel[e].norm());
  if (foe >= 0 && cars.inputOf[foe] >= 0) k.maxSpeed = std::max(k.maxSpeed, cars.vel[foe].norm());
  const double a = cars.accel[e];
  if (std::isnan(a)) return;
  k.maxD = std::isnan(k.maxD) ? a : std::min(k.maxD, a);
  // SSAM's DR: the first negative acceleration; while there is none, the lowest
  if (!k.braked) {
    k.dr = std::isnan(k.dr) ? a : std::min(k.dr, a);
    k.braked = a < 0.0;
    if (k.braked) k.dr = a;
  }
}

// lane: the ego's reported lane (LanePrediction::reportedLane)
inline void capture(const VehicleTable& cars, int lane, int e, const Threat& th, ConflictCapture& c) {
  c.ego = cars.body[e];
  c.lane = lane;
  if (th.kind == WarningKind::Vehicle) {
    c.foe = cars.body[th.foe];
    c.feature = -1;
  } else {
    c.feature = th.feature;
  }
}

// On a collision course (conflict.hpp): the two bodies' exact rectangles meet within the safe
// time. Always so for a box warning (its TTC is the rectangles', along the prediction); for the
// circle detectors, whose zones reach beyond the body, the rectangles in straight lines at the
// detector's motion model (as hindsight's near misses have it).
inline bool onCollisionCourse(const DetectorConfig& dc, const Body& ego, const Body& foe, double safeTime) {
  return dc.kind == DetectorKind::Box || boxTtc(ego, foe, dc.motion, safeTime) <= safeTime;
}

// The conflict fields of w (x .. lateralSpeed, but lane and line: the caller names them) from a
// capture, the two masses (foeMass for vehicle warnings), whether one of the two is a pedestrian
// (the type is then Pedestrian), the episode's minimum TTC and the safe time then, and the
// detector (for the collision course).
void describeConflict(const ConflictCapture& c, WarningKind kind, double egoMass, double foeMass, bool pedestrian, double ttc,
                      double safeTime, const DetectorConfig& detector, const RoadFeatures& road, const ConflictConfig& config,
                      Warning& w);

}  // namespace st::highway::detail
