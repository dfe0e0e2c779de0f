#pragma once
// Road fixtures shared by the highway tests.
#include <string>
#include <utility>
#include <vector>

#include <sthighway/road.hpp>

namespace st::highway {

// Lane `index` of `edge`, named as SUMO names it (edge_index), along `shape`.
inline Lane laneOf(const std::string& edge, int index, std::vector<Vec2> shape) {
  Lane l;
  l.id = edge + "_" + std::to_string(index);
  l.edge = edge;
  l.index = index;
  l.shape = std::move(shape);
  return l;
}

// One straight lane along x from -100 to 1000 m, 3.2 m wide (edge "e"): a road for scenes whose
// geometry is worked out by hand.
inline RoadGeometry oneLaneRoad() {
  RoadGeometry r;
  r.lanes.push_back({"e_0", "e", 0, {Vec2(-100.0, 0.0), Vec2(1000.0, 0.0)}, 3.2, false});
  return r;
}

}  // namespace st::highway
