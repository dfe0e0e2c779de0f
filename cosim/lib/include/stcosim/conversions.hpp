#pragma once
// SUMO's conventions to ours, in one place:
//   position  SUMO reports the centre of the front bumper; we use the centre of the body:
//             centre = front - L/2 * (cos h, sin h).
//   heading   SUMO's angle is navigational degrees (0 = north, clockwise); ours is radians
//             counter-clockwise from +x: h = (90 - angle) * pi / 180.
//   velocity  SUMO's angle already turns with the vehicle's lateral motion in the sublane model
//             (it is the direction of travel), so the velocity is |v| along the heading with
//             |v| = hypot(speed, lateral speed) and our lateral speed is 0. Without the sublane
//             model lateral speed is 0 and this is the plain speed.
//   signals   SUMO bit 0 (right blinker) and bit 1 (left blinker) to our TurnSignal bits.
//   mass      the vType's <param key="mass" value="kg"/> if present, else the documented per-class
//             default of st::highway::classDefaults (passenger 1500 kg, truck 15 t, bus 12 t,
//             motorcycle 250 kg, emergency 3.5 t, other 1500 kg).
//   size      the vType's length and width (SUMO's length includes no minGap).
#include <limits>

#include <sthighway/road.hpp>
#include <sthighway/vehicle.hpp>

#include <stcosim/backend.hpp>

namespace st::cosim {

// A vType as the highway model wants it, converted once per type.
struct VehicleTypeInfo {
  highway::VehicleClass vehicleClass = highway::VehicleClass::Other;
  double length = 0.0, width = 0.0, mass = 0.0;
  double decel = std::numeric_limits<double>::quiet_NaN();  // m/s^2, SUMO's vType decel; NaN unknown
};
VehicleTypeInfo toVehicleTypeInfo(const SumoVehicleType& type);

highway::VehicleState toVehicleState(const SumoVehicle& v, const SumoVehicleType& type);
// The same into an existing state (its id's buffer is reused); `equipped` is left as it is.
void toVehicleState(const SumoVehicle& v, const VehicleTypeInfo& type, highway::VehicleState& s);
// Lanes as the highway model wants them (shapes and widths from the network).
highway::RoadGeometry toRoadGeometry(const std::vector<SumoLane>& lanes);

}  // namespace st::cosim
