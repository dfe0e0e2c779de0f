#include <stcosim/plugin.hpp>

#include <algorithm>
#include <limits>

#include <stcore/box2.hpp>
#include <sthighway/brake_policy.hpp>
#include <sthighway/detector.hpp>

#include <stcosim/conversions.hpp>

namespace st::cosim {

const char* toString(Action a) {
  switch (a) {
    case Action::None: return "none";
    case Action::Color: return "color";
    case Action::Brake: return "brake";
  }
  return "?";
}

bool parseAction(const std::string& text, Action& out) {
  if (text == "none") out = Action::None;
  else if (text == "color" || text == "colour") out = Action::Color;
  else if (text == "brake") out = Action::Brake;
  else return false;
  return true;
}

namespace {
// What the monitor uses: acceleration only to predict with constant acceleration, blinkers only
// to excuse a lane-marker crossing.
VehicleReads readsFor(const highway::MonitorConfig& m) {
  VehicleReads r;
  r.acceleration = m.detector.motion == highway::MotionModel::ConstantAcceleration;
  r.signals = m.checkRoad;
  r.route = m.prediction == highway::Prediction::Road;
  r.priority = m.priorityRules;
  return r;
}
}  // namespace

HighwayPlugin::HighwayPlugin(Backend& backend, PluginConfig config)
    : HighwayPlugin(nullptr, backend, std::move(config), toRoadGeometry(backend.lanes())) {}

HighwayPlugin::HighwayPlugin(std::unique_ptr<Backend>&& owned, Backend& backend, PluginConfig config,
                             const highway::RoadGeometry& road)
    : owned_(std::move(owned)), backend_(backend), config_(std::move(config)), monitor_(road, config_.monitor) {
  const std::vector<std::string> edges = highway::edgeIds(road);
  for (int e = 0; e < static_cast<int>(edges.size()); ++e) edgeIndex_.emplace(edges[e], e);
  backend_.setReads(readsFor(config_.monitor));
  incidentRuns_.resize(config_.incidents.size());
}

HighwayPlugin::~HighwayPlugin() = default;

std::unique_ptr<HighwayPlugin> HighwayPlugin::forLibsumo(PluginConfig config) {
  std::unique_ptr<Backend> backend = attachLibsumo();
  Backend& b = *backend;
  const highway::RoadGeometry road = toRoadGeometry(b.lanes());
  return std::unique_ptr<HighwayPlugin>(new HighwayPlugin(std::move(backend), b, std::move(config), road));
}

const HighwayPlugin::TypeInfo& HighwayPlugin::typeInfo(int typeIndex) {
  const auto k = static_cast<std::size_t>(typeIndex);
  if (k >= types_.size()) types_.resize(k + 1);
  TypeInfo& t = types_[k];
  if (!t.known) {
    const SumoVehicleType& sumo = backend_.vehicleType(typeIndex);
    t.info = toVehicleTypeInfo(sumo);
    const auto& smart = config_.smart.types;
    t.smart = std::find(smart.begin(), smart.end(), sumo.id) != smart.end();
    t.known = true;
  }
  return t;
}

double HighwayPlugin::bodyGap(const SumoCollision& c) const {
  const highway::VehicleState *a = nullptr, *b = nullptr;
  for (const highway::VehicleState& v : states_) {
    if (v.id == c.collider) a = &v;
    if (v.id == c.victim) b = &v;
  }
  if (!a || !b) return std::numeric_limits<double>::quiet_NaN();
  return distance(highway::bodyOf(*a).box(), highway::bodyOf(*b).box());
}

double HighwayPlugin::collidingGap(const SumoCollision& c, double stepLength) const {
  const Box2 *a = nullptr, *b = nullptr;
  for (const CollidingBody& k : collidingBodies_) {
    if (std::abs(k.time - c.time) > 0.5 * stepLength) continue;
    if (k.id == c.collider) a = &k.box;
    if (k.id == c.victim) b = &k.box;
  }
  return a && b ? distance(*a, *b) : std::numeric_limits<double>::quiet_NaN();
}

void HighwayPlugin::step() {
  backend_.read();
  update();
}

void HighwayPlugin::update() {
  prepare();
  detect();
  act();
}

void HighwayPlugin::detect() { monitor_.step(time_, states_); }

void HighwayPlugin::prepare() {
  time_ = backend_.time();
  const StepEvents& ev = backend_.events();
  counters_.steps++;
  counters_.departed += ev.departed.size();
  counters_.arrived += ev.arrived.size();
  counters_.teleports += ev.teleportStarted.size();
  collisionCounter_.step(ev.collisions);
  counters_.collisions = collisionCounter_.distinct();
  counters_.collisionSteps = collisionCounter_.reports();
  const std::size_t newCollisions = collisions_.size();
  collisions_.insert(collisions_.end(), ev.collisions.begin(), ev.collisions.end());

  // convert in place; decide each vehicle's equipment once, on first sight
  const auto& vehicles = backend_.vehicles();
  const auto& persons = backend_.persons();
  vehicleStates_ = vehicles.size();
  states_.resize(vehicles.size() + persons.size());
  serials_.resize(states_.size());
  for (std::size_t i = 0; i < vehicles.size(); ++i) {
    const SumoVehicle& v = vehicles[i];
    const TypeInfo& t = typeInfo(v.typeIndex);
    toVehicleState(v, t.info, states_[i]);
    bodies_.fit(v.serial, time_, states_[i]);
    serials_[i] = v.serial;
    if (v.serial >= perVehicle_.size()) perVehicle_.resize(v.serial + 1);
    PerVehicle& pv = perVehicle_[v.serial];
    if (pv.equipped < 0) {
      pv.equipped = t.smart || highway::drawnEquipped(config_.smart.seed, v.id, config_.smart.penetration);
      if (pv.equipped) counters_.equipped++;
    }
    states_[i].equipped = pv.equipped != 0;
    // the route from the current edge on, as the monitor's edge indices (converted once per route)
    if (pv.routeVersion != v.routeVersion) {
      pv.routeVersion = v.routeVersion;
      pv.route.clear();
      for (const std::string& e : v.route) {
        const auto it = edgeIndex_.find(e);
        pv.route.push_back(it == edgeIndex_.end() ? -1 : it->second);
      }
    }
    auto& route = states_[i].route;
    route.fill(-1);
    for (int k = 0; k < highway::kRouteAhead && v.routeIndex >= 0; ++k) {
      const std::size_t at = static_cast<std::size_t>(v.routeIndex) + k;
      if (at >= pv.route.size() || pv.route[at] < 0) break;
      route[k] = pv.route[at];
    }
  }
  // persons on foot: foes with their own bodies, predicted in straight lines (no route, no lane)
  for (std::size_t j = 0; j < persons.size(); ++j) {
    const SumoVehicle& p = persons[j];
    const std::size_t i = vehicles.size() + j;
    const TypeInfo& t = typeInfo(p.typeIndex);
    toVehicleState(p, t.info, states_[i]);
    states_[i].equipped = t.smart;
    states_[i].route.fill(-1);
    serials_[i] = p.serial;
  }
  // each collision's bodies at this step: touching, or apart (SUMO's minGap rule)
  for (std::size_t k = newCollisions; k < collisions_.size(); ++k) collisions_[k].gap = bodyGap(collisions_[k]);
  // the bodies of the vehicles SUMO named colliding, from then on for kCollidingWatch s (SUMO names
  // a pair once, then reports it in its file at every step it still counts as a collision)
  for (const std::string& id : ev.colliding) collidingSince_[id] = time_;
  if (!collidingSince_.empty()) {
    for (const highway::VehicleState& v : states_) {
      const auto it = collidingSince_.find(v.id);
      if (it != collidingSince_.end() && time_ - it->second <= kCollidingWatch)
        collidingBodies_.push_back({time_, v.id, highway::bodyOf(v).box()});
    }
    std::erase_if(collidingSince_, [&](const auto& kv) { return time_ - kv.second > kCollidingWatch; });
  }
  // incidents act on the states, not on the warnings: they need not wait for detect()
  runIncidents();
}

bool HighwayPlugin::inIncident(std::uint32_t serial) const {
  return std::any_of(incidentRuns_.begin(), incidentRuns_.end(), [&](const IncidentRun& r) {
    return r.serial == serial && (r.phase == IncidentRun::Phase::Braking || r.phase == IncidentRun::Phase::Holding);
  });
}

void HighwayPlugin::runIncidents() {
  using Phase = IncidentRun::Phase;
  // a phase starts at the first step at or after its time; the slack only absorbs the rounding of
  // SUMO's summed step times (a phase end is rarely on a step, so half a step would start it early)
  const double t = backend_.time() + 1e-6 * backend_.deltaT();
  const auto& vehicles = backend_.vehicles();
  for (std::size_t k = 0; k < incidentRuns_.size(); ++k) {
    IncidentRun& run = incidentRuns_[k];
    const Incident& inc = config_.incidents[k];
    if (run.phase == Phase::Done || t < inc.time) continue;
    if (run.phase == Phase::Pending) {
      std::size_t best = vehicles.size();
      double bestDistance = 0.0;
      for (std::size_t i = 0; i < vehicles.size(); ++i) {
        const double d = (states_[i].position - Vec2(inc.x, inc.y)).squaredNorm();
        if (best == vehicles.size() || d < bestDistance) best = i, bestDistance = d;
      }
      if (best == vehicles.size()) continue;  // an empty road: the next step
      run.vehicle = vehicles[best].id;
      run.serial = vehicles[best].serial;
      const double duration = std::max((states_[best].speed - inc.speed) / inc.deceleration, backend_.deltaT());
      backend_.slowDown(run.vehicle, inc.speed, duration);
      run.until = backend_.time() + duration;
      run.phase = Phase::Braking;
      counters_.incidents++;
      continue;
    }
    const bool onRoad = std::any_of(vehicles.begin(), vehicles.end(),
                                    [&](const SumoVehicle& v) { return v.serial == run.serial; });
    if (!onRoad) {  // arrived or teleported: the incident is over
      run.phase = Phase::Done;
      continue;
    }
    if (t < run.until) continue;
    if (run.phase == Phase::Braking) {
      backend_.setSpeed(run.vehicle, inc.speed);
      run.until = backend_.time() + inc.hold;
      run.phase = Phase::Holding;
    } else {
      backend_.setSpeed(run.vehicle, -1.0);
      run.phase = Phase::Done;
    }
  }
}

void HighwayPlugin::act() {
  const ActionConfig& a = config_.actions;
  if (a.action == Action::None) return;
  // The alerts are of states_, whose vehicles are named by their serials: with colour beside the
  // step (DetectionStage) the backend is a step ahead of them, and a vehicle that has left since
  // is not painted. In line the two are the same vehicles.
  // Marks are act()'s number, so nothing is cleared per call.
  const auto& vehicles = backend_.vehicles();
  const std::uint64_t now = ++acts_;
  for (const SumoVehicle& v : vehicles)
    if (v.serial < perVehicle_.size()) perVehicle_[v.serial].onRoadAt = now;
  for (const highway::Alert& al : monitor_.alerts()) {
    const auto i = static_cast<std::size_t>(al.vehicle);
    if (i >= vehicleStates_) continue;  // an equipped person: warned in the outputs, no colour or brake in SUMO
    const highway::VehicleState& s = states_.at(i);
    const std::uint32_t serial = serials_[i];
    PerVehicle& pv = perVehicle_[serial];
    if (pv.onRoadAt != now) continue;
    pv.alertedAt = now;
    const int level = al.ttc < a.redFraction * al.safeTime ? 2 : 1;
    if (!pv.painted) {
      pv.original = backend_.color(s.id);
      pv.painted = true;
    }
    if (pv.level != level) {
      backend_.setColor(s.id, level == 2 ? a.dangerColor : a.warningColor);
      pv.level = static_cast<std::uint8_t>(level);
      counters_.colorChanges++;
    }
    if (a.action == Action::Brake && al.kind == highway::WarningKind::Vehicle && al.foe >= 0 &&
        !inIncident(serial)) {
      // re-decided at every step (sthighway/brake_policy.hpp); SUMO's slowDown takes at least a step
      const highway::VehicleState& f = states_.at(static_cast<std::size_t>(al.foe));
      if (const auto brake = highway::brakeFor(s, f, a.brake)) {
        backend_.slowDown(s.id, brake->targetSpeed, std::max(brake->duration, backend_.deltaT()));
        counters_.brakeCommands++;
      }
    }
  }
  // warnings over: give the vehicle its own colour back (only vehicles on the road: a teleporting
  // one keeps its level until it is back)
  for (const SumoVehicle& v : vehicles) {
    if (v.serial >= perVehicle_.size()) continue;  // appeared after the alerts' tick: never painted
    PerVehicle& pv = perVehicle_[v.serial];
    if (pv.level == 0 || pv.alertedAt == now) continue;
    backend_.setColor(v.id, pv.original);
    pv.level = 0;
    counters_.colorChanges++;
  }
}

void HighwayPlugin::finish() { monitor_.finish(backend_.time()); }

std::vector<SumoCollision> HighwayPlugin::takeCollisions() {
  std::vector<SumoCollision> out;
  out.swap(collisions_);
  return out;
}

int HighwayPlugin::drawCells() {
  const highway::CellNetwork& cells = monitor_.cells();
  for (int c = 0; c < cells.cellCount(); ++c) {
    const Aabb<2> box = cells.cellExtent(c);
    const double x0 = box.min.x(), y0 = box.min.y(), x1 = box.max.x(), y1 = box.max.y();
    // alternate two colours so neighbouring cells are told apart
    const Rgba col = c % 2 == 0 ? Rgba{0, 160, 255, 255} : Rgba{255, 120, 0, 255};
    backend_.addPolygon("stsim_cell_" + std::to_string(c), {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}, col,
                        false, 5);
  }
  // read back: what SUMO holds, not what was sent
  const std::string prefix = "stsim_cell_";
  int held = 0;
  for (const auto& id : backend_.polygonIds()) held += id.rfind(prefix, 0) == 0;
  return held;
}

}  // namespace st::cosim
