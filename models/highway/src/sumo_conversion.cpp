#include <sthighway/sumo_conversion.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <string_view>

namespace st::highway {

namespace {

// What SUMO 1.15 gives a vType of each vClass that sets no length, width or decel (read back
// through TraCI's vehicletype.getLength/getWidth/getDecel), so a vType file read beside a trace
// gives the bodies the live run had. Classes not listed take passenger's, as SUMO does.
struct SumoClassDefaults {
  std::string_view vClass;
  double length, width, decel;
};
constexpr SumoClassDefaults kSumoClassDefaults[] = {
    {"passenger", 5.0, 1.8, 4.5},   {"truck", 7.1, 2.4, 4.0},      {"trailer", 16.5, 2.55, 4.0},
    {"delivery", 6.5, 2.16, 4.5},   {"bus", 12.0, 2.5, 4.0},       {"coach", 14.0, 2.6, 4.0},
    {"motorcycle", 2.2, 0.9, 10.0}, {"moped", 2.1, 0.78, 7.0},     {"bicycle", 1.6, 0.65, 3.0},
    {"emergency", 6.5, 2.16, 4.5},  {"pedestrian", 0.215, 0.478, 2.0}, {"tram", 22.0, 2.4, 3.0},
    {"rail", 135.0, 2.84, 1.3},
};

SumoClassDefaults sumoClassDefaults(std::string_view vClass) {
  for (const SumoClassDefaults& d : kSumoClassDefaults)
    if (d.vClass == vClass) return d;
  return kSumoClassDefaults[0];
}

}  // namespace

VehicleTypeInfo toVehicleTypeInfo(const SumoTypeRecord& type) {
  VehicleTypeInfo t;
  const std::string_view vClass = type.vClass.empty() ? std::string_view("passenger") : std::string_view(type.vClass);
  t.vehicleClass = vehicleClassFromName(vClass);
  const SumoClassDefaults d = sumoClassDefaults(vClass);
  t.length = type.length.value_or(d.length);
  t.width = type.width.value_or(d.width);
  t.decel = type.decel.value_or(d.decel);
  t.mass = type.mass.value_or(classDefaults(t.vehicleClass).mass);
  return t;
}

VehicleTypeInfo defaultPersonType() {
  SumoTypeRecord r;
  r.vClass = "pedestrian";
  return toVehicleTypeInfo(r);
}

VehicleTypeInfo guessVehicleType(const std::string& typeName) {
  std::string name = typeName;
  for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  auto has = [&](std::string_view needle) { return name.find(needle) != std::string::npos; };
  VehicleClass c = VehicleClass::Passenger;
  if (has("truck") || has("trailer") || has("lorry") || has("hgv"))
    c = VehicleClass::Truck;
  else if (has("bus") || has("coach"))
    c = VehicleClass::Bus;
  else if (has("moto") || has("moped"))
    c = VehicleClass::Motorcycle;
  else if (has("emergency") || has("ambulance"))
    c = VehicleClass::Emergency;
  const ClassDefaults d = classDefaults(c);
  VehicleTypeInfo t;
  t.vehicleClass = c;
  t.length = d.length;
  t.width = d.width;
  t.mass = d.mass;
  return t;  // decel unknown
}

std::uint8_t toTurnSignals(int sumoSignals) {
  std::uint8_t s = kSignalNone;
  if (sumoSignals & kSumoBlinkerLeft) s |= kSignalLeft;
  if (sumoSignals & kSumoBlinkerRight) s |= kSignalRight;
  return s;
}

double stopDistanceOf(const SumoVehicleRecord& v, double decel) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double d = std::max(0.0, v.nextSignalDistance);
  const double brake = decel > 0.0 ? decel : 4.5;
  switch (v.nextSignal) {
    case 'r':
    case 'u':
    case 's':
      // unless it cannot stop even at an emergency's braking (twice its decel, SUMO's default
      // emergencyDecel): then it runs the light, as SUMO's drivers past that point do
      return v.speed * v.speed <= 4.0 * brake * d ? d : kInf;
    case 'y':
      return v.speed * v.speed <= 2.0 * brake * d ? d : kInf;  // it can stop: it does
    default:
      return kInf;
  }
}

void toVehicleState(const SumoVehicleRecord& v, const VehicleTypeInfo& type, VehicleState& s) {
  s.vehicleClass = type.vehicleClass;
  s.length = type.length;
  s.width = type.width;
  s.mass = type.mass;
  s.decel = type.decel;
  s.heading = headingFromNavigationDegrees(v.angle);
  s.position = centreFromFrontBumper(Vec2(v.x, v.y), s.heading, s.length);
  s.speed = v.lateralSpeed == 0.0 ? v.speed : std::copysign(std::hypot(v.speed, v.lateralSpeed), v.speed);
  s.lateralSpeed = 0.0;
  s.acceleration = v.acceleration;
  s.signals = toTurnSignals(v.signals);
  s.stopDistance = stopDistanceOf(v, type.decel);
}

std::string junctionOfLane(const std::string& laneId) {
  if (laneId.size() < 2 || laneId[0] != ':') return "";
  const std::size_t index = laneId.rfind('_');
  if (index == std::string::npos || index < 2) return "";
  const std::size_t link = laneId.rfind('_', index - 1);
  if (link == std::string::npos || link < 2) return "";
  return laneId.substr(1, link - 1);
}

}  // namespace st::highway
