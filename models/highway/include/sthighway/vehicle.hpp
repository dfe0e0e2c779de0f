#pragma once
// The state of one vehicle at one tick, in our conventions: centre of the body, heading in
// radians counter-clockwise from +x, SI units. Whoever feeds the model (a trace reader, the SUMO
// coupling, a test) converts to these once.
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>

#include <stcore/vec.hpp>

namespace st::highway {

// Road users that differ in braking force (safe time) and default size/mass. Bicycles are
// vehicles to SUMO and to us; a pedestrian is a SUMO person (cosim reads them beside the
// vehicles): a foe with its own small body, never equipped unless a scenario says so.
enum class VehicleClass : std::uint8_t { Passenger, Truck, Bus, Motorcycle, Emergency, Other, Bicycle, Pedestrian };
inline constexpr int kVehicleClassCount = 8;

const char* toString(VehicleClass c);
// Maps SUMO's vClass names ("passenger", "truck", "trailer", "bus", "coach", "motorcycle",
// "bicycle", "pedestrian", ...) and our own names; anything unknown is Other.
VehicleClass vehicleClassFromName(std::string_view name);

// Turn-signal bits (ours, not SUMO's: the trace reader converts).
enum TurnSignal : std::uint8_t { kSignalNone = 0, kSignalLeft = 1, kSignalRight = 2 };

// How many edges of a vehicle's route it carries (VehicleState::route): enough for the
// junctions within the longest prediction horizon on urban blocks; beyond them, straight on.
inline constexpr int kRouteAhead = 8;

struct VehicleState {
  std::string id;                // for output; the monitor finds a vehicle by its handle
  // The caller's dense index for this vehicle (0, 1, 2, ...; the same at every tick while it is
  // on the road, never given to another vehicle at the same tick), or -1: found by its id.
  int handle = -1;
  Vec2 position = Vec2::Zero();  // centre of the body (m)
  double heading = 0.0;          // rad, counter-clockwise from +x
  double speed = 0.0;            // along the heading (m/s)
  double lateralSpeed = 0.0;     // to the left of the heading (m/s)
  double acceleration = 0.0;     // along the heading (m/s^2)
  double length = 5.0;           // m
  double width = 1.8;            // m
  double mass = 1500.0;          // kg
  // Its normal maximum braking (m/s^2, SUMO's vType `decel`; beyond it SUMO calls braking an
  // emergency), or NaN: unknown. Hindsight confirms a warning by braking beyond it.
  double decel = std::numeric_limits<double>::quiet_NaN();
  VehicleClass vehicleClass = VehicleClass::Passenger;
  std::uint8_t signals = kSignalNone;  // TurnSignal bits
  bool equipped = true;          // a smart car raises warnings; every vehicle is a potential foe
  // The lane it drives on: an index into the monitor's RoadGeometry::lanes, or -1 (unknown; a
  // source without a network). Only reported (warnings.csv), never used to decide a warning.
  int lane = -1;
  // Its route from the edge it is on (or, inside a junction, the edge it left) on: indices into
  // edgeIds(road) of the monitor's RoadGeometry, -1 past the last one known. The road-aware
  // prediction follows it through junctions; without one (all -1: FCD traces, most callers) a
  // car is predicted into the turn its signal shows, else the straightest successor.
  std::array<int, kRouteAhead> route = {-1, -1, -1, -1, -1, -1, -1, -1};
  // Where it must stop: metres from its front bumper to a red light's stop line ahead (SUMO's
  // next traffic light, sumo_conversion.hpp), infinity: nowhere. Its motion is predicted braking
  // evenly to stand there, under either motion model.
  double stopDistance = std::numeric_limits<double>::infinity();

  Vec2 direction() const { return {std::cos(heading), std::sin(heading)}; }
  Vec2 velocity() const {
    const Vec2 d = direction();
    return speed * d + lateralSpeed * Vec2(-d.y(), d.x());
  }
};

// Typical size and mass per class, for sources that do not give them (documented defaults:
// passenger 5 m x 1.8 m 1500 kg; truck 12 m x 2.55 m 15 t; bus 12 m x 2.55 m 12 t;
// motorcycle 2.2 m x 0.9 m 250 kg; emergency 6.5 m x 2.2 m 3.5 t; other as passenger;
// bicycle 1.6 m x 0.65 m 90 kg with its rider; pedestrian 0.215 m x 0.478 m (SUMO's person) 70 kg).
struct ClassDefaults {
  double length;
  double width;
  double mass;
};
ClassDefaults classDefaults(VehicleClass c);

// SUMO (and most traffic tools) report the front-bumper centre and a navigational angle in
// degrees (0 = north, clockwise). These turn that into our centre + math heading.
inline double headingFromNavigationDegrees(double degrees) {
  return toRadians(90.0 - degrees);
}
inline Vec2 centreFromFrontBumper(const Vec2& front, double heading, double length) {
  return front - 0.5 * length * Vec2(std::cos(heading), std::sin(heading));
}

// Which vehicles carry the smart-car system at a penetration rate: a deterministic draw in [0, 1)
// per seed and vehicle id, independent of arrival order and of the standard library (FNV-1a of
// the id mixed by splitmix64), so a trace replay and a live SUMO run equip the same vehicles.
double equipmentDraw(std::uint64_t seed, std::string_view id);
inline bool drawnEquipped(std::uint64_t seed, std::string_view id, double penetration) {
  return penetration >= 1.0 || equipmentDraw(seed, id) < penetration;
}

}  // namespace st::highway
