// The TraCI backend (libtraci). Vehicle state comes from one variable subscription per vehicle,
// made when it departs; the simulation's departures, arrivals, teleports, time and expected-vehicle
// count come from one simulation subscription. SUMO sends all subscription results with the answer
// to the step command, so a step costs one round trip however many vehicles there are. Only
// departures (subscribe) cost extra trips. Collisions are not read per step: SUMO 1.15's libtraci
// leaves getCollisions unimplemented (collisions.hpp reads SUMO's collision file instead).
#include <libsumo/libtraci.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <memory>
#include <optional>
#include <unordered_set>

#include "backend_common.hpp"
#include "sumo_process.hpp"
#include "traci_relay.hpp"
#include <stcosim/backend.hpp>

namespace st::cosim {
namespace {

using libsumo::TraCIResults;

// The per-step variables, as VehicleReads asks: SUMO's server answers each subscribed variable
// of each vehicle with a full getter of its own (about 0.8 us per variable and vehicle in SUMO
// 1.15, bench/RESULTS.md), so a variable not needed is not subscribed. The type, needed once per
// vehicle, is a getter at its first appearance rather than a variable sent every step.
// With traffic lights (`lights`), the lane and the position on it for the next light.
std::vector<int> vehicleVars(const VehicleReads& reads, bool lateral, bool lights) {
  std::vector<int> vars{libsumo::VAR_POSITION, libsumo::VAR_ANGLE, libsumo::VAR_SPEED};
  if (lateral) vars.push_back(libsumo::VAR_SPEED_LAT);
  if (reads.acceleration) vars.push_back(libsumo::VAR_ACCELERATION);
  if (reads.signals) vars.push_back(libsumo::VAR_SIGNALS);
  if (reads.route || lights) {
    vars.push_back(libsumo::VAR_ROUTE_INDEX);
    vars.push_back(libsumo::VAR_ROUTE_ID);
  }
  if (lights) {
    vars.push_back(libsumo::VAR_LANE_ID);
    vars.push_back(libsumo::VAR_LANEPOSITION);
  }
  return vars;
}
// A person's per-step variables; VAR_VEHICLE tells a rider (not on foot) apart.
const std::vector<int> kPersonVars{libsumo::VAR_POSITION, libsumo::VAR_ANGLE, libsumo::VAR_SPEED, libsumo::VAR_VEHICLE};
const std::vector<int> kSimulationVars{libsumo::VAR_TIME,
                                       libsumo::VAR_DEPARTED_VEHICLES_IDS,
                                       libsumo::VAR_ARRIVED_VEHICLES_IDS,
                                       libsumo::VAR_TELEPORT_STARTING_VEHICLES_IDS,
                                       libsumo::VAR_TELEPORT_ENDING_VEHICLES_IDS,
                                       libsumo::VAR_MIN_EXPECTED_VEHICLES,
                                       libsumo::VAR_COLLIDING_VEHICLES_IDS};

template <class T>
const T& resultAs(const TraCIResults& r, int var, const std::string& what) {
  const auto it = r.find(var);
  const T* v = it == r.end() ? nullptr : dynamic_cast<const T*>(it->second.get());
  if (v == nullptr) throw SumoError("TraCI: subscription result " + what + " missing or of the wrong type");
  return *v;
}

std::atomic<int> connectionCounter{0};

class TraciBackend final : public Backend {
 public:
  // Connects to localhost:port (or host:port); `process` is the SUMO we launched, if any.
  TraciBackend(const std::string& host, int port, int order, std::unique_ptr<detail::SumoProcess> process)
      : host_(host), port_(port), order_(order), process_(std::move(process)) {
    label_ = "stsim" + std::to_string(connectionCounter++);
    // on this host, wait for the port to listen (reading /proc, without connecting: a probing
    // connection would take one of SUMO's --num-clients slots), so libtraci connects at its first
    // try and does not print its retry messages
    const bool local = host == "localhost" || host == "127.0.0.1" || host == "::1";
    if (local && !process_) {
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      while (!detail::portListening(port)) {
        if (std::chrono::steady_clock::now() > deadline)
          throw SumoError("nothing listens on " + where() + " (start SUMO with --remote-port " + std::to_string(port) +
                          ")");
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    }
    // a server we did not start is reached through the relay, which checks its replies' framing
    // before libtraci (which trusts them) sees them
    if (!process_) {
      try {
        relay_ = std::make_unique<detail::TraciRelay>(host, port, local ? 1 : 10);
      } catch (const SumoError& e) {
        closed_ = true;
        throw SumoError("cannot connect to SUMO at " + where() + ": " + e.what());
      }
    }
    try {
      if (relay_) libtraci::Simulation::init(relay_->localPort(), 0, "127.0.0.1", label_);
      else libtraci::Simulation::init(port, local ? 0 : 10, host, label_);
      if (order_ > 0) libtraci::Simulation::setOrder(order_);
    } catch (const std::exception& e) {
      const std::string why = relay_ && !relay_->failure().empty() ? relay_->failure() : std::string(e.what());
      std::string msg = "cannot connect to SUMO at " + where() + ": " + why;
      if (process_) {
        // SUMO listens before it loads its inputs: a bad input shows up as a dropped connection;
        // give it a moment to exit and report its own error line
        process_->stop(2.0);
        const std::string tail = process_->logTail();
        if (!tail.empty()) msg = "SUMO failed: " + tail;
      }
      closed_ = true;
      throw SumoError(msg);
    }
    guard([&] {
      deltaT_ = libtraci::Simulation::getDeltaT();
      gui_ = libtraci::Simulation::hasGUI();
      endTime_ = libtraci::Simulation::getEndTime();
      lateral_ = detail::movesSideways<libtraci::Simulation>();
      signals_.load<libtraci::TrafficLight, libtraci::Lane>();
      subscribedWith_ = reads_;
      vars_ = vehicleVars(reads_, lateral_, lights());
      libtraci::Simulation::subscribe(kSimulationVars);
      // vehicles already on the road when we attach
      const auto ids = libtraci::Vehicle::getIDList();
      for (const auto& id : ids) subscribe(id);
      StepEvents initial;
      initial.departed = ids;
      const auto results = libtraci::Vehicle::getAllSubscriptionResults();  // a const copy: not moved
      results_ = &results;
      applyEvents(initial);
      time_ = libtraci::Simulation::getTime();
      minExpected_ = libtraci::Simulation::getMinExpectedNumber();
      readVehicles();
      results_ = nullptr;
      readPersons();
    });
  }
  ~TraciBackend() override { close(); }

  BackendKind kind() const override { return BackendKind::Traci; }

  void read() override {
    guard([&] {
      const TraCIResults sim = libtraci::Simulation::getSubscriptionResults();
      time_ = resultAs<libsumo::TraCIDouble>(sim, libsumo::VAR_TIME, "time").value;
      events_.departed = resultAs<libsumo::TraCIStringList>(sim, libsumo::VAR_DEPARTED_VEHICLES_IDS, "departed").value;
      events_.arrived = resultAs<libsumo::TraCIStringList>(sim, libsumo::VAR_ARRIVED_VEHICLES_IDS, "arrived").value;
      events_.teleportStarted =
          resultAs<libsumo::TraCIStringList>(sim, libsumo::VAR_TELEPORT_STARTING_VEHICLES_IDS, "teleports").value;
      events_.teleportEnded =
          resultAs<libsumo::TraCIStringList>(sim, libsumo::VAR_TELEPORT_ENDING_VEHICLES_IDS, "teleports").value;
      minExpected_ = resultAs<libsumo::TraCIInt>(sim, libsumo::VAR_MIN_EXPECTED_VEHICLES, "expected").value;
      events_.colliding = resultAs<libsumo::TraCIStringList>(sim, libsumo::VAR_COLLIDING_VEHICLES_IDS, "colliding").value;
      for (const auto& id : events_.arrived) subscribed_.erase(id);
      // a subscription's answer carries the current values, so departing vehicles are read this step
      if (reads_ == subscribedWith_) {
        for (const auto& id : events_.departed) subscribe(id);
      } else {
        // the reads changed: every vehicle SUMO still holds (teleporting ones too) is subscribed again
        subscribedWith_ = reads_;
        vars_ = vehicleVars(reads_, lateral_, lights());
        for (const auto& id : events_.departed) subscribed_.insert(id);
        for (const auto& id : subscribed_) libtraci::Vehicle::subscribe(id, vars_);
      }
      const auto results = libtraci::Vehicle::getAllSubscriptionResults();
      results_ = &results;
      applyEvents(events_);
      readVehicles();
      results_ = nullptr;
      readPersons();
    });
  }

  bool running() override { return minExpected_ > 0 && (endTime_ < 0 || time_ < endTime_ - 0.5 * deltaT_); }

  std::vector<SumoLane> lanes() override {
    std::vector<SumoLane> out;
    guard([&] { out = detail::readLanes<libtraci::Lane>(); });
    return out;
  }

  Rgba color(const std::string& id) override {
    Rgba out;
    guard([&] { out = detail::readColor<libtraci::Vehicle, libtraci::VehicleType>(id); });
    return out;
  }
  void setColor(const std::string& id, Rgba c) override {
    guard([&] { libtraci::Vehicle::setColor(id, libsumo::TraCIColor(c.r, c.g, c.b, c.a)); });
  }
  void slowDown(const std::string& id, double speed, double duration) override {
    guard([&] { detail::slowDownAtCommandedRate<libtraci::Vehicle>(id, speed, duration); });
  }
  void setSpeed(const std::string& id, double speed) override {
    guard([&] { libtraci::Vehicle::setSpeed(id, speed); });
  }
  void addPolygon(const std::string& id, const std::vector<std::pair<double, double>>& shape, Rgba c, bool fill,
                  int layer) override {
    guard([&] {
      detail::addPolygon<libtraci::Polygon, libsumo::TraCIPositionVector, libsumo::TraCIColor>(id, shape, c, fill,
                                                                                              layer);
    });
  }
  std::vector<std::string> polygonIds() override {
    std::vector<std::string> ids;
    guard([&] { ids = libtraci::Polygon::getIDList(); });
    return ids;
  }
  bool hasGui() override { return gui_; }

  void close() noexcept override {
    if (closed_) return;
    closed_ = true;
    if (relay_) relay_->closeWithin(5.0);
    try {
      libtraci::Simulation::switchConnection(label_);
      if (!broken_) libtraci::Simulation::close();
    } catch (...) {
    }
    relay_.reset();
    if (process_) process_->stop(broken_ ? 0.0 : 10.0);
  }

  std::string describe() const override {
    std::string d = "libtraci " + where();
    if (process_) d += gui_ ? " (launched sumo-gui)" : " (launched)";
    else if (gui_) d += " (sumo-gui)";
    if (order_ > 0) d += " (client order " + std::to_string(order_) + ")";
    return d;
  }

 protected:
  void advance() override {
    guard([&] { libtraci::Simulation::step(); });
  }
  SumoVehicleType readVehicleType(const std::string& typeId) override {
    SumoVehicleType t;
    guard([&] { t = detail::readVehicleType<libtraci::VehicleType>(typeId); });
    return t;
  }
  // once per vehicle, at its first appearance (called within read())
  std::string readTypeId(const std::string& vehicleId) override { return libtraci::Vehicle::getTypeID(vehicleId); }
  std::string readPersonTypeId(const std::string& personId) override { return libtraci::Person::getTypeID(personId); }

 private:
  std::string where() const { return host_ + ":" + std::to_string(port_); }

  void subscribe(const std::string& id) {
    libtraci::Vehicle::subscribe(id, vars_);
    subscribed_.insert(id);
  }


  // Runs a TraCI exchange on our connection; turns libtraci's errors into one-line SumoErrors.
  template <class F>
  void guard(F&& f) {
    if (broken_ || closed_) throw SumoError("TraCI connection to " + where() + " is closed");
    try {
      libtraci::Simulation::switchConnection(label_);
      f();
    } catch (const libsumo::TraCIException& e) {
      // SUMO refused a command (unknown id, bad value); the connection is fine, unless the relay
      // cut it (libtraci may report a cut reply as a parse error)
      if (relayFailed()) throw lost(e.what());
      throw SumoError(std::string("TraCI: ") + e.what());
    } catch (const SumoError&) {
      throw;
    } catch (const std::exception& e) {
      // FatalTraCIError, or tcpip::SocketException when the peer resets the connection
      throw lost(e.what());
    }
  }

  bool relayFailed() const { return relay_ && !relay_->failure().empty(); }

  // Marks the connection broken and says why: the relay's reason if it cut the connection, else
  // libtraci's; SUMO's own last error line if we launched it.
  SumoError lost(const std::string& what) {
    broken_ = true;
    std::string msg = "TraCI connection to " + where();
    if (relayFailed()) {
      msg += " broken at t = " + std::to_string(time_) + " s: " + relay_->failure();
    } else {
      msg += " lost at t = " + std::to_string(time_) + " s: " + what;
    }
    if (process_) {
      const std::string tail = process_->logTail();
      if (!tail.empty()) msg += " (SUMO: " + tail + ")";
    }
    return SumoError(msg);
  }

  const TraCIResults& vehicleResults(const std::string& id) const {
    const auto it = results_->find(id);
    if (it == results_->end()) throw SumoError("TraCI: no subscription results for vehicle '" + id + "'");
    return it->second;
  }

  // a vehicle's or person's position, heading and speed from its step's subscription results
  static void readPose(SumoVehicle& v, const TraCIResults& r) {
    const auto& p = resultAs<libsumo::TraCIPosition>(r, libsumo::VAR_POSITION, "position");
    v.x = p.x;
    v.y = p.y;
    v.angle = resultAs<libsumo::TraCIDouble>(r, libsumo::VAR_ANGLE, "angle").value;
    v.speed = resultAs<libsumo::TraCIDouble>(r, libsumo::VAR_SPEED, "speed").value;
  }

  // the per-step values, in place
  void readVehicles() {
    const bool lights = this->lights();
    if (lights) signals_.readStates<libtraci::TrafficLight>();
    for (SumoVehicle& v : vehicles_) {
      const TraCIResults& r = vehicleResults(v.id);
      readPose(v, r);
      if (lateral_) v.lateralSpeed = resultAs<libsumo::TraCIDouble>(r, libsumo::VAR_SPEED_LAT, "lateral speed").value;
      if (reads_.acceleration)
        v.acceleration = resultAs<libsumo::TraCIDouble>(r, libsumo::VAR_ACCELERATION, "acceleration").value;
      if (reads_.signals) v.signals = resultAs<libsumo::TraCIInt>(r, libsumo::VAR_SIGNALS, "signals").value;
      if (reads_.route || lights) {
        v.routeIndex = resultAs<libsumo::TraCIInt>(r, libsumo::VAR_ROUTE_INDEX, "route index").value;
        const std::string& routeId = resultAs<libsumo::TraCIString>(r, libsumo::VAR_ROUTE_ID, "route").value;
        if (routeId != v.routeId) {
          // one round trip per vehicle and route (SUMO gives a rerouted vehicle a new route id)
          v.route = libtraci::Vehicle::getRoute(v.id);
          v.routeId = routeId;
          v.routeVersion = ++routeReads_;
        }
      }
      if (lights)
        signals_.next(v, [&] {
          return std::pair<const std::string&, double>(
              resultAs<libsumo::TraCIString>(r, libsumo::VAR_LANE_ID, "lane").value,
              resultAs<libsumo::TraCIDouble>(r, libsumo::VAR_LANEPOSITION, "lane position").value);
        }, reads_.priority);
    }
  }

  // The persons on foot: their list (one round trip a step), a subscription for each new one (one
  // trip each), their values from the step's answer.
  void readPersons() {
    if (!reads_.persons) return;
    const std::vector<std::string> ids = libtraci::Person::getIDList();
    for (const std::string& id : ids)
      if (personsSubscribed_.insert(id).second) libtraci::Person::subscribe(id, kPersonVars);
    if (personsSubscribed_.size() > ids.size()) {  // some have left SUMO (their subscriptions with them)
      const std::unordered_set<std::string> present(ids.begin(), ids.end());
      std::erase_if(personsSubscribed_, [&](const std::string& id) { return !present.contains(id); });
    }
    const auto results = libtraci::Person::getAllSubscriptionResults();
    auto of = [&](const std::string& id) -> const TraCIResults& {
      const auto it = results.find(id);
      if (it == results.end()) throw SumoError("TraCI: no subscription results for person '" + id + "'");
      return it->second;
    };
    std::vector<std::string> walking;
    for (const std::string& id : ids)
      if (resultAs<libsumo::TraCIString>(of(id), libsumo::VAR_VEHICLE, "person's vehicle").value.empty())
        walking.push_back(id);
    applyPersons(walking);
    for (SumoVehicle& p : persons_) readPose(p, of(p.id));
  }

  std::string host_;
  int port_;
  int order_;
  std::unique_ptr<detail::SumoProcess> process_;
  std::unique_ptr<detail::TraciRelay> relay_;  // attached servers only
  std::string label_;
  bool gui_ = false;  // SUMO's own answer (hasGUI)
  bool broken_ = false;
  bool closed_ = false;
  double endTime_ = -1.0;
  int minExpected_ = 1;
  const libsumo::SubscriptionResults* results_ = nullptr;  // the step's, while read() runs
  bool lateral_ = true;       // SUMO moves vehicles sideways at finite speed
  detail::SignalBook signals_;  // the network's lights and where its cars give way
  bool lights() const { return reads_.nextSignal && signals_.any(reads_.priority); }
  VehicleReads subscribedWith_;  // the reads vars_ was made for
  std::vector<int> vars_;        // each vehicle's subscribed variables
  std::unordered_set<std::string> subscribed_;  // the vehicles SUMO holds a subscription of ours for
  std::unordered_set<std::string> personsSubscribed_;  // the persons likewise
};

}  // namespace

std::unique_ptr<Backend> launchTraci(const SumoLaunch& launch) {
  std::string binary = launch.sumoBinary.empty() ? (launch.gui ? "sumo-gui" : "sumo") : launch.sumoBinary;
  std::vector<std::string> args = launch.args;
  if (launch.gui) {
    args.push_back("--start");
    args.push_back("--quit-on-end");
  }
  auto process = std::make_unique<detail::SumoProcess>(binary, args, launch.logFile);
  const int port = process->port();
  return std::make_unique<TraciBackend>("localhost", port, 0, std::move(process));
}

std::unique_ptr<Backend> attachTraci(const TraciEndpoint& endpoint) {
  return std::make_unique<TraciBackend>(endpoint.host, endpoint.port, endpoint.order, nullptr);
}

}  // namespace st::cosim
