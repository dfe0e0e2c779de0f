#pragma once
// The backend's SUMO records through the highway model's one conversion
// (sthighway/sumo_conversion.hpp: SUMO's conventions and ours, for every source alike).
#include <limits>

#include <sthighway/road.hpp>
#include <sthighway/vehicle.hpp>

#include <stcosim/backend.hpp>

namespace st::cosim {

using highway::VehicleTypeInfo;
VehicleTypeInfo toVehicleTypeInfo(const SumoVehicleType& type);

highway::VehicleState toVehicleState(const SumoVehicle& v, const SumoVehicleType& type);
// The same into an existing state (its id's buffer is reused); `equipped` is left as it is.
void toVehicleState(const SumoVehicle& v, const VehicleTypeInfo& type, highway::VehicleState& s);
// Lanes as the highway model wants them (shapes and widths from the network).
highway::RoadGeometry toRoadGeometry(const std::vector<SumoLane>& lanes);

}  // namespace st::cosim
