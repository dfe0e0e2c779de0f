// stsim._stsim: the highway model (models/highway) for Python, a thin layer. Vehicle states come
// in as a list of dicts (one per vehicle) or a dict of columns (NumPy arrays or sequences), in our
// conventions (centre, heading in rad from +x) or SUMO's (front bumper, navigational degrees:
// converted as st::cosim::toVehicleState does, with the same sthighway/vehicle.hpp functions).
// Every bad input is a Python exception naming the vehicle and key; nothing is clamped or guessed.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <sthighway/monitor.hpp>
#include <sthighway/settings.hpp>
#include <sthighway/sumo_files.hpp>
#include <stsim/version.hpp>

namespace py = pybind11;
namespace hw = st::highway;

namespace {

// ---- checked conversions of Python values -------------------------------------------------

std::string typeName(py::handle h) { return py::str(py::type::handle_of(h).attr("__name__")); }

// A real number: int or float (NumPy scalars too), not bool, not str.
double toDouble(py::handle h, const std::string& what) {
  if (PyBool_Check(h.ptr()) || PyUnicode_Check(h.ptr()) || PyBytes_Check(h.ptr()) || !PyNumber_Check(h.ptr()) ||
      PyComplex_Check(h.ptr()))
    throw py::type_error(what + " must be a number, got " + typeName(h));
  const double x = PyFloat_AsDouble(h.ptr());
  if (x == -1.0 && PyErr_Occurred()) throw py::error_already_set();
  return x;
}

double toFinite(py::handle h, const std::string& what) {
  const double x = toDouble(h, what);
  if (!std::isfinite(x)) throw py::value_error(what + " must be finite, got " + std::to_string(x));
  return x;
}

long toInt(py::handle h, const std::string& what) {
  if (PyBool_Check(h.ptr()) || !PyIndex_Check(h.ptr())) throw py::type_error(what + " must be an integer, got " + typeName(h));
  return py::cast<long>(py::reinterpret_borrow<py::object>(h));
}

bool toBool(py::handle h, const std::string& what) {
  if (PyBool_Check(h.ptr())) return h.ptr() == Py_True;
  if (py::isinstance(h, py::module_::import("numpy").attr("bool_"))) return py::cast<bool>(h);
  if (PyIndex_Check(h.ptr()) && !PyFloat_Check(h.ptr())) {
    const long v = toInt(h, what);
    if (v == 0 || v == 1) return v == 1;
  }
  throw py::type_error(what + " must be a bool, got " + typeName(h));
}

std::string toStr(py::handle h, const std::string& what) {
  if (!PyUnicode_Check(h.ptr()) && !py::isinstance(h, py::module_::import("numpy").attr("str_")))
    throw py::type_error(what + " must be a str, got " + typeName(h));
  return py::cast<std::string>(h);
}

// ---- vehicle states -----------------------------------------------------------------------

// The keys a vehicle may have; which ones depend on the convention.
enum Key { kId, kX, kY, kHeading, kAngle, kSpeed, kLateralSpeed, kAcceleration, kLength, kWidth, kMass, kClass,
           kSignals, kEquipped, kLane, kRoute, kKeyCount };
const char* const kKeyNames[kKeyCount] = {"id", "x", "y", "heading", "angle", "speed", "lateral_speed", "acceleration",
                                          "length", "width", "mass", "vehicle_class", "signals", "equipped", "lane", "route"};

enum class Convention { Ours, Sumo };

std::string knownKeys(Convention c) {
  std::string s;
  for (int k = 0; k < kKeyCount; ++k) {
    if ((c == Convention::Ours && k == kAngle) || (c == Convention::Sumo && k == kHeading)) continue;
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
      return k;
    }
  throw py::value_error(where + ": unknown key '" + name + "' (known: " + knownKeys(c) + ")");
}

hw::VehicleClass classOf(const std::string& name, Convention c, const std::string& what) {
  if (c == Convention::Sumo) return hw::vehicleClassFromName(name);  // as the SUMO coupling does
  for (int k = 0; k < hw::kVehicleClassCount; ++k)
    if (name == hw::toString(static_cast<hw::VehicleClass>(k))) return static_cast<hw::VehicleClass>(k);
  throw py::value_error(what + " must be passenger, truck, bus, motorcycle, emergency or other, got '" + name + "'");
}

// One vehicle's values as given, before the convention is applied.
struct Raw {
  std::string id;
  double v[kKeyCount] = {};
  bool has[kKeyCount] = {};
  hw::VehicleClass vehicleClass = hw::VehicleClass::Passenger;
  long signals = 0;
  bool equipped = true;
  std::string lane;  // the lane id (reported in the warnings' lane column); empty: unknown
  std::vector<std::string> route;  // edge ids from the current edge on (SUMO: route[routeIndex:])
};

void setValue(Raw& r, int key, py::handle value, Convention c, const std::string& where) {
  const std::string what = where + ": '" + kKeyNames[key] + "'";
  r.has[key] = true;
  switch (key) {
    case kId: r.id = toStr(value, what); break;
    case kClass: r.vehicleClass = classOf(toStr(value, what), c, what); break;
    case kSignals:
      r.signals = toInt(value, what);
      if (r.signals < 0) throw py::value_error(what + " must be >= 0");
      break;
    case kEquipped: r.equipped = toBool(value, what); break;
    case kLane: r.lane = value.is_none() ? std::string() : toStr(value, what); break;
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

// A lane id's index into the monitor's RoadGeometry::lanes (VehicleState::lane), and an edge id's
// into edgeIds(road) (VehicleState::route).
using LaneIndex = std::unordered_map<std::string, int>;
using EdgeIndex = std::unordered_map<std::string, int>;

// The state in our conventions. SUMO's: as st::cosim::toVehicleState (cosim/lib/src/conversions.cpp).
void toState(const Raw& r, Convention c, std::size_t i, const LaneIndex& lanes, const EdgeIndex& edges,
             hw::VehicleState& s) {
  const std::string where = vehicleWhere(i, r);
  const int needed[] = {kId, kX, kY, c == Convention::Ours ? kHeading : kAngle, kSpeed};
  for (int k : needed)
    if (!r.has[k]) throw py::value_error(where + ": missing '" + kKeyNames[k] + "'");
  const hw::ClassDefaults d = hw::classDefaults(r.vehicleClass);
  s = hw::VehicleState{};  // every field this layer does not set keeps the model's default
  s.id = r.id;
  s.vehicleClass = r.vehicleClass;
  s.length = r.has[kLength] ? r.v[kLength] : d.length;
  s.width = r.has[kWidth] ? r.v[kWidth] : d.width;
  s.mass = r.has[kMass] ? r.v[kMass] : d.mass;
  s.acceleration = r.has[kAcceleration] ? r.v[kAcceleration] : 0.0;
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
  if (c == Convention::Ours) {
    s.position = st::Vec2(r.v[kX], r.v[kY]);
    s.heading = r.v[kHeading];
    s.speed = r.v[kSpeed];
    s.lateralSpeed = lateral;
    if (r.signals > (hw::kSignalLeft | hw::kSignalRight))
      throw py::value_error(where + ": 'signals' must be 0..3 (1 left, 2 right), got " + std::to_string(r.signals));
    s.signals = static_cast<std::uint8_t>(r.signals);
  } else {
    s.heading = hw::headingFromNavigationDegrees(r.v[kAngle]);
    s.position = hw::centreFromFrontBumper(st::Vec2(r.v[kX], r.v[kY]), s.heading, s.length);
    const double speed = r.v[kSpeed];
    s.speed = lateral == 0.0 ? speed : std::copysign(std::hypot(speed, lateral), speed);
    s.lateralSpeed = 0.0;
    s.signals = 0;  // SUMO's bit 1 is the left blinker, bit 0 the right
    if (r.signals & 2) s.signals |= hw::kSignalLeft;
    if (r.signals & 1) s.signals |= hw::kSignalRight;
  }
}

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
      const bool numeric = k != kId && k != kClass && k != kSignals && k != kEquipped && k != kLane && k != kRoute;
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
  d["vehicle_class"] = hw::toString(s.vehicleClass);
  d["signals"] = static_cast<int>(s.signals);
  d["equipped"] = s.equipped;
  if (road) d["lane"] = s.lane >= 0 ? py::object(py::str(road->lanes.at(static_cast<std::size_t>(s.lane)).id)) : py::none();
  return d;
}

// ---- settings -----------------------------------------------------------------------------

// Every key of sthighway/settings.hpp, by its YAML name ("safe_time.vehicle_reaction"), its flat
// spelling (safe_time_vehicle_reaction=1.0) or nested dicts (safe_time={"vehicle_reaction": 1.0}).
// The table's type decides what a value must be (TypeError); the table checks it (ValueError),
// in the words every front end uses.
void setFromPython(hw::MonitorConfig& cfg, const hw::Setting& s, py::handle value) {
  const std::string what = std::string("setting '") + s.key + "'";
  hw::SettingValue v;
  switch (s.type) {
    case hw::SettingType::Number:
    case hw::SettingType::Integer:
      v = toDouble(value, what);  // an int or a float (a whole number for an Integer: the table checks)
      break;
    case hw::SettingType::Boolean: v = toBool(value, what); break;
    case hw::SettingType::Choice: v = toStr(value, what); break;
  }
  try {
    hw::applySetting(cfg, s, v);
  } catch (const hw::SettingError& e) {
    throw py::value_error("setting '" + e.key() + "' " + e.problem());
  }
}

void setNested(hw::MonitorConfig& cfg, const std::string& name, py::handle value) {
  if (const hw::Setting* s = hw::findSetting(name)) return setFromPython(cfg, *s, value);
  bool section = false;
  for (const hw::Setting& s : hw::monitorSettings()) section = section || std::string(s.key).rfind(name + ".", 0) == 0;
  if (section && py::isinstance<py::dict>(value)) {
    for (auto [k, v] : py::reinterpret_borrow<py::dict>(value)) setNested(cfg, name + "." + toStr(k, "a key of setting '" + name + "'"), v);
    return;
  }
  if (section) {
    std::string msg = "setting '";
    msg.append(name).append("' must be a dict of its keys, got ").append(typeName(value));
    throw py::type_error(msg);
  }
  std::string msg = "Monitor() got an unknown setting '";
  msg.append(name).append("' (known:");
  for (const hw::Setting& s : hw::monitorSettings()) msg.append(" ").append(s.key);
  msg.append("; in a keyword '.' is written '_')");
  throw py::type_error(msg);
}

hw::MonitorConfig configOf(const py::kwargs& kw) {
  hw::MonitorConfig cfg;
  for (auto [name, value] : kw) setNested(cfg, py::cast<std::string>(name), value);
  try {
    hw::checkSettings(cfg);
  } catch (const hw::SettingError& e) {
    throw py::value_error("setting '" + e.key() + "' " + e.problem());
  }
  return cfg;
}

// ---- the monitor --------------------------------------------------------------------------

struct PyAlert {
  int vehicle = -1;
  std::string ego;
  hw::WarningKind kind = hw::WarningKind::Vehicle;
  hw::Zone zone = hw::Zone::Body;
  double ttc = 0.0, safeTime = 0.0;
  int foe = -1;
  std::string foeId;
};

class Monitor {
 public:
  Monitor(const hw::RoadGeometry& road, const hw::MonitorConfig& cfg) : monitor_(road, cfg), hindsight_(cfg.hindsight) {
    for (std::size_t i = 0; i < road.lanes.size(); ++i) lanes_.emplace(road.lanes[i].id, static_cast<int>(i));
    const std::vector<std::string> edges = hw::edgeIds(road);
    for (std::size_t e = 0; e < edges.size(); ++e) edges_.emplace(edges[e], static_cast<int>(e));
  }

  void step(double t, py::handle vehicles, Convention c) {
    if (!std::isfinite(t)) throw py::value_error("step time must be finite, got " + std::to_string(t));
    readStates(vehicles, c, lanes_, edges_, states_);
    {
      py::gil_scoped_release free;
      monitor_.step(t, states_);
    }
  }
  void finish(double t) { monitor_.finish(t); }
  // every setting in effect, by its key (sthighway/settings.hpp)
  py::dict settings() const {
    py::dict out;
    for (const hw::Setting& s : hw::monitorSettings()) {
      const hw::SettingValue v = s.get(monitor_.config());
      if (const double* x = std::get_if<double>(&v)) {
        if (s.type == hw::SettingType::Integer) out[s.key] = static_cast<long>(*x);
        else out[s.key] = *x;
      } else if (const bool* b = std::get_if<bool>(&v)) {
        out[s.key] = *b;
      } else {
        out[s.key] = std::get<std::string>(v);
      }
    }
    return out;
  }
  std::vector<hw::Warning> takeFinished() { return monitor_.takeFinished(); }
  std::vector<hw::HindsightEvent> takeEvents() {
    std::vector<hw::HindsightEvent> out;
    monitor_.takeEvents(out);
    return out;
  }
  std::vector<hw::Warning> openWarnings() const { return monitor_.openWarnings(); }
  std::vector<PyAlert> alerts() const {
    std::vector<PyAlert> out;
    for (const hw::Alert& a : monitor_.alerts()) {
      PyAlert p{a.vehicle, states_.at(static_cast<std::size_t>(a.vehicle)).id, a.kind, a.zone, a.ttc, a.safeTime, a.foe, {}};
      if (a.foe >= 0) p.foeId = states_.at(static_cast<std::size_t>(a.foe)).id;
      out.push_back(std::move(p));
    }
    return out;
  }
  py::dict counters() const {
    const hw::MonitorCounters& c = monitor_.counters();
    py::dict d;
    d["ticks"] = c.ticks;
    d["vehicle_updates"] = c.vehicleUpdates;
    d["vehicles_seen"] = c.vehiclesSeen;
    d["vehicle_meters"] = c.vehicleMeters;
    d["handoffs"] = c.handoffs;
    d["subdivisions"] = c.subdivisions;
    d["reunions"] = c.reunions;
    d["candidate_pairs"] = c.candidatePairs;
    d["toi_checks"] = c.toiChecks;
    d["feature_checks"] = c.featureChecks;
    d["warnings_begun"] = c.warningsBegun;
    d["road_predicted_updates"] = c.roadPredicted;  // vehicle updates predicted along a lane
    d["route_predicted_updates"] = c.routePredicted;  // of them, along the route the source gave
    d["straight_fallback_updates"] = c.straightFallbacks;  // ... on no fitting lane: straight
    py::dict byKind, tet, tit, byZone;
    for (int k = 0; k < hw::kWarningKindCount; ++k) {
      const char* name = hw::toString(static_cast<hw::WarningKind>(k));
      byKind[name] = c.warningsByKind[static_cast<std::size_t>(k)];
      tet[name] = c.tet[static_cast<std::size_t>(k)];
      tit[name] = c.tit[static_cast<std::size_t>(k)];
    }
    for (int z = 0; z < hw::kZoneCount; ++z) byZone[hw::toString(static_cast<hw::Zone>(z))] = c.warningsByZone[static_cast<std::size_t>(z)];
    py::dict byType;
    for (int k = 0; k < hw::kConflictTypeCount; ++k)
      byType[hw::toString(static_cast<hw::ConflictType>(k))] = c.warningsByType[static_cast<std::size_t>(k)];
    d["warnings_by_kind"] = byKind;
    d["warnings_by_zone"] = byZone;
    d["warnings_by_type"] = byType;
    d["tet_s"] = tet;
    d["tit_s2"] = tit;
    d["hindsight"] = hindsightCounters(c);
    return d;
  }
  // summary.json's "hindsight" as counters: None with hindsight off; a share of nothing is None
  py::object hindsightCounters(const hw::MonitorCounters& c) const {
    if (!hindsight_.enabled) return py::none();
    auto share = [](std::uint64_t part, std::uint64_t whole) {
      return whole ? py::object(py::float_(static_cast<double>(part) / static_cast<double>(whole))) : py::object(py::none());
    };
    py::dict h, byKind, nearMisses;
    h["clearance_m"] = hindsight_.clearance;
    h["evasive_deceleration"] = hindsight_.evasiveDeceleration;
    h["lead_s"] = hindsight_.lead;
    for (int k = 0; k < hw::kWarningKindCount; ++k) {
      const auto i = static_cast<std::size_t>(k);
      py::dict one;
      one["judged"] = c.judged[i];
      one["confirmed"] = c.confirmed[i];
      one["precision"] = share(c.confirmed[i], c.judged[i]);
      byKind[hw::toString(static_cast<hw::WarningKind>(k))] = one;
    }
    nearMisses["events"] = c.nearMisses;
    nearMisses["warned"] = c.nearMissesWarned;
    nearMisses["recall"] = share(c.nearMissesWarned, c.nearMisses);
    nearMisses["lead_times_s"] = c.nearMissLeads;  // each warned near miss's lead, in order found
    h["by_kind"] = byKind;
    h["near_misses"] = nearMisses;
    return h;
  }
  double lastTime() const { return monitor_.lastTime(); }
  std::size_t featureCount() const { return monitor_.features().features.size(); }
  int cellCount() const { return monitor_.cells().cellCount(); }

 private:
  hw::HighwayMonitor monitor_;
  hw::HindsightConfig hindsight_;
  LaneIndex lanes_;                       // lane id -> index into the road's lanes
  EdgeIndex edges_;                       // edge id -> index into edgeIds(road)
  std::vector<hw::VehicleState> states_;  // the last step's, for the alerts' ids
};

hw::RoadGeometry roadOf(py::handle net) {
  if (net.is_none()) return {};
  if (!PyUnicode_Check(net.ptr()) && !py::isinstance(net, py::module_::import("os").attr("PathLike")))
    throw py::type_error("net must be a path to a .net.xml or None, got " + typeName(net));
  const std::string path = py::str(py::module_::import("os").attr("fspath")(net));
  return hw::readSumoNet(path);
}

// Lanes given by the caller (e.g. read through TraCI): dicts with id, edge, index, shape, width.
hw::RoadGeometry roadOfLanes(py::handle lanes) {
  hw::RoadGeometry road;
  if (!py::isinstance<py::sequence>(lanes)) throw py::type_error("lanes must be a list of dicts, got " + typeName(lanes));
  std::size_t i = 0;
  for (py::handle item : lanes) {
    const std::string where = "lane " + std::to_string(i++);
    if (!py::isinstance<py::dict>(item)) throw py::type_error(where + " must be a dict, got " + typeName(item));
    const auto d = py::reinterpret_borrow<py::dict>(item);
    hw::Lane l;
    for (auto [k, v] : d) {
      const std::string key = py::isinstance<py::str>(k) ? py::cast<std::string>(k) : std::string(py::repr(k));
      const std::string what = where + ": '" + key + "'";
      if (key == "id") l.id = toStr(v, what);
      else if (key == "edge") l.edge = toStr(v, what);
      else if (key == "index") l.index = static_cast<int>(toInt(v, what));
      else if (key == "width") l.width = toFinite(v, what);
      else if (key == "internal") l.internal = toBool(v, what);
      else if (key == "length") {
        l.length = toFinite(v, what);
        if (l.length < 0.0) throw py::value_error(what + ": must not be negative");
      }
      else if (key == "shape") {
        for (py::handle p : v) {
          const auto xy = py::reinterpret_borrow<py::sequence>(p);
          if (py::len(xy) != 2) throw py::value_error(what + ": points must be (x, y)");
          l.shape.emplace_back(toFinite(xy[0], what), toFinite(xy[1], what));
        }
      } else throw py::value_error(what + ": unknown key (known: id, edge, index, shape, width, internal, length)");
    }
    road.lanes.push_back(std::move(l));
  }
  return road;
}

// ---- a warning's hindsight and conflict fields, as warnings.csv writes them -----------------
// (models/highway/src/report.cpp, warningCsvRow): None where its cell is empty

py::object judgedNumber(const hw::Warning& w, double x) {
  return w.verdict != hw::Verdict::Unjudged && std::isfinite(x) ? py::object(py::float_(x)) : py::object(py::none());
}
py::object vehicleJudged(const hw::Warning& w, double x) {
  return w.kind == hw::WarningKind::Vehicle ? judgedNumber(w, x) : py::object(py::none());
}
py::object roadJudged(const hw::Warning& w, bool b) {
  return w.verdict != hw::Verdict::Unjudged && w.kind != hw::WarningKind::Vehicle ? py::object(py::bool_(b))
                                                                                 : py::object(py::none());
}
// a conflict column: NaN (does not apply) is None; an infinite DRAC stays inf
py::object conflictNumber(double x) { return std::isnan(x) ? py::object(py::none()) : py::object(py::float_(x)); }

class Fcd {
 public:
  // with a net, each vehicle's lane attribute is read against it (as `stsim highway --fcd --net`)
  Fcd(const std::string& path, py::handle vtypes, py::handle net)
      : road_(net.is_none() ? std::nullopt : std::optional<hw::RoadGeometry>(roadOf(net))),
        reader_(path, typesOf(vtypes), {}, road_ ? &*road_ : nullptr) {}
  py::object next() {
    hw::FcdFrame frame;
    bool more = false;
    {
      py::gil_scoped_release free;
      more = reader_.next(frame);
    }
    if (!more) throw py::stop_iteration();
    py::list vs;
    for (const auto& v : frame.vehicles) vs.append(stateDict(v, road_ ? &*road_ : nullptr));
    return py::make_tuple(frame.time, vs);
  }

 private:
  static hw::VehicleTypes typesOf(py::handle vtypes) {
    if (vtypes.is_none()) return {};
    return hw::readSumoVehicleTypes(toStr(py::str(py::module_::import("os").attr("fspath")(vtypes)), "vtypes"));
  }
  std::optional<hw::RoadGeometry> road_;  // before reader_, which keeps a pointer to it
  hw::FcdReader reader_;
};

}  // namespace

PYBIND11_MODULE(_stsim, m) {
  m.doc() = "stsim's smart-car collision warnings (the SUMO-free highway model)";
  m.attr("__version__") = STSIM_VERSION_STRING;
  py::register_exception<hw::InputError>(m, "InputError", PyExc_ValueError);

  py::class_<hw::HindsightEvent>(m, "HindsightEvent",
                                 "A near miss or an unsignalled line crossing that happened, and whether it was warned\n"
                                 "(what events.csv has: models/highway/README.md, Hindsight).")
      .def_property_readonly("kind", [](const hw::HindsightEvent& e) { return hw::toString(e.kind); }, "near_miss or crossing")
      .def_readonly("time", &hw::HindsightEvent::time)
      .def_readonly("ego", &hw::HindsightEvent::ego)
      .def_readonly("foe", &hw::HindsightEvent::foe, "near miss: the other vehicle; crossing: the line")
      .def_readonly("x", &hw::HindsightEvent::x)
      .def_readonly("y", &hw::HindsightEvent::y)
      .def_readonly("lane", &hw::HindsightEvent::lane)
      .def_readonly("speed", &hw::HindsightEvent::speed)
      .def_property_readonly("gap", [](const hw::HindsightEvent& e) { return conflictNumber(e.gap); }, "m, near miss: body to body")
      .def_property_readonly("lateral_speed", [](const hw::HindsightEvent& e) { return conflictNumber(e.lateralSpeed); },
                             "m/s, crossing: towards the line")
      .def_readonly("warned", &hw::HindsightEvent::warned, "a warning about it was open the lead time before")
      .def_property_readonly("lead", [](const hw::HindsightEvent& e) { return conflictNumber(e.lead); },
                             "s since the earliest warning about it began; None: not warned");

  py::class_<hw::Warning>(m, "WarningEpisode", "One warning episode: (ego, foe, kind) from its first tick to its end.")
      .def_readonly("ego", &hw::Warning::ego)
      .def_readonly("foe", &hw::Warning::foe)
      .def_property_readonly("kind", [](const hw::Warning& w) { return hw::toString(w.kind); })
      .def_property_readonly("zone", [](const hw::Warning& w) { return hw::toString(w.zone); })
      .def_readonly("begin", &hw::Warning::begin)
      .def_readonly("end", &hw::Warning::end)
      .def_readonly("min_ttc", &hw::Warning::minTtc)
      .def_readonly("min_ttc_time", &hw::Warning::minTtcTime)
      .def_readonly("safe_time", &hw::Warning::safeTimeAtMin)
      .def_readonly("open", &hw::Warning::open)
      // hindsight and the conflict record: what warnings.csv has in these columns, None where its
      // cell is empty (the column does not apply to the kind, or the episode is not judged)
      .def_property_readonly("verdict", [](const hw::Warning& w) { return hw::toString(w.verdict); },
                             "confirmed, nuisance, or '' (not judged: open, or hindsight off)")
      .def_property_readonly("clearance", [](const hw::Warning& w) { return vehicleJudged(w, w.clearance); },
                             "m, vehicle: the smallest body-to-body distance in the window")
      .def_property_readonly("clearance_time", [](const hw::Warning& w) { return judgedNumber(w, w.clearanceTime); },
                             "s, when (road: when the body touched the line)")
      .def_property_readonly("deceleration", [](const hw::Warning& w) { return vehicleJudged(w, w.deceleration); },
                             "m/s^2, vehicle: the strongest braking of either vehicle in the window")
      .def_property_readonly("crossed", [](const hw::Warning& w) { return roadJudged(w, w.crossed); },
                             "road: the body touched the line within the safe time")
      .def_property_readonly("signalled", [](const hw::Warning& w) { return roadJudged(w, w.signalled); },
                             "road: with the turn signal of that side on")
      .def_property_readonly("x", [](const hw::Warning& w) { return conflictNumber(w.x); }, "m, the ego's centre at the minimum TTC")
      .def_property_readonly("y", [](const hw::Warning& w) { return conflictNumber(w.y); })
      .def_readonly("lane", &hw::Warning::lane, "the ego's lane id, '' if unknown")
      .def_property_readonly("ego_speed", [](const hw::Warning& w) { return conflictNumber(w.egoSpeed); }, "m/s")
      .def_property_readonly("foe_speed", [](const hw::Warning& w) { return conflictNumber(w.foeSpeed); }, "m/s; None for road warnings")
      .def_property_readonly("heading_angle", [](const hw::Warning& w) { return conflictNumber(w.headingAngle); },
                             "deg between the headings; road: to the line; None for a hazard")
      .def_property_readonly("type", [](const hw::Warning& w) { return hw::toString(w.type); },
                             "rear_end, lane_change, crossing (SSAM's angles) or road")
      .def_property_readonly("drac", [](const hw::Warning& w) { return conflictNumber(w.drac); },
                             "m/s^2, deceleration rate to avoid the crash (inf at TTC 0 while closing)")
      .def_property_readonly("max_delta_v", [](const hw::Warning& w) { return conflictNumber(w.maxDeltaV); },
                             "m/s, SSAM's MaxDeltaV; None for road warnings")
      .def_readonly("line", &hw::Warning::line, "road warnings: the curb, marker or hazard")
      .def_property_readonly("lateral_speed", [](const hw::Warning& w) { return conflictNumber(w.lateralSpeed); },
                             "m/s, road warnings: the ego's speed towards the line; None for vehicles")
      .def("__repr__", [](const hw::Warning& w) {
        return "<WarningEpisode " + w.ego + " -> " + w.foe + " " + hw::toString(w.kind) + " " + hw::toString(w.zone) + " [" +
               std::to_string(w.begin) + ", " + std::to_string(w.end) + "] min_ttc " + std::to_string(w.minTtc) + ">";
      });

  py::class_<PyAlert>(m, "Alert", "An equipped car's worst current threat at the last step.")
      .def_readonly("vehicle", &PyAlert::vehicle, "index into the last step's vehicles")
      .def_readonly("ego", &PyAlert::ego)
      .def_property_readonly("kind", [](const PyAlert& a) { return hw::toString(a.kind); })
      .def_property_readonly("zone", [](const PyAlert& a) { return hw::toString(a.zone); })
      .def_readonly("ttc", &PyAlert::ttc)
      .def_readonly("safe_time", &PyAlert::safeTime)
      .def_readonly("foe", &PyAlert::foe, "the other vehicle's index (vehicle warnings), else -1")
      .def_readonly("foe_id", &PyAlert::foeId)
      .def("__repr__", [](const PyAlert& a) {
        return "<Alert " + a.ego + " " + hw::toString(a.kind) + (a.foeId.empty() ? "" : " " + a.foeId) + " ttc " +
               std::to_string(a.ttc) + " safe " + std::to_string(a.safeTime) + ">";
      });

  py::class_<Monitor>(m, "Monitor",
                      "Monitor(net=None, *, lanes=None, **settings): smart-car warnings, one step() per tick.\n"
                      "net: a SUMO .net.xml (lane shapes and widths) or None (no road: car-car only);\n"
                      "lanes: the same as a list of dicts {id, edge, index, shape, width, internal, length}.\n"
                      "settings: detector (concentric|five|box), layout (a|b), motion (velocity|acceleration),\n"
                      "prediction (road|straight: along the lanes, the default, or the report's straight line),\n"
                      "broadphase (cells|all-pairs), check_road, vehicle_reaction_time, road_reaction_time,\n"
                      "brake_force {class: N}, concentric_inner_margin, concentric_outer_margin, body_circles,\n"
                      "cell_length, tx_power_dbm, path_loss_exponent, reference_distance, hysteresis_db,\n"
                      "radio_range, fat_margin, fat_lookahead, decomposition_factor, max_depth;\n"
                      "hindsight (bool), clearance (m), evasive_deceleration (m/s^2), hindsight_lead (s);\n"
                      "rear_end_below, crossing_above (deg, the conflict types' angles).")
      .def(py::init([](py::object net, py::object lanes, py::kwargs kw) {
             if (!net.is_none() && !lanes.is_none()) throw py::value_error("give net or lanes, not both");
             const hw::RoadGeometry road = lanes.is_none() ? roadOf(net) : roadOfLanes(lanes);
             return std::make_unique<Monitor>(road, configOf(kw));
           }),
           py::arg("net") = py::none(), py::kw_only(), py::arg("lanes") = py::none())
      .def("step", [](Monitor& self, double t, py::handle v) { self.step(t, v, Convention::Ours); }, py::arg("t"),
           py::arg("vehicles"),
           "Every vehicle's state at time t (s, increasing): a list of dicts or a dict of columns with keys\n"
           "id, x, y (centre, m), heading (rad from +x), speed (m/s); optional lateral_speed, acceleration,\n"
           "length, width, mass (default: the class's), vehicle_class, signals (1 left, 2 right), equipped,\n"
           "lane (its lane id in the net: reported in the warnings' lane column; None: unknown).\n"
           "Vehicles absent have left.")
      .def("step_sumo", [](Monitor& self, double t, py::handle v) { self.step(t, v, Convention::Sumo); }, py::arg("t"),
           py::arg("vehicles"),
           "As step(), in SUMO's conventions: x, y of the front bumper, angle in navigational degrees,\n"
           "signals as SUMO's bits (1 right, 2 left), vehicle_class a SUMO vClass.")
      .def("finish", &Monitor::finish, py::arg("t"), "Closes every open episode at time t.")
      .def_property_readonly("settings", &Monitor::settings,
                             "Every setting in effect, by its scenario key (stsim highway --settings lists them).")
      .def("take_finished", &Monitor::takeFinished, "Episodes that ended since the last call, in order of ending.")
      .def("take_events", &Monitor::takeEvents,
           "Near misses and unsignalled crossings hindsight found since the last call (HindsightEvent).")
      .def("open_warnings", &Monitor::openWarnings)
      .def("alerts", &Monitor::alerts)
      .def_property_readonly("counters", &Monitor::counters)
      .def_property_readonly("last_time", &Monitor::lastTime)
      .def_property_readonly("feature_count", &Monitor::featureCount, "curbs, lane markers and hazards")
      .def_property_readonly("cell_count", &Monitor::cellCount);

  py::class_<Fcd>(m, "FcdReader",
                  "FcdReader(path, vtypes=None, net=None): iterates a SUMO FCD trace as (time, [vehicle dict]) in\n"
                  "our conventions (what Monitor.step takes), read as `stsim highway --fcd` reads it; with the\n"
                  "network (a .net.xml), each vehicle's 'lane' (its lane id, None for a lane the network lacks).")
      .def(py::init([](py::object path, py::object vtypes, py::object net) {
             return std::make_unique<Fcd>(toStr(py::str(py::module_::import("os").attr("fspath")(path)), "path"), vtypes, net);
           }),
           py::arg("path"), py::arg("vtypes") = py::none(), py::arg("net") = py::none())
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__", &Fcd::next);
}
