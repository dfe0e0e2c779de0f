#pragma once
// What an episode keeps of its tick of minimum TTC for the analyst (sthighway/conflict.hpp):
// where the ego was, both speeds, the angle, the type and the severity. Taken only when an
// episode's minimum improves, kept apart from the episode pool so the pool stays small.
#include <sthighway/conflict.hpp>
#include <sthighway/monitor.hpp>

#include "pair_test.hpp"
#include "road_search.hpp"
#include "vehicle_table.hpp"

namespace st::highway::detail {

struct ConflictCapture {
  Vec2 position = Vec2::Zero();  // the ego's centre (m)
  double egoSpeed = 0.0;         // |velocity| (m/s)
  double foeSpeed = 0.0;         // vehicle warnings; NaN for road
  double headingAngle = 0.0;     // deg: between the headings; road: between heading and line (0..90)
  double drac = 0.0;             // m/s^2
  double maxDeltaV = 0.0;        // vehicle warnings; NaN for road
  double lateralSpeed = 0.0;     // road: speed towards the line; NaN for vehicle warnings
  int lane = -1;                 // the ego's lane (index into the road's lanes)
  int feature = -1;              // road: the feature that fired
  ConflictType type = ConflictType::Road;
};

// The capture of ego e's threat th at this tick.
ConflictCapture captureConflict(const VehicleTable& cars, const RoadSearch& road, const ConflictConfig& config, int e,
                                const Threat& th);

}  // namespace st::highway::detail
