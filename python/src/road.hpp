#pragma once
// The road a monitor checks: from a SUMO .net.xml, or from lane dicts the caller read (TraCI).
#include <pybind11/pybind11.h>

#include <sthighway/road.hpp>

namespace stpy {

st::highway::RoadGeometry roadOf(pybind11::handle net);
// Lanes given by the caller (e.g. read through TraCI): dicts with id, edge, index, shape, width.
st::highway::RoadGeometry roadOfLanes(pybind11::handle lanes);

}  // namespace stpy
