#pragma once
// Vehicle states from Python: a list of dicts (one per vehicle) or a dict of columns (NumPy
// arrays or sequences), in our conventions (centre, heading in rad from +x) or SUMO's (front
// bumper, navigational degrees, SUMO's vClass and signal bits: through the one conversion every
// SUMO source uses, sthighway/sumo_conversion.hpp); and a state back as a dict.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <unordered_map>
#include <vector>

#include <sthighway/monitor.hpp>

namespace stpy {

namespace py = pybind11;
namespace hw = st::highway;

enum class Convention { Ours, Sumo };

// A lane id's index into the monitor's RoadGeometry::lanes (VehicleState::lane), and an edge id's
// into edgeIds(road) (VehicleState::route).
using LaneIndex = std::unordered_map<std::string, int>;
using EdgeIndex = std::unordered_map<std::string, int>;

// A list of dicts, or a dict of equally long columns, into out (in the given order).
void readStates(py::handle vehicles, Convention c, const LaneIndex& lanes, const EdgeIndex& edges,
                std::vector<hw::VehicleState>& out);
// A state as the dict step() takes in our conventions (with its lane id when road is given).
py::dict stateDict(const hw::VehicleState& s, const hw::RoadGeometry* road);

}  // namespace stpy
