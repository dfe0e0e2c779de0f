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

}  // namespace st::highway
