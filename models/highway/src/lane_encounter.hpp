#pragma once
// How two road users' paths meet (EncounterType, sthighway/conflict.hpp), read from the lanes each
// drives on and takes next: the network's topology and its junction lanes' shapes, not the
// momentary headings SSAM's angle classes use.
#include <limits>
#include <vector>

#include <sthighway/conflict.hpp>

#include "lane_prediction.hpp"

namespace st::highway::detail {

// How and where two paths meet. The point lies on both paths' centre lines: where they cross
// (crossing, opposing), where the common lane starts (merging), where the lanes part (diverging);
// NaN when one follows the other, they run side by side, or nothing is known. lane: the lane of
// one of the paths the point lies on (-1 with no point); a junction lane names the junction.
// alongA, alongB: where the paths cross, the unit direction of each one's lane there (NaN else).
struct LaneMeeting {
  EncounterType type = EncounterType::Unknown;
  Vec2 point = Vec2::Constant(std::numeric_limits<double>::quiet_NaN());
  int lane = -1;
  Vec2 alongA = Vec2::Constant(std::numeric_limits<double>::quiet_NaN());
  Vec2 alongB = Vec2::Constant(std::numeric_limits<double>::quiet_NaN());
};

// The meeting of the two cars (slots) whose paths reach reachA and reachB m past their centres.
// scratchA, scratchB: kept by the caller between calls (the lanes ahead of each).
LaneMeeting laneEncounter(const LanePrediction& lanes, int a, int b, double reachA, double reachB,
                          std::vector<int>& scratchA, std::vector<int>& scratchB);

// The same on two lane lists (each from the lane its car is on, in the order its path takes them).
LaneMeeting laneEncounter(const LanePrediction& lanes, const std::vector<int>& la, const std::vector<int>& lb);

}  // namespace st::highway::detail
