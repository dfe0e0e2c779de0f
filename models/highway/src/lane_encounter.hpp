#pragma once
// How two road users' paths meet (EncounterType, sthighway/conflict.hpp), read from the lanes each
// drives on and takes next: the network's topology and its junction lanes' shapes, not the
// momentary headings SSAM's angle classes use.
#include <vector>

#include <sthighway/conflict.hpp>

#include "lane_prediction.hpp"

namespace st::highway::detail {

// The encounter of the two cars (slots) whose paths reach reachA and reachB m past their centres.
// scratchA, scratchB: kept by the caller between calls (the lanes ahead of each).
EncounterType laneEncounter(const LanePrediction& lanes, int a, int b, double reachA, double reachB,
                        std::vector<int>& scratchA, std::vector<int>& scratchB);

// The same on two lane lists (each from the lane its car is on, in the order its path takes them).
EncounterType laneEncounter(const LanePrediction& lanes, const std::vector<int>& la, const std::vector<int>& lb);

}  // namespace st::highway::detail
