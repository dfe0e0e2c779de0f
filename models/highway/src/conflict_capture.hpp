#pragma once
// What an episode keeps of its tick of minimum TTC for the analyst (sthighway/conflict.hpp): the
// two bodies' positions, velocities and axes, copied when an episode's minimum improves (often:
// an approach improves it every tick) and turned into speeds, angle, type and severity only
// when the episode ends. Kept apart from the episode pool so the pool stays small.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

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
// leaving the conflict area to the second entering it, as SUMO's SSM device has it (Allen et al.
// 1978). The paths are the ones the two vehicles' fronts take (SUMO keeps a front on its lane's
// centre line): from the tick of the minimum TTC on, behind that the straight line back along the
// heading. The conflict point is where the two paths cross, and a vehicle is in the conflict area
// from its front half the other's width before the point until its back, a length behind the front
// along its path, is half the other's width past it, where paths cross at right angles. At other
// angles the area begins where SSM's does (MSDevice_SSM: MSLink's lengths before the crossing): the
// front at the other's lane border, over the sine of the crossing's angle, less half the lane's
// width left beside the other vehicle, so the area runs from (W/2)/sin - (W - w)/2 before the point
// to w + L past that (W: the other's lane width, w its width, L the vehicle's length). Until one
// path has run over the other,
// the point is where one's straight line ahead meets the other's path. Each passage is timed between
// ticks by linear interpolation; one behind the tick of the minimum TTC happened by then at the
// latest. Paths that start closer than SSAM's rear-end angle to parallel (SSAM's rear-ends: their
// own PET), or cross at an acute angle of sine below 0.2 (SUMO's floor), are inactive. A turning car's
// path is its own, so a left turn across oncoming traffic has its PET where the two really cross.
struct PetWatch {
  struct Point {
    Vec2 p;
    double arc;  // along the path from the front at the start (m; < 0: the line behind it)
    double t;    // when the front was there (s; NaN: the line behind, never driven in the watch)
  };
  bool active = false;
  bool crossed = false;                       // one's path has run over the other's: the point holds for good
  std::array<std::vector<Point>, 2> path;     // ego, foe
  std::array<double, 2> length{}, width{}, laneWidth{};
  Vec2 x = Vec2::Zero();                      // the conflict point
  std::array<double, 2> in{}, out{};          // the arcs along each path where its front enters, and leaves, the area
  std::array<double, 2> enter{}, exit{};      // s, NaN until seen
  double lastT = 0.0;
  // PET (s) once known, else NaN: entry of the later-entering minus exit of the earlier; known once
  // the paths have crossed, or (settled: the watch is over) where one's line ahead meets the other's
  // path (a vehicle that entered the area and stopped short of the crossing)
  double pet(bool settled = false) const {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (!active || !(crossed || settled) || std::isnan(enter[0]) || std::isnan(enter[1])) return nan;
    const int first = enter[0] <= enter[1] ? 0 : 1;
    return std::isnan(exit[first]) ? nan : enter[1 - first] - exit[first];
  }
};

// The paths a PET watch starts on: headed at least the rear-end angle apart, as a sine (worked
// out once: a watch starts at every new minimum TTC).
struct PetAngles {
  double minSine = 0.0;
  static PetAngles of(double minAngleDeg) { return {std::sin(toRadians(minAngleDeg))}; }
};

// A PET watch on the two bodies at time t (the tick of a new minimum TTC), on lanes of those widths.
void startPet(const Body& a, const Body& b, double laneWidthA, double laneWidthB, double t, const PetAngles& angles,
              PetWatch& w);
inline void startPet(const Body& a, const Body& b, double t, double minAngleDeg, PetWatch& w) {
  startPet(a, b, kSumoLaneWidth, kSumoLaneWidth, t, PetAngles::of(minAngleDeg), w);
}

// The vehicles' fronts at a later tick t (NaN: that one is gone; VehicleTable::front): the paths
// grow, their crossing is looked for, and the area's ends each has passed are timed.
void observePet(const Vec2& fa, const Vec2& fb, double t, PetWatch& w);

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
  return dc.kind == DetectorKind::Box || boxTtc(ego, foe, dc.motion, safeTime).actTime() <= safeTime;
}

// The conflict fields of w (x .. lateralSpeed, but lane and line: the caller names them) from a
// capture, the two masses (foeMass for vehicle warnings), whether one of the two is a pedestrian
// (the type is then Pedestrian), the episode's minimum TTC and the safe time then, and the
// detector (for the collision course).
void describeConflict(const ConflictCapture& c, WarningKind kind, double egoMass, double foeMass, bool pedestrian, double ttc,
                      double safeTime, const DetectorConfig& detector, const RoadFeatures& road, const ConflictConfig& config,
                      Warning& w);

}  // namespace st::highway::detail
