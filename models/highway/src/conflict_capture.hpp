#pragma once
// What an episode keeps of its tick of minimum TTC for the analyst (sthighway/conflict.hpp): the
// two bodies' positions, velocities and axes, copied when an episode's minimum improves (often:
// an approach improves it every tick) and turned into speeds, angle, type and severity only
// when the episode ends. Kept apart from the episode pool so the pool stays small.
#include <sthighway/conflict.hpp>
#include <sthighway/monitor.hpp>

#include "pair_test.hpp"
#include "road_search.hpp"
#include "vehicle_table.hpp"

namespace st::highway::detail {

struct ConflictCapture {
  Body ego, foe;     // foe: vehicle threats
  int lane = -1;     // the ego's lane (index into the road's lanes)
  int feature = -1;  // road threats: the feature that fired
};

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
// capture, the two masses (foeMass for vehicle warnings), the episode's minimum TTC and the safe
// time then, and the detector (for the collision course).
void describeConflict(const ConflictCapture& c, WarningKind kind, double egoMass, double foeMass, double ttc,
                      double safeTime, const DetectorConfig& detector, const RoadFeatures& road, const ConflictConfig& config,
                      Warning& w);

}  // namespace st::highway::detail
