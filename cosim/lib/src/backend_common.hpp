#pragma once
// What the backends share (besides Backend's vehicle bookkeeping, which makes both see exactly the
// same vehicles in the same order): the reads that are the same call in libsumo and libtraci (the two libraries
// expose one API in two namespaces; the templates take the namespace's classes, e.g.
// readLanes<libsumo::Lane>(), and are instantiated where that library's header is included).
#include <libsumo/TraCIDefs.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <stcosim/backend.hpp>
#include <sthighway/sumo_conversion.hpp>

namespace st::cosim::detail {

// SUMO lane ids end in "_<index>".
inline int laneIndex(const std::string& laneId) {
  const auto us = laneId.rfind('_');
  return us == std::string::npos ? 0 : std::stoi(laneId.substr(us + 1));
}

template <class Lane>
std::vector<SumoLane> readLanes() {
  std::vector<SumoLane> out;
  for (const auto& id : Lane::getIDList()) {
    SumoLane l;
    l.id = id;
    l.edge = Lane::getEdgeID(id);
    l.index = laneIndex(id);
    l.width = Lane::getWidth(id);
    l.length = Lane::getLength(id);
    for (const auto& p : Lane::getShape(id).value) l.shape.emplace_back(p.x, p.y);
    l.internal = !id.empty() && id[0] == ':';
    out.push_back(std::move(l));
  }
  return out;
}

// A vType's size, class and `mass` param (kg); a mass that is not a positive number is an error.
template <class VehicleType>
SumoVehicleType readVehicleType(const std::string& typeId) {
  SumoVehicleType t;
  t.id = typeId;
  t.vClass = VehicleType::getVehicleClass(typeId);
  t.length = VehicleType::getLength(typeId);
  t.width = VehicleType::getWidth(typeId);
  t.decel = VehicleType::getDecel(typeId);
  const std::string mass = VehicleType::getParameter(typeId, "mass");
  if (!mass.empty()) {
    std::size_t used = 0;
    double m = 0.0;
    try {
      m = std::stod(mass, &used);
    } catch (...) {
    }
    if (used != mass.size() || !(m > 0.0))
      throw SumoError("vType '" + typeId + "': param 'mass' must be a positive number of kg, got '" + mass + "'");
    t.mass = m;
  }
  return t;
}

// The colour the vehicle is drawn in: a vehicle without a colour of its own reports SUMO's default
// yellow but is drawn in its type's colour, which is then the colour to restore.
template <class Vehicle, class VehicleType>
Rgba readColor(const std::string& id) {
  auto c = Vehicle::getColor(id);
  if (c.r == 255 && c.g == 255 && c.b == 0 && c.a == 255) c = VehicleType::getColor(Vehicle::getTypeID(id));
  return {static_cast<std::uint8_t>(c.r), static_cast<std::uint8_t>(c.g), static_cast<std::uint8_t>(c.b),
          static_cast<std::uint8_t>(c.a)};
}

template <class Polygon, class PositionVector, class Color>
void addPolygon(const std::string& id, const std::vector<std::pair<double, double>>& shape, Rgba c, bool fill,
                int layer) {
  PositionVector pv;
  for (const auto& [x, y] : shape) {
    typename decltype(pv.value)::value_type p;
    p.x = x;
    p.y = y;
    pv.value.push_back(p);
  }
  Polygon::add(id, pv, Color(c.r, c.g, c.b, c.a), fill, "stsim", layer);
}

// SUMO caps a commanded slowdown at the vType's comfortable `decel` while the vehicle's speed mode
// has bit 2 ("regard maximum deceleration", set by default): a slowDown asking 8 m/s^2 of a car
// with decel 4.5 gets 4.5. Clearing that bit (the others, safe speed among them, stay) lets the
// duration set the deceleration, as the caller computed it.
template <class Vehicle>
void slowDownAtCommandedRate(const std::string& id, double speed, double duration) {
  constexpr int kRegardMaxDecel = 1 << 2;
  const int mode = Vehicle::getSpeedMode(id);
  if (mode & kRegardMaxDecel) Vehicle::setSpeedMode(id, mode & ~kRegardMaxDecel);
  Vehicle::slowDown(id, speed, duration);
}

// Whether SUMO moves vehicles sideways at finite speed (the sublane model or lane-change
// durations); else lateral speed is identically 0 and need not be read. An option SUMO does not
// know, or not as a number, counts as on.
template <class Simulation>
bool movesSideways() {
  auto positive = [](const char* name) {
    try {
      return std::stod(Simulation::getOption(name)) > 0.0;
    } catch (const libsumo::TraCIException&) {
      return true;
    } catch (const std::logic_error&) {  // std::stod: not a number, out of range
      return true;
    }
  };
  return positive("lateral-resolution") || positive("lanechange.duration");
}

// The persons on foot (not riding a vehicle) of this step.
template <class Person>
std::vector<std::string> walkingPersons() {
  std::vector<std::string> ids = Person::getIDList();
  std::erase_if(ids, [](const std::string& id) { return !Person::getVehicle(id).empty(); });
  return ids;
}

// Each vehicle's next point to stop or yield at, as SUMO's junctions have it: the state of the
// link its route takes at the end of its lane (a traffic light's, read once a step; an unsignalised
// junction's fixed one) and the distance to that lane's end (the stop line), or to the wait point
// inside the junction where SUMO holds a turner for the traffic it crosses (an internal lane whose
// exit link is minor, `m`: the left turn's). The links are read once, each light's state once a
// step (SUMO's getNextTLS per vehicle and step cost 70 % of stsim's time on a four-arm
// intersection). A vehicle on a major link with no wait point, past its wait point, or at the end
// of its route has none.
class SignalBook {
 public:
  template <class TrafficLight, class Lane>
  void load() {
    ids_ = TrafficLight::getIDList();
    states_.assign(ids_.size(), std::string());
    for (std::size_t k = 0; k < ids_.size(); ++k) {
      const auto links = TrafficLight::getControlledLinks(ids_[k]);
      for (std::size_t i = 0; i < links.size(); ++i)
        for (const auto& l : links[i]) {
          if (l.fromLane.empty() || l.toLane.empty()) continue;
          const std::string from = Lane::getEdgeID(l.fromLane), to = Lane::getEdgeID(l.toLane);
          links_.try_emplace(from + '\n' + to, Link{static_cast<int>(k), static_cast<int>(i), 0, waitOf<Lane>(l.viaLane)});
          if (!laneLength_.count(l.fromLane)) laneLength_.emplace(l.fromLane, Lane::getLength(l.fromLane));
        }
    }
    // the junctions without a light: their links' fixed states, where a driver yields or stops
    // (lanes in id order: an edge's first lane's link stands for the edge's, as a replay takes it)
    std::vector<std::string> lanes = Lane::getIDList();
    std::sort(lanes.begin(), lanes.end());
    for (const std::string& lane : lanes) {
      if (lane.empty() || lane[0] == ':') continue;
      std::string from;
      for (const auto& c : Lane::getLinks(lane)) {
        if (c.state.size() != 1) continue;
        const double wait = waitOf<Lane>(c.approachedInternal);
        if (!highway::givesWayAt(c.state[0]) && wait == 0.0) continue;  // a major link straight through
        if (from.empty()) from = Lane::getEdgeID(lane);
        links_.try_emplace(from + '\n' + Lane::getEdgeID(c.approachedLane), Link{-1, 0, c.state[0], wait});
        if (!laneLength_.count(lane)) laneLength_.emplace(lane, Lane::getLength(lane));
      }
    }
  }
  // whether any car can have a next light (or, with the priority rules, a yield)
  bool any(bool priority) const { return !ids_.empty() || (priority && !links_.empty()); }
  template <class TrafficLight>
  void readStates() {
    for (std::size_t k = 0; k < ids_.size(); ++k) states_[k] = TrafficLight::getRedYellowGreenState(ids_[k]);
  }
  // `where` gives the vehicle's lane and position on it, asked only when its route's next step
  // passes a light or (`priority`: the priority rules read) a yield (a car past its last one
  // reads nothing more)
  template <class Where>
  void next(SumoVehicle& v, Where&& where, bool priority) {
    v.nextSignal = 0;
    v.nextSignalDistance = 0.0;
    if (v.routeIndex < 0 || static_cast<std::size_t>(v.routeIndex) + 1 >= v.route.size()) return;
    key_.assign(v.route[static_cast<std::size_t>(v.routeIndex)]);
    key_ += '\n';
    key_ += v.route[static_cast<std::size_t>(v.routeIndex) + 1];
    const auto link = links_.find(key_);
    if (link == links_.end()) return;
    const Link& l = link->second;
    if (l.tls < 0 && !priority) return;
    char state = l.fixed;
    if (l.tls >= 0) {
      const std::string& s = states_[static_cast<std::size_t>(l.tls)];
      if (static_cast<std::size_t>(l.index) >= s.size()) return;
      state = s[static_cast<std::size_t>(l.index)];
    }
    const auto [lane, lanePos] = where();
    if (const auto len = laneLength_.find(lane); len != laneLength_.end()) {
      v.nextSignal = state;
      v.nextSignalDistance = std::max(0.0, len->second - lanePos);
      // a link that lets it go on holds a turner at its wait point: it yields there
      if (priority && l.wait > 0.0 && highway::entersAt(state)) {
        v.nextSignal = 'm';
        v.nextSignalDistance += l.wait;
      }
    } else if (const auto wait = waitLength_.find(lane); priority && wait != waitLength_.end()) {
      v.nextSignal = 'm';  // in the junction, before its wait point
      v.nextSignalDistance = std::max(0.0, wait->second - lanePos);
    }
  }

 private:
  struct Link {
    int tls, index;  // the light and its link index (tls -1: no light)
    char fixed;      // without a light, the link's fixed state (SUMO's m, =, s, w, M)
    double wait;     // from the stop line to the wait point inside the junction (m); 0: none
  };
  // The length of an internal lane whose exit is minor (a wait point: SUMO holds a turner at its
  // end), remembered by lane; 0 for any other lane.
  template <class Lane>
  double waitOf(const std::string& via) {
    if (via.empty() || via[0] != ':') return 0.0;
    if (const auto it = waitLength_.find(via); it != waitLength_.end()) return it->second;
    for (const auto& c : Lane::getLinks(via))
      if (c.state == "m" && !c.approachedInternal.empty()) {
        const double len = Lane::getLength(via);
        waitLength_.emplace(via, len);
        return len;
      }
    return 0.0;
  }
  std::vector<std::string> ids_, states_;
  std::unordered_map<std::string, Link> links_;         // "from edge\nto edge" -> the first link between them
  std::unordered_map<std::string, double> laneLength_;  // lanes ending at a light or a yield -> their length (m)
  std::unordered_map<std::string, double> waitLength_;  // internal lanes ending at a wait point -> their length (m)
  std::string key_;
};

}  // namespace st::cosim::detail
