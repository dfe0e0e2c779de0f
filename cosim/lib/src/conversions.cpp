#include <stcosim/conversions.hpp>


namespace st::cosim {

VehicleTypeInfo toVehicleTypeInfo(const SumoVehicleType& type) {
  highway::SumoTypeRecord r;
  r.vClass = type.vClass;
  r.length = type.length;
  r.width = type.width;
  r.mass = type.mass;
  if (type.decel > 0.0) r.decel = type.decel;
  return highway::toVehicleTypeInfo(r);
}

void toVehicleState(const SumoVehicle& v, const VehicleTypeInfo& type, highway::VehicleState& s) {
  s.id = v.id;
  s.handle = static_cast<int>(v.serial);  // dense, kept while the vehicle is on the road
  highway::toVehicleState(v, type, s);
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
