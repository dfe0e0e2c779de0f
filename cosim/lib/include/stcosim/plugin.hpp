#pragma once
// The smart-car plugin: after each SUMO step it reads every vehicle's state through a Backend,
// converts it (conversions.hpp), runs the highway monitor (cells, handoff, detectors, safe time) and
// acts on the warnings in SUMO (colour and/or brake).
//
// For users who drive SUMO themselves with libsumo:
//     libsumo::Simulation::start({"sumo", "-c", "x.sumocfg"});
//     auto plugin = st::cosim::HighwayPlugin::forLibsumo(config);
//     while (libsumo::Simulation::getMinExpectedNumber() > 0) {
//       libsumo::Simulation::step();
//       plugin->step();
//       for (const auto& w : plugin->takeFinished()) ...;
//     }
//     plugin->finish();
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include <stcore/box2.hpp>
#include <sthighway/brake_policy.hpp>
#include <sthighway/monitor.hpp>
#include <stcosim/backend.hpp>
#include <stcosim/collisions.hpp>
#include <stcosim/conversions.hpp>

namespace st::cosim {

// Which vehicles are smart cars: those whose vType is listed, plus each other vehicle with
// probability `penetration` (a deterministic draw from seed and vehicle id).
struct SmartCars {
  double penetration = 1.0;
  std::vector<std::string> types;
  std::uint64_t seed = 42;
};

enum class Action : std::uint8_t { None, Color, Brake };
const char* toString(Action a);
bool parseAction(const std::string& text, Action& out);  // "none", "color", "brake"

struct ActionConfig {
  Action action = Action::Color;
  // Colour: yellow while a warning holds, red while TTC < redFraction * safe time; the vehicle's
  // own colour comes back when the warning ends. Colours are also applied with Action::Brake.
  // The yellow is gold (255, 215, 0), not SUMO's default vehicle colour (255, 255, 0), so a warned
  // car is never mistaken for one that has no colour of its own.
  Rgba warningColor{255, 215, 0, 255};
  Rgba dangerColor{255, 0, 0, 255};
  double redFraction = 0.5;
  // Brake: on a car-car warning, the smart car brakes as highway::brakeFor decides (a slower foe
  // ahead in its path, down to the foe's speed) with SUMO's slowDown.
  highway::BrakeSettings brake;
};

// A scripted incident, for studies of what the warnings and actions do when a leader brakes hard:
// at `time` the vehicle nearest to (x, y) brakes to `speed` at `deceleration` (beyond its vType's
// comfortable decel if need be), holds that speed for `hold` seconds, then drives on under SUMO's
// driver model. Picking by place rather than by id keeps an incident where it is meant to be
// whatever the seed's departures.
struct Incident {
  double time = 0.0;          // s
  double x = 0.0, y = 0.0;    // m, network coordinates
  double speed = 0.0;         // m/s
  double deceleration = 8.0;  // m/s^2
  double hold = 30.0;         // s
};

struct PluginConfig {
  highway::MonitorConfig monitor;
  SmartCars smart;
  ActionConfig actions;
  std::vector<Incident> incidents;
};

struct PluginCounters {
  std::uint64_t steps = 0;
  std::uint64_t departed = 0, arrived = 0, teleports = 0;
  std::uint64_t equipped = 0;        // distinct smart cars seen
  std::uint64_t colorChanges = 0;
  std::uint64_t brakeCommands = 0;
  std::uint64_t incidents = 0;  // scripted incidents started
  // SUMO's collisions (needs --collision.action warn). With "warn" SUMO reports a pair again at
  // every step it still overlaps, so `collisionSteps` counts those reports and `collisions` the
  // distinct collisions: a pair counts again only after a step without contact.
  std::uint64_t collisions = 0;
  std::uint64_t collisionSteps = 0;
  // Of SUMO's collisions, the contacts (the bodies touch: SumoCollision::contact, counted as
  // `collisions` over the touching reports only) and the minGap violations (the distinct runs of
  // reports with the bodies apart; one that went on to touch is a contact too). Set by the run
  // once every report is in (runScenario).
  std::uint64_t contacts = 0;
  std::uint64_t mingapViolations = 0;
};

class HighwayPlugin {
 public:
  // Reads the network's lanes from the backend and builds the monitor; tells the backend which
  // optional variables the configuration needs (VehicleReads). Throws std::invalid_argument for a
  // bad configuration, SumoError for a SUMO failure.
  HighwayPlugin(Backend& backend, PluginConfig config);
  ~HighwayPlugin();
  // A plugin on the libsumo simulation the caller started in this process; it owns its backend.
  static std::unique_ptr<HighwayPlugin> forLibsumo(PluginConfig config);

  // Reads the state SUMO is in now (call after Simulation::step()) and updates.
  void step();
  // Updates from the state the backend already holds (the runner steps the backend itself):
  // prepare(), detect(), act().
  void update();
  // update()'s stages, for a caller that runs detection beside SUMO's next step (DetectionStage):
  // prepare and act talk to SUMO (its thread); detect touches only the monitor and reads states().
  void prepare();  // convert the backend's vehicles into states(), count, run scripted incidents
  void detect();   // the monitor's step on states()
  void act();      // colour / brake on the monitor's alerts (colour also a step late: DetectionStage)
  // Closes every open warning at the current time.
  void finish();

  std::vector<highway::Warning> takeFinished() { return monitor_.takeFinished(); }
  // The conflicts settled since the last call (HighwayMonitor::takeConflicts).
  void takeConflicts(std::vector<highway::Conflict>& out) { monitor_.takeConflicts(out); }
  // Hindsight's near misses and unsignalled crossings since the last call (HighwayMonitor::takeEvents).
  void takeEvents(std::vector<highway::HindsightEvent>& out) { monitor_.takeEvents(out); }
  // Each episode's TTC and DRAC per tick (HighwayMonitor::recordTrajectories, takeTrajectories).
  void recordTrajectories(bool on) { monitor_.recordTrajectories(on); }
  void takeTrajectories(std::vector<highway::TrajectoryPoint>& out) { monitor_.takeTrajectories(out); }
  std::vector<highway::Warning> openWarnings() const { return monitor_.openWarnings(); }
  std::span<const highway::Alert> alerts() const { return monitor_.alerts(); }
  // SUMO collisions since the last call.
  std::vector<SumoCollision> takeCollisions();
  // The bodies of the vehicles SUMO named colliding (StepEvents::colliding), step by step, and a
  // collision report's gap from them (NaN when one is not among them): how a report read from
  // SUMO's file after the run is told a contact or a minGap violation.
  struct CollidingBody {
    double time;
    std::string id;
    Box2 box;
  };
  double collidingGap(const SumoCollision& c, double stepLength) const;

  // The converted states of the last update: the backend's vehicles in their order, then its
  // persons on foot (foes, equipped only if their vType is a smart type).
  const std::vector<highway::VehicleState>& states() const { return states_; }
  const highway::HighwayMonitor& monitor() const { return monitor_; }
  // for the run's writer (highway::TickFiles), which takes what the monitor finished
  highway::HighwayMonitor& monitor() { return monitor_; }
  const PluginCounters& counters() const { return counters_; }
  const PluginConfig& config() const { return config_; }
  Backend& backend() { return backend_; }

  // Draws every cell's extent as an unfilled polygon (ids "stsim_cell_<n>") in SUMO; visible in
  // sumo-gui. Returns the number of "stsim_cell_" polygons SUMO reports holding afterwards.
  int drawCells();

 private:
  HighwayPlugin(std::unique_ptr<Backend>&& owned, Backend& backend, PluginConfig config,
                const highway::RoadGeometry& road);
  void runIncidents();
  bool inIncident(std::uint32_t serial) const;  // braking or held by a scripted incident

  std::unique_ptr<Backend> owned_;
  Backend& backend_;
  PluginConfig config_;
  highway::HighwayMonitor monitor_;
  std::unordered_map<std::string, int> edgeIndex_;  // SUMO edge id -> index into edgeIds(road)
  std::vector<highway::VehicleState> states_;
  highway::PathBodies bodies_;  // each vehicle's body along its path, by its serial
  std::size_t vehicleStates_ = 0;  // states_[0, this) are vehicles, the rest persons
  double time_ = 0.0;  // s, of states_
  // per vType (by the backend's type index): converted once, and whether it is a smart type
  struct TypeInfo {
    bool known = false;
    bool smart = false;
    VehicleTypeInfo info;
  };
  std::vector<TypeInfo> types_;
  const TypeInfo& typeInfo(int typeIndex);
  // per vehicle, by its serial (SumoVehicle::serial): equipment decided once, the colour painted
  struct PerVehicle {
    std::int8_t equipped = -1;  // -1 not decided yet
    std::uint8_t level = 0;     // 0 own colour, 1 warning, 2 danger
    bool painted = false;       // `original` read (at its first warning)
    Rgba original;
    std::uint64_t onRoadAt = 0, alertedAt = 0;  // the act() that found it on the road, alerted
    std::uint64_t routeVersion = 0;  // of SumoVehicle::route, converted into
    std::vector<int> route;          // its edges as indices (-1: not in the network's lanes)
  };
  std::vector<PerVehicle> perVehicle_;
  std::vector<std::uint32_t> serials_;  // per state index: its vehicle's serial
  std::uint64_t acts_ = 0;  // act() calls so far
  std::vector<SumoCollision> collisions_;
  // the distance of a collision's two bodies in states_ (m); NaN if one is not there
  double bodyGap(const SumoCollision& c) const;
  std::vector<CollidingBody> collidingBodies_;
  std::unordered_map<std::string, double> collidingSince_;  // id -> when SUMO last named it colliding
  static constexpr double kCollidingWatch = 30.0;            // s its body is kept after
  CollisionCounter collisionCounter_;
  // config_.incidents' progress, by index
  struct IncidentRun {
    enum class Phase : std::uint8_t { Pending, Braking, Holding, Done } phase = Phase::Pending;
    std::string vehicle;
    std::uint32_t serial = 0;
    double until = 0.0;  // s, end of the current phase
  };
  std::vector<IncidentRun> incidentRuns_;
  PluginCounters counters_;
};

}  // namespace st::cosim
