// The embedded backend: SUMO runs inside this process; vehicle state comes from direct getters.
// Measured in SUMO 1.15 (bench/cosim_overhead, cosim/README.md): libsumo's subscriptions fill a
// map of shared_ptr results per vehicle and variable in every step and cost more than the getters;
// each getter costs a lookup by id (std::map) in SUMO's vehicle dictionary, so only what is needed
// is read (VehicleReads) and the id, type and serial are read once per vehicle.

#include <libsumo/libsumo.h>

#include <memory>

#include "backend_common.hpp"
#include "sumo_process.hpp"
#include <stcore/cpu_clock.hpp>
#include <stcosim/backend.hpp>

namespace st::cosim {
namespace {

class LibsumoBackend final : public Backend {
 public:
  explicit LibsumoBackend(bool owns) : owns_(owns) {
    deltaT_ = libsumo::Simulation::getDeltaT();
    time_ = libsumo::Simulation::getTime();
    lateral_ = detail::movesSideways<libsumo::Simulation>();  // else one getter per vehicle and step saved
    signals_.load<libsumo::TrafficLight, libsumo::Lane>();
    // vehicles already on the road when we attach
    StepEvents initial;
    initial.departed = libsumo::Vehicle::getIDList();
    applyEvents(initial);
    readVehicles();
  }
  ~LibsumoBackend() override { close(); }

  BackendKind kind() const override { return BackendKind::Libsumo; }

  void read() override {
    try {
      time_ = libsumo::Simulation::getTime();
      events_.departed = libsumo::Simulation::getDepartedIDList();
      events_.arrived = libsumo::Simulation::getArrivedIDList();
      events_.teleportStarted = libsumo::Simulation::getStartingTeleportIDList();
      events_.teleportEnded = libsumo::Simulation::getEndingTeleportIDList();
      events_.collisions.clear();
      for (const auto& c : libsumo::Simulation::getCollisions())
        events_.collisions.push_back({c.collider, c.victim, c.type, c.lane, c.colliderSpeed, c.victimSpeed, c.pos, time_});
      applyEvents(events_);
      readVehicles();
    } catch (const libsumo::TraCIException& e) {
      throw SumoError(std::string("libsumo: ") + e.what());
    }
  }

  bool running() override {
    return libsumo::Simulation::getMinExpectedNumber() > 0 &&
           (libsumo::Simulation::getEndTime() < 0 || time_ < libsumo::Simulation::getEndTime() - 0.5 * deltaT_);
  }

  std::vector<SumoLane> lanes() override { return detail::readLanes<libsumo::Lane>(); }

  Rgba color(const std::string& id) override {
    return detail::readColor<libsumo::Vehicle, libsumo::VehicleType>(id);
  }
  void setColor(const std::string& id, Rgba c) override {
    libsumo::Vehicle::setColor(id, libsumo::TraCIColor(c.r, c.g, c.b, c.a));
  }
  void slowDown(const std::string& id, double speed, double duration) override {
    detail::slowDownAtCommandedRate<libsumo::Vehicle>(id, speed, duration);
  }
  void setSpeed(const std::string& id, double speed) override { libsumo::Vehicle::setSpeed(id, speed); }
  void addPolygon(const std::string& id, const std::vector<std::pair<double, double>>& shape, Rgba c, bool fill,
                  int layer) override {
    detail::addPolygon<libsumo::Polygon, libsumo::TraCIPositionVector, libsumo::TraCIColor>(id, shape, c, fill, layer);
  }
  std::vector<std::string> polygonIds() override { return libsumo::Polygon::getIDList(); }
  bool hasGui() override { return false; }

  void close() noexcept override {
    if (!open_) return;
    open_ = false;
    if (!owns_) return;
    try {
      libsumo::Simulation::close();
    } catch (...) {
    }
  }
  std::string describe() const override { return owns_ ? "libsumo" : "libsumo (attached)"; }

 protected:
  SumoVehicleType readVehicleType(const std::string& typeId) override {
    return detail::readVehicleType<libsumo::VehicleType>(typeId);
  }
  std::string readTypeId(const std::string& vehicleId) override { return libsumo::Vehicle::getTypeID(vehicleId); }
  std::string readPersonTypeId(const std::string& personId) override { return libsumo::Person::getTypeID(personId); }

  void advance() override {
    try {
      libsumo::Simulation::step();
    } catch (const libsumo::TraCIException& e) {
      throw SumoError(std::string("libsumo: ") + e.what());
    } catch (const std::exception& e) {  // ProcessError from SUMO's core
      throw SumoError(std::string("SUMO: ") + e.what());
    }
  }

 private:
  // the per-step values, in place
  void readVehicles() {
    const bool lights = reads_.nextSignal && signals_.any(reads_.priority);
    const double t0 = threadCpuSeconds();
    for (SumoVehicle& v : vehicles_) {
      const auto p = libsumo::Vehicle::getPosition(v.id);
      v.x = p.x;
      v.y = p.y;
      v.angle = libsumo::Vehicle::getAngle(v.id);
      v.speed = libsumo::Vehicle::getSpeed(v.id);
      if (lateral_) v.lateralSpeed = libsumo::Vehicle::getLateralSpeed(v.id);
      if (reads_.acceleration) v.acceleration = libsumo::Vehicle::getAcceleration(v.id);
      if (reads_.signals) v.signals = libsumo::Vehicle::getSignals(v.id);
      if (reads_.route || lights) {
        v.routeIndex = libsumo::Vehicle::getRouteIndex(v.id);
        std::string routeId = libsumo::Vehicle::getRouteID(v.id);
        if (routeId != v.routeId) {
          v.route = libsumo::Vehicle::getRoute(v.id);
          v.routeId = std::move(routeId);
          v.routeVersion = ++routeReads_;
        }
      }
    }
    // the lights after the vehicles (each car's next light needs its route), timed apart
    const double t1 = threadCpuSeconds();
    if (lights) {
      signals_.readStates<libsumo::TrafficLight>();
      for (SumoVehicle& v : vehicles_)
        signals_.next(v, [&] {
          return std::pair<std::string, double>(libsumo::Vehicle::getLaneID(v.id), libsumo::Vehicle::getLanePosition(v.id));
        }, reads_.priority);
    }
    const double t2 = threadCpuSeconds();
    readCost_.vehicles += t1 - t0;
    readCost_.lights += t2 - t1;
    if (!reads_.persons) return;
    applyPersons(detail::walkingPersons<libsumo::Person>());
    for (SumoVehicle& p : persons_) {
      const auto at = libsumo::Person::getPosition(p.id);
      p.x = at.x;
      p.y = at.y;
      p.angle = libsumo::Person::getAngle(p.id);
      p.speed = libsumo::Person::getSpeed(p.id);
    }
    readCost_.persons += threadCpuSeconds() - t2;
  }

  bool owns_;
  bool open_ = true;
  bool lateral_ = true;  // SUMO moves vehicles sideways at finite speed (sublane model or lane-change duration)
  detail::SignalBook signals_;  // the network's lights and where its cars give way
};

}  // namespace

std::unique_ptr<Backend> startLibsumo(const SumoLaunch& launch) {
  ensureSumoHome();
  std::vector<std::string> cmd{"sumo"};
  cmd.insert(cmd.end(), launch.args.begin(), launch.args.end());
  // SUMO prints some start errors itself (option checks: "Error: The end time should be after
  // the begin time.") and throws a bare "Process Error"; others come only in the exception, over
  // several lines. Its stderr is held during the start and both become one line.
  std::string what;
  std::string printed;
  {
    detail::StderrCapture capture;
    try {
      libsumo::Simulation::start(cmd);
    } catch (const std::exception& e) {
      what = e.what();
    }
    printed = capture.finish();
  }
  if (what.empty()) return std::make_unique<LibsumoBackend>(true);
  std::string config;
  for (std::size_t i = 0; i + 1 < launch.args.size(); ++i)
    if (launch.args[i] == "-c") config = " " + launch.args[i + 1];
  throw SumoError("SUMO failed to start" + config + ": " + detail::sumoErrorLine(printed, what));
}

std::unique_ptr<Backend> attachLibsumo() {
  if (!libsumo::Simulation::isLoaded()) throw SumoError("libsumo: no simulation is loaded in this process");
  return std::make_unique<LibsumoBackend>(false);
}

}  // namespace st::cosim
