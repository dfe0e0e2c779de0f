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
  Vec2 egoPos = Vec2::Zero(), egoVel = Vec2::Zero(), egoAxis = Vec2(1.0, 0.0);
  Vec2 foePos = Vec2::Zero(), foeVel = Vec2::Zero(), foeAxis = Vec2(1.0, 0.0);  // vehicle threats
  int lane = -1;     // the ego's lane (index into the road's lanes)
  int feature = -1;  // road threats: the feature that fired
};

inline void capture(const VehicleTable& cars, int e, const Threat& th, ConflictCapture& c) {
  const Body& a = cars.body[e];
  c.egoPos = a.position;
  c.egoVel = a.velocity;
  c.egoAxis = a.axis;
  c.lane = cars.lane[e];
  if (th.kind == WarningKind::Vehicle) {
    const Body& b = cars.body[th.foe];
    c.foePos = b.position;
    c.foeVel = b.velocity;
    c.foeAxis = b.axis;
    c.feature = -1;
  } else {
    c.feature = th.feature;
  }
}

// The conflict fields of w (x .. lateralSpeed, but lane and line: the caller names them) from a
// capture, the two masses (foeMass for vehicle warnings) and the episode's minimum TTC.
void describeConflict(const ConflictCapture& c, WarningKind kind, double egoMass, double foeMass, double ttc,
                      const RoadFeatures& road, const ConflictConfig& config, Warning& w);

}  // namespace st::highway::detail
