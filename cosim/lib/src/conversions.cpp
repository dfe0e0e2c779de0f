#include <stcosim/conversions.hpp>

#include <cmath>

namespace st::cosim {

VehicleTypeInfo toVehicleTypeInfo(const SumoVehicleType& type) {
  VehicleTypeInfo t;
  t.vehicleClass = highway::vehicleClassFromName(type.vClass);
  t.length = type.length;
  t.width = type.width;
  t.mass = type.mass ? *type.mass : highway::classDefaults(t.vehicleClass).mass;
  if (type.decel > 0.0) t.decel = type.decel;
  return t;
}

void toVehicleState(const SumoVehicle& v, const VehicleTypeInfo& type, highway::VehicleState& s) {
  s.id = v.id;
  s.handle = static_cast<int>(v.serial);  // dense, kept while the vehicle is on the road
  s.vehicleClass = type.vehicleClass;
  s.length = type.length;
  s.width = type.width;
  s.mass = type.mass;
  s.decel = type.decel;
  s.heading = highway::headingFromNavigationDegrees(v.angle);
  s.position = highway::centreFromFrontBumper(Vec2(v.x, v.y), s.heading, s.length);
  s.speed = v.lateralSpeed == 0.0 ? v.speed : std::copysign(std::hypot(v.speed, v.lateralSpeed), v.speed);
  s.lateralSpeed = 0.0;
  s.acceleration = v.acceleration;
  s.signals = 0;
  if (v.signals & kSumoBlinkerLeft) s.signals |= highway::kSignalLeft;
  if (v.signals & kSumoBlinkerRight) s.signals |= highway::kSignalRight;
}

highway::VehicleState toVehicleState(const SumoVehicle& v, const SumoVehicleType& type) {
  highway::VehicleState s;
  toVehicleState(v, toVehicleTypeInfo(type), s);
  return s;
}

highway::RoadGeometry toRoadGeometry(const std::vector<SumoLane>& lanes) {
  highway::RoadGeometry road;
  road.lanes.reserve(lanes.size());
  for (const auto& l : lanes) {
    highway::Lane h;
    h.id = l.id;
    h.edge = l.edge;
    h.index = l.index;
    h.width = l.width;
    h.length = l.length;
    h.internal = l.internal;
    for (const auto& [x, y] : l.shape) h.shape.emplace_back(x, y);
    road.lanes.push_back(std::move(h));
  }
  return road;
}

}  // namespace st::cosim
