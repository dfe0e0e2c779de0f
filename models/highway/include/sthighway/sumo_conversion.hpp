#pragma once
// SUMO's records to the highway model's states: the one conversion every source uses (libsumo and
// libtraci through cosim, FCD traces through FcdReader, Python's step_sumo), so a replay or a
// script sees what the live run saw. SUMO's conventions and ours:
//   position  SUMO reports the centre of the front bumper; we use the centre of the body:
//             centre = front - L/2 * (cos h, sin h). On a curve the body is the chord from
//             SUMO's back to its front, shorter than L (PathBodies below).
//   heading   SUMO's angle is navigational degrees (0 = north, clockwise); ours is radians
//             counter-clockwise from +x: h = (90 - angle) * pi / 180.
//   velocity  SUMO's angle already turns with the vehicle's lateral motion in the sublane model
//             (it is the direction of travel), so the velocity is |v| along the heading with
//             |v| = hypot(speed, lateral speed) and our lateral speed is 0. Without the sublane
//             model lateral speed is 0 and this is the plain speed. (A lane change SUMO makes in
//             one step is no lateral motion: SUMO reports none.)
//   signals   bit 0 (right blinker) and bit 1 (left blinker) to our TurnSignal bits; bit 2, the
//             hazard lights, says nothing about a lane change and is not a blinker here.
//   lights    the link state of its next traffic light and the distance to its stop line become
//             where it must stop (stopDistanceOf): the prediction brakes it evenly to stand there.
//   type      the vType's vClass (SUMO's default when absent: passenger; a name we do not know:
//             Other), its length and width (SUMO's length includes no minGap) and decel, each
//             SUMO 1.15's default for the vClass where the vType sets none (what a live run reads
//             back from SUMO), and its mass from <param key="mass" value="kg"/> (or a mass
//             attribute) if present, else the per-class default of classDefaults.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <sthighway/vehicle.hpp>

namespace st::highway {

// SUMO's signal bits (TraCI "signal states", FCD's `signals`).
inline constexpr int kSumoBlinkerRight = 1;
inline constexpr int kSumoBlinkerLeft = 2;
inline constexpr int kSumoHazardLights = 4;

// A vType as SUMO gives it; what is not given is empty.
struct SumoTypeRecord {
  std::string vClass;             // SUMO's vClass name; empty: SUMO's default, passenger
  std::optional<double> length;   // m
  std::optional<double> width;    // m
  std::optional<double> mass;     // kg
  std::optional<double> decel;    // m/s^2, SUMO's decel (normal maximum braking)
};

// A vType as the highway model wants it, converted once per type.
struct VehicleTypeInfo {
  VehicleClass vehicleClass = VehicleClass::Passenger;
  double length = 5.0;
  double width = 1.8;
  double mass = 1500.0;
  double decel = std::numeric_limits<double>::quiet_NaN();  // m/s^2, the vType's `decel`; NaN: not given
};
VehicleTypeInfo toVehicleTypeInfo(const SumoTypeRecord& type);

// SUMO's default person type (DEFAULT_PEDTYPE, vClass pedestrian): the type of a person whose
// vType is not known.
VehicleTypeInfo defaultPersonType();

// A type that no vType describes (a trace read without its route file): the class guessed from
// the type's name ("truck", "bus", "moto", ... in it; else passenger) with classDefaults' body
// and mass, decel unknown.
VehicleTypeInfo guessVehicleType(const std::string& typeName);

// One vehicle in one step as SUMO reports it.
struct SumoVehicleRecord {
  double x = 0.0, y = 0.0;    // front-bumper centre (m)
  double angle = 0.0;         // navigational degrees: 0 = north, clockwise
  double speed = 0.0;         // longitudinal (m/s)
  double lateralSpeed = 0.0;  // to the left (m/s), sublane model only
  double acceleration = 0.0;  // longitudinal (m/s^2)
  int signals = 0;            // SUMO's signal bits
  // Where its route next has it stop or give way: the state of its link at the next traffic light
  // or junction (SUMO's letters: r red, y yellow, G green, g a light's minor green, m minor, =
  // equal, s stop sign or stop then go, w all-way stop, u red-yellow, o/O off) and the distance
  // from its front bumper to the stop line, or to the wait point inside the junction where SUMO
  // holds a turner (then m) (m); 0: none ahead or not read.
  char nextSignal = 0;
  double nextSignalDistance = 0.0;
};

// Where the car must stop (VehicleState::stopDistance): at its next stop line when that is red
// (r), red-yellow (u), a stop sign (s, w) and it can stop there braking at most twice its vType's
// decel (an emergency's; SUMO's passenger 4.5 m/s^2 if unknown); yellow (y) when it can stop at
// its decel; a link where it gives way (g, m, =: the priority rules) at that point when it can
// stop at its decel (one that cannot has taken its gap); else nowhere (infinity: it goes on).
double stopDistanceOf(const SumoVehicleRecord& v, double decel);

// SUMO's link states where a driver gives way or stops first: a light's minor green (g), a
// junction's minor link (m), equal priority (=), a stop sign (s), an all-way stop (w).
bool givesWayAt(char linkState);
// Those that let a car into the junction (green, minor, equal, off): on a turn with a wait point
// inside the junction, it gives way there (m).
bool entersAt(char linkState);

std::uint8_t toTurnSignals(int sumoSignals);

// The junction a lane lies in: SUMO names a junction's internal lanes, crossings and walking areas
// ":<junction>_<n>_<index>" (":C_12_0", ":C_c0_0", ":C_w1_0"; a junction id may hold '_'
// itself, as "cluster_1_2"); "" for a lane between junctions or an unknown one.
std::string junctionOfLane(const std::string& laneId);

// Writes the record's motion and the type's body into `s`; its id, handle, lane, route and
// `equipped` are the caller's and left as they are.
void toVehicleState(const SumoVehicleRecord& v, const VehicleTypeInfo& type, VehicleState& s);

// SUMO lays a vehicle along the lanes it drives: its back is where its front was `length` metres
// of path before, and its angle points from that back to its front (MSVehicle::computeAngle); its
// junction collision check and the SSM device use that straight body. On a curve the chord is
// shorter than the vehicle: a 10 m truck on a 5.6 m corner is 8.8 m from back to front, and laid
// at full length along SUMO's angle it would reach 1.2 m past SUMO's back into the next lane.
// PathBodies keeps each vehicle's recent fronts (moved sideways with it when it changes lanes in
// one step) and gives the body the chord from the trail's point `length` behind to the front. The
// full length stays where the trail does not reach that far (just inserted) or its point is off the
// line of SUMO's angle (a sublane turn, a trace sampled too coarsely to follow the curve).
class PathBodies {
 public:
  // Fits s, a vehicle converted by toVehicleState at time t, to its chord. key: the caller's dense
  // index for the vehicle (a serial, a trace handle), never another vehicle's while it is on the
  // road. Persons are left as they are.
  void fit(std::size_t key, double t, VehicleState& s);

 private:
  struct Trail {
    std::vector<Vec2> fronts;  // oldest first
    double time = -std::numeric_limits<double>::infinity();
  };
  std::vector<Trail> trails_;
};

}  // namespace st::highway
