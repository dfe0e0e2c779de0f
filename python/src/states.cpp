#include "states.hpp"

#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>
#include <limits>
#include <stdexcept>

#include <sthighway/sumo_conversion.hpp>

#include "values.hpp"

namespace stpy {

namespace {

// The keys a vehicle may have; which ones depend on the convention.
enum Key { kId, kX, kY, kHeading, kAngle, kSpeed, kLateralSpeed, kAcceleration, kLength, kWidth, kMass, kDecel, kClass,
           kSignals, kEquipped, kLane, kRoute, kNextSignal, kNextSignalDistance, kStopDistance, kKeyCount };
const char* const kKeyNames[kKeyCount] = {"id", "x", "y", "heading", "angle", "speed", "lateral_speed", "acceleration",
                                          "length", "width", "mass", "decel", "vehicle_class", "signals", "equipped", "lane", "route",
                                          "next_signal", "next_signal_distance", "stop_distance"};
// SUMO's link states (TraCI's getNextTLS, getRedYellowGreenState)
constexpr std::string_view kLinkStates = "rRyYgGsuoOmM=w";


std::string knownKeys(Convention c) {
  std::string s;
  for (int k = 0; k < kKeyCount; ++k) {
    if ((c == Convention::Ours && (k == kAngle || k == kNextSignal || k == kNextSignalDistance)) ||
        (c == Convention::Sumo && (k == kHeading || k == kStopDistance)))
      continue;
    s += (s.empty() ? "" : ", ") + std::string(kKeyNames[k]);
  }
  return s;
}

int keyOf(const std::string& name, Convention c, const std::string& where) {
  for (int k = 0; k < kKeyCount; ++k)
    if (name == kKeyNames[k]) {
      if (c == Convention::Ours && k == kAngle)
        throw py::value_error(where + ": unknown key 'angle' (SUMO's navigational angle: use step_sumo(), or 'heading' in rad)");
      if (c == Convention::Sumo && k == kHeading)
        throw py::value_error(where + ": unknown key 'heading' for step_sumo() (SUMO gives 'angle' in degrees)");
      if (c == Convention::Ours && (k == kNextSignal || k == kNextSignalDistance))
        throw py::value_error(where + ": unknown key '" + name + "' for step() (SUMO's next light: step_sumo(); ours: 'stop_distance')");
      if (c == Convention::Sumo && k == kStopDistance)
        throw py::value_error(where + ": unknown key 'stop_distance' for step_sumo() (give SUMO's 'next_signal' and 'next_signal_distance')");
      return k;
    }
  throw py::value_error(where + ": unknown key '" + name + "' (known: " + knownKeys(c) + ")");
}

hw::VehicleClass classOf(const std::string& name, Convention c, const std::string& what) {
  if (c == Convention::Sumo) return hw::vehicleClassFromName(name);  // as the SUMO coupling does
  for (int k = 0; k < hw::kVehicleClassCount; ++k)
    if (name == hw::toString(static_cast<hw::VehicleClass>(k))) return static_cast<hw::VehicleClass>(k);
  throw py::value_error(what + " must be passenger, truck, bus, motorcycle, emergency, other, bicycle or pedestrian, got '" + name + "'");
}

// One vehicle's values as given, before the convention is applied.
struct Raw {
  std::string id;
  double v[kKeyCount] = {};
  bool has[kKeyCount] = {};
  hw::VehicleClass vehicleClass = hw::VehicleClass::Passenger;
  std::string className;  // as given (SUMO's vClass for step_sumo)
  long signals = 0;
  bool equipped = true;
  std::string lane;  // the lane id (reported in the warnings' lane column); empty: unknown
  std::vector<std::string> route;  // edge ids from the current edge on (SUMO: route[routeIndex:])
  char nextSignal = 0;             // SUMO's link state of its next light, 0: none
  double stopDistance = std::numeric_limits<double>::infinity();
};

void setValue(Raw& r, int key, py::handle value, Convention c, const std::string& where) {
  const std::string what = where + ": '" + kKeyNames[key] + "'";
  r.has[key] = true;
  switch (key) {
    case kId: r.id = toStr(value, what); break;
    case kClass:
      r.className = toStr(value, what);
      r.vehicleClass = classOf(r.className, c, what);
      break;
    case kSignals:
      r.signals = toInt(value, what);
      if (r.signals < 0) throw py::value_error(what + " must be >= 0");
      break;
    case kEquipped: r.equipped = toBool(value, what); break;
    case kLane: r.lane = value.is_none() ? std::string() : toStr(value, what); break;
    case kNextSignal: {
      const std::string s = value.is_none() ? std::string() : toStr(value, what);
      if (s.size() > 1 || (s.size() == 1 && kLinkStates.find(s[0]) == std::string_view::npos))
        throw py::value_error(what + " must be one of SUMO's link states (" + std::string(kLinkStates) + ") or None, got '" + s + "'");
      r.nextSignal = s.empty() ? 0 : s[0];
      break;
    }
    case kStopDistance:
      if (!value.is_none()) {
        r.stopDistance = toFinite(value, what);
        if (r.stopDistance < 0.0) throw py::value_error(what + " must be >= 0 (None: nowhere)");
      }
      break;
    case kRoute:
      r.route.clear();
      if (value.is_none()) break;
      if (PyUnicode_Check(value.ptr()) || !py::isinstance<py::sequence>(value))
        throw py::type_error(what + " must be a list of edge ids, got " + typeName(value));
      for (py::handle e : value) r.route.push_back(toStr(e, what));
      break;
    default: r.v[key] = toFinite(value, what);
  }
}

std::string vehicleWhere(std::size_t i, const Raw& r) {
  return "vehicle " + std::to_string(i) + (r.has[kId] ? " ('" + r.id + "')" : "");
}

// The state in our conventions; SUMO's through the one conversion (sthighway/sumo_conversion.hpp).
void toState(const Raw& r, Convention c, std::size_t i, const LaneIndex& lanes, const EdgeIndex& edges,
             hw::VehicleState& s) {
  const std::string where = vehicleWhere(i, r);
  const int needed[] = {kId, kX, kY, c == Convention::Ours ? kHeading : kAngle, kSpeed};
  for (int k : needed)
    if (!r.has[k]) throw py::value_error(where + ": missing '" + kKeyNames[k] + "'");
  s = hw::VehicleState{};  // every field this layer does not set keeps the model's default
  s.id = r.id;
  s.equipped = r.equipped;
  if (!r.lane.empty()) {
    // as the FCD reader does: the lane's index in the road, -1 for a lane the road lacks
    const auto at = lanes.find(r.lane);
    s.lane = at == lanes.end() ? -1 : at->second;
  }
  // as the SUMO coupling does: up to kRouteAhead edges, ending at the first the road lacks
  for (std::size_t k = 0; k < r.route.size() && k < static_cast<std::size_t>(hw::kRouteAhead); ++k) {
    const auto at = edges.find(r.route[k]);
    if (at == edges.end()) break;
    s.route[k] = at->second;
  }
  const double lateral = r.has[kLateralSpeed] ? r.v[kLateralSpeed] : 0.0;
  if (c == Convention::Sumo) {
    // SUMO's records through the one conversion the live coupling and the FCD reader use
    hw::SumoTypeRecord type;
    type.vClass = r.className;
    if (r.has[kLength]) type.length = r.v[kLength];
    if (r.has[kWidth]) type.width = r.v[kWidth];
    if (r.has[kMass]) type.mass = r.v[kMass];
    if (r.has[kDecel]) type.decel = r.v[kDecel];
    hw::SumoVehicleRecord v;
    v.x = r.v[kX];
    v.y = r.v[kY];
    v.angle = r.v[kAngle];
    v.speed = r.v[kSpeed];
    v.lateralSpeed = lateral;
    v.acceleration = r.has[kAcceleration] ? r.v[kAcceleration] : 0.0;
    v.signals = static_cast<int>(r.signals);
    v.nextSignal = r.nextSignal;
    v.nextSignalDistance = r.has[kNextSignalDistance] ? r.v[kNextSignalDistance] : 0.0;
    if (r.nextSignal && !r.has[kNextSignalDistance])
      throw py::value_error(where + ": 'next_signal' needs 'next_signal_distance' (m to its stop line)");
    hw::toVehicleState(v, hw::toVehicleTypeInfo(type), s);
    return;
  }
  const hw::ClassDefaults d = hw::classDefaults(r.vehicleClass);
  s.vehicleClass = r.vehicleClass;
  s.length = r.has[kLength] ? r.v[kLength] : d.length;
  s.width = r.has[kWidth] ? r.v[kWidth] : d.width;
  s.mass = r.has[kMass] ? r.v[kMass] : d.mass;
  if (r.has[kDecel]) s.decel = r.v[kDecel];  // else unknown (hindsight.evasive_deceleration)
  s.acceleration = r.has[kAcceleration] ? r.v[kAcceleration] : 0.0;
  s.position = st::Vec2(r.v[kX], r.v[kY]);
  s.heading = r.v[kHeading];
  s.speed = r.v[kSpeed];
  s.lateralSpeed = lateral;
  if (r.signals > (hw::kSignalLeft | hw::kSignalRight))
    throw py::value_error(where + ": 'signals' must be 0..3 (1 left, 2 right), got " + std::to_string(r.signals));
  s.signals = static_cast<std::uint8_t>(r.signals);
  s.stopDistance = r.stopDistance;
}

}  // namespace

// A list of dicts, or a dict of equally long columns.
void readStates(py::handle vehicles, Convention c, const LaneIndex& lanes, const EdgeIndex& edges,
                std::vector<hw::VehicleState>& out) {
  std::vector<Raw> raws;
  if (py::isinstance<py::dict>(vehicles)) {
    const auto columns = py::reinterpret_borrow<py::dict>(vehicles);
    std::optional<std::size_t> n;
    std::vector<std::pair<int, py::object>> cols;
    for (auto [name, col] : columns) {
      const std::string key = py::isinstance<py::str>(name) ? py::cast<std::string>(name) : std::string(py::repr(name));
      const int k = keyOf(key, c, "column");
      if (PyUnicode_Check(col.ptr()) || !py::hasattr(col, "__len__"))
        throw py::type_error("column '" + key + "' must be a sequence or array, got " + typeName(col));
      const std::size_t len = py::len(col);
      if (n && *n != len)
        throw py::value_error("column '" + key + "' has " + std::to_string(len) + " values, the others " + std::to_string(*n));
      n = len;
      cols.emplace_back(k, py::reinterpret_borrow<py::object>(col));
    }
    raws.resize(n.value_or(0));
    // numbers through one NumPy conversion per column where it can (ids and names element-wise)
    for (auto& [k, col] : cols) {
      const bool numeric = k != kId && k != kClass && k != kSignals && k != kEquipped && k != kLane && k != kRoute &&
                           k != kNextSignal && k != kStopDistance;
      if (numeric && py::isinstance<py::array>(col) && py::cast<py::array>(col).dtype().kind() == 'f') {
        auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(col);
        if (!a || a.ndim() != 1)
          throw py::value_error(std::string("column '") + kKeyNames[k] + "' must be one-dimensional");
        const double* p = a.data();
        for (std::size_t i = 0; i < raws.size(); ++i) {
          if (!std::isfinite(p[i]))
            throw py::value_error("vehicle " + std::to_string(i) + ": '" + kKeyNames[k] + "' must be finite, got " +
                                  std::to_string(p[i]));
          raws[i].v[k] = p[i];
          raws[i].has[k] = true;
        }
        continue;
      }
      std::size_t i = 0;
      for (py::handle value : col) {
        if (i >= raws.size()) break;
        setValue(raws[i], k, value, c, "vehicle " + std::to_string(i));
        ++i;
      }
    }
  } else if (py::isinstance<py::sequence>(vehicles) && !PyUnicode_Check(vehicles.ptr())) {
    const auto rows = py::reinterpret_borrow<py::sequence>(vehicles);
    raws.resize(py::len(rows));
    for (std::size_t i = 0; i < raws.size(); ++i) {
      py::object row = rows[i];
      if (!py::isinstance<py::dict>(row))
        throw py::type_error("vehicle " + std::to_string(i) + " must be a dict, got " + typeName(row));
      const auto d = py::reinterpret_borrow<py::dict>(row);
      if (d.contains("id")) setValue(raws[i], kId, d["id"], c, "vehicle " + std::to_string(i));
      for (auto [name, value] : d) {
        const std::string where = vehicleWhere(i, raws[i]);
        if (!py::isinstance<py::str>(name)) throw py::type_error(where + ": keys must be str, got " + typeName(name));
        const int k = keyOf(py::cast<std::string>(name), c, where);
        if (k != kId) setValue(raws[i], k, value, c, where);
      }
    }
  } else {
    throw py::type_error("vehicles must be a list of dicts or a dict of columns, got " + typeName(vehicles));
  }
  out.resize(raws.size());
  for (std::size_t i = 0; i < raws.size(); ++i) toState(raws[i], c, i, lanes, edges, out[i]);
}

py::dict stateDict(const hw::VehicleState& s, const hw::RoadGeometry* road) {
  py::dict d;
  d["id"] = s.id;
  d["x"] = s.position.x();
  d["y"] = s.position.y();
  d["heading"] = s.heading;
  d["speed"] = s.speed;
  d["lateral_speed"] = s.lateralSpeed;
  d["acceleration"] = s.acceleration;
  d["length"] = s.length;
  d["width"] = s.width;
  d["mass"] = s.mass;
  if (!std::isnan(s.decel)) d["decel"] = s.decel;
  d["vehicle_class"] = hw::toString(s.vehicleClass);
  d["signals"] = static_cast<int>(s.signals);
  d["equipped"] = s.equipped;
  if (road) d["lane"] = s.lane >= 0 ? py::object(py::str(road->lanes.at(static_cast<std::size_t>(s.lane)).id)) : py::none();
  return d;
}

}  // namespace stpy
