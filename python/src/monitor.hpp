#pragma once
// The monitor as Python holds it: the highway monitor, the ids of its road's lanes and edges, and
// the last step's states (for the alerts' ids).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <string>
#include <unordered_map>
#include <vector>

#include <sthighway/monitor.hpp>
#include <sthighway/settings.hpp>
#include <sthighway/sumo_conversion.hpp>
#include <sthighway/sumo_files.hpp>
#include <stio/format.hpp>

#include "states.hpp"

namespace stpy {

struct PyAlert {
  int vehicle = -1;
  std::string ego;
  hw::WarningKind kind = hw::WarningKind::Vehicle;
  hw::Zone zone = hw::Zone::Body;
  double ttc = 0.0, safeTime = 0.0;
  int foeVehicle = -1;  // the foe's index into the last step's vehicles; -1 for road warnings
  std::string foe;       // its id, as WarningEpisode.foe
};

class Monitor {
 public:
  Monitor(const hw::RoadGeometry& road, const hw::MonitorConfig& cfg)
      : monitor_(road, cfg), hindsight_(cfg.hindsight), bounds_(hw::fcdChecksFor(road, {}, "the road")) {
    for (std::size_t i = 0; i < road.lanes.size(); ++i) lanes_.emplace(road.lanes[i].id, static_cast<int>(i));
    const std::vector<std::string> edges = hw::edgeIds(road);
    for (std::size_t e = 0; e < edges.size(); ++e) edges_.emplace(edges[e], static_cast<int>(e));
  }

  void step(double t, py::handle vehicles, Convention c) {
    if (!std::isfinite(t)) throw py::value_error("step time must be finite, got " + std::to_string(t));
    readStates(vehicles, c, lanes_, edges_, states_);
    for (std::size_t i = 0; i < states_.size(); ++i)
      if (const std::string why = implausible(states_[i]); !why.empty())
        throw py::value_error("vehicle " + std::to_string(i) + " ('" + states_[i].id + "'): " + why);
    if (c == Convention::Sumo)  // bodies along their paths, as the SUMO coupling has them
      for (hw::VehicleState& s : states_) bodies_.fit(bodyKeys_.try_emplace(s.id, bodyKeys_.size()).first->second, t, s);
    {
      py::gil_scoped_release free;
      monitor_.step(t, states_);
    }
  }
  void finish(double t) {
    if (!std::isfinite(t)) throw py::value_error("finish time must be finite, got " + st::io::number(t));
    monitor_.finish(t);
  }
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
  std::vector<hw::Conflict> takeConflicts() {
    std::vector<hw::Conflict> out;
    monitor_.takeConflicts(out);
    return out;
  }
  std::vector<hw::Warning> openWarnings() const { return monitor_.openWarnings(); }
  std::vector<PyAlert> alerts() const {
    std::vector<PyAlert> out;
    for (const hw::Alert& a : monitor_.alerts()) {
      PyAlert p{a.vehicle, states_.at(static_cast<std::size_t>(a.vehicle)).id, a.kind, a.zone, a.ttc, a.safeTime, a.foe, {}};
      if (a.foe >= 0) p.foe = states_.at(static_cast<std::size_t>(a.foe)).id;
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
    d["persons_seen"] = c.personsSeen;
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
  hw::PathBodies bodies_;                 // SUMO's bodies along their paths (step_sumo)
  std::unordered_map<std::string, std::size_t> bodyKeys_;  // vehicle id -> its key in bodies_
  hw::FcdChecks bounds_;                  // the road's box (bounded when it has lanes)

  // What no vehicle has, refused as the CLI refuses it in a trace (sthighway/sumo_files.hpp's
  // bounds): "" when the state is plausible. The monitor itself only asks for finite values.
  std::string implausible(const hw::VehicleState& v) const {
    const double x = v.position.x(), y = v.position.y();
    if (bounds_.bounded) {
      const double g = hw::FcdChecks::kOutsideMargin;
      if (!(x >= bounds_.lo.x() - g && x <= bounds_.hi.x() + g && y >= bounds_.lo.y() - g && y <= bounds_.hi.y() + g))
        return "position (" + st::io::number(x) + ", " + st::io::number(y) + ") is more than " + st::io::number(g) +
               " m outside the road's lanes";
    } else if (!(std::abs(x) <= hw::kNetMaxCoordinate && std::abs(y) <= hw::kNetMaxCoordinate)) {
      return "position (" + st::io::number(x) + ", " + st::io::number(y) + ") is farther than " +
             st::io::number(hw::kNetMaxCoordinate) + " m from the origin";
    }
    if (!(std::abs(v.heading) <= hw::kMaxHeading))
      return "heading " + st::io::number(v.heading) + " rad is not a heading (at most " + st::io::number(hw::kMaxHeading) +
             " either way)";
    if (v.speed < 0.0) return "speed " + st::io::number(v.speed) + " m/s is negative";
    if (v.speed > hw::kFcdMaxSpeed)
      return "speed " + st::io::number(v.speed) + " m/s is beyond any vehicle's (at most " + st::io::number(hw::kFcdMaxSpeed) + ")";
    if (!(std::abs(v.acceleration) <= hw::kFcdMaxAcceleration))
      return "acceleration " + st::io::number(v.acceleration) + " m/s^2 is beyond any vehicle's (at most " +
             st::io::number(hw::kFcdMaxAcceleration) + ")";
    if (v.length > hw::kFcdMaxSize || v.width > hw::kFcdMaxSize)
      return "length and width must be at most " + st::io::number(hw::kFcdMaxSize) + " m";
    return "";
  }
};


}  // namespace stpy
