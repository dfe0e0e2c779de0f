#pragma once
// The SUMO coupling behind one interface. Two backends:
//   libsumo  SUMO embedded in this process; state read with direct getters (the cheapest way);
//   libtraci a TraCI client, either launching `sumo`/`sumo-gui` itself or attaching to a SUMO that
//            already runs with --remote-port (as one of --num-clients clients, with a client order);
//            state read through one variable subscription per vehicle, so a step is one round trip.
// Both report the same things in SUMO's own conventions (front-bumper position, navigational
// degrees); conversion to ours happens once, in conversions.hpp. Errors (SUMO refusing a file, a
// dropped connection) are thrown as SumoError with a one-line message.
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <sthighway/sumo_conversion.hpp>

namespace st::cosim {

struct SumoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class BackendKind : std::uint8_t { Libsumo, Traci };
const char* toString(BackendKind k);

// SUMO's signal bits (TraCI "signal states"), as the one conversion names them.
using highway::kSumoBlinkerLeft;
using highway::kSumoBlinkerRight;

// One vehicle on the road after a step, as SUMO reports it: the record the one conversion reads
// (position, angle, speeds, acceleration, signals: every step; acceleration and signals only if
// asked, VehicleReads) and what the backend keeps beside it. Its id, type and serial are read
// when it appears.
struct SumoVehicle : highway::SumoVehicleRecord {
  std::string id;
  std::string type;           // vType id
  int typeIndex = -1;         // Backend::vehicleType(typeIndex) is this vehicle's vType
  // 0, 1, 2, ... in order of first appearance, kept through a teleport, new after an arrival:
  // an index for per-vehicle data that needs no lookup by id
  std::uint32_t serial = 0;
  // Its route (VehicleReads::route): the index of its current edge in it (inside a junction, of
  // the edge it left), the route's id, its edges (read again only when the id changes: SUMO
  // gives a rerouted vehicle a new route), and a number that changes whenever they are read
  // (unique in the backend's life: a per-vehicle cache keyed by it is never stale).
  int routeIndex = -1;
  std::string routeId;
  std::vector<std::string> route;
  std::uint64_t routeVersion = 0;
};

// A vehicle type, read once per type and cached by the backend.
struct SumoVehicleType {
  std::string id;
  std::string vClass;            // SUMO vClass name, e.g. "passenger", "truck"
  double length = 0.0;           // m
  double width = 0.0;            // m
  std::optional<double> mass;    // from a <param key="mass"> (kg), if present
  double decel = std::numeric_limits<double>::quiet_NaN();  // m/s^2, SUMO's decel (normal maximum braking)
};

// A lane of the network (SUMO's centre-line shape, in driving direction).
struct SumoLane {
  std::string id;
  std::string edge;
  int index = 0;       // 0 = rightmost
  double width = 0.0;  // m
  double length = 0.0; // m, SUMO's (positions and speeds along the lane are in it)
  std::vector<std::pair<double, double>> shape;
  bool internal = false;  // a junction-internal lane (id starting with ':')
};

struct SumoCollision {
  std::string collider, victim, type, lane;
  double colliderSpeed = 0.0, victimSpeed = 0.0;  // m/s
  double pos = 0.0;                               // on the lane (m)
  double time = 0.0;                              // s
  // The two bodies' distance at the report (m; 0 touching or overlapping), from the vehicles'
  // states of that step (HighwayPlugin); NaN when unknown (collisions read from SUMO's file after
  // the run). SUMO's default rule (--collision.mingap-factor 1) also reports a follower closer
  // than its minGap with the bodies apart: contact() tells the two apart.
  double gap = std::numeric_limits<double>::quiet_NaN();
  // The bodies touch (within kContactGap); an unknown gap counts as SUMO reported it, a contact.
  bool contact() const;
};

// What happened in the last step.
struct StepEvents {
  std::vector<std::string> departed;
  std::vector<std::string> arrived;
  std::vector<std::string> teleportStarted;
  std::vector<std::string> teleportEnded;
  std::vector<SumoCollision> collisions;
  // The vehicles SUMO found in a collision this step (TraCI runs, whose collision reports come
  // from SUMO's file after the run: their bodies are kept to tell contacts from minGap violations).
  std::vector<std::string> colliding;
};

// The per-step variables read besides position, angle and speed (and lateral speed, which is
// read only when SUMO can move vehicles sideways). Each is one more call per vehicle and step into
// libsumo, whose getters cost a lookup by id each. What is not read is 0.
struct VehicleReads {
  bool acceleration = true;  // used by the constant-acceleration motion model only
  bool signals = true;       // blinkers: used by the lane-marker check only
  bool route = true;         // the route: used by the road-aware prediction only
  bool nextSignal = true;    // the next traffic light's state and distance (networks with lights only)
  // the priority rules too: where a car gives way at a minor link or a left turn's wait point
  // (nextSignal m, g, =; networks with such links only)
  bool priority = true;
  // persons on foot (Backend::persons): their list each step (one call, nothing on a network
  // without persons) and position, angle and speed of each
  bool persons = true;
  bool operator==(const VehicleReads&) const = default;
};

struct Rgba {
  std::uint8_t r = 255, g = 255, b = 255, a = 255;
};

// How to start SUMO: the options after the executable (e.g. {"-c", "x.sumocfg", "--seed", "42"}).
struct SumoLaunch {
  std::vector<std::string> args;
  bool gui = false;                 // sumo-gui instead of sumo (launched via TraCI)
  std::string logFile;              // SUMO's console output of a launched process goes here ("" = /dev/null)
  std::string sumoBinary;           // "" = "sumo" / "sumo-gui" from PATH
};

// Where to attach to a SUMO started elsewhere with --remote-port PORT --num-clients N.
struct TraciEndpoint {
  std::string host = "localhost";
  int port = 0;
  int order = 1;   // this client's order among the N clients (TraCI setOrder); ignored if N = 1
};

class Backend {
 public:
  virtual ~Backend() = default;
  Backend(const Backend&) = delete;
  Backend& operator=(const Backend&) = delete;

  virtual BackendKind kind() const = 0;
  // Advances SUMO by one step and reads the new state (vehicles(), events(), time()).
  // Throws SumoError (e.g. the connection dropped).
  void step();
  // Reads the current state without advancing SUMO: for users who call Simulation::step()
  // themselves (the plugin's own API).
  virtual void read() = 0;

  double time() const { return time_; }           // s, simulation time after the last step
  double deltaT() const { return deltaT_; }       // s, SUMO's step length
  // Vehicles on the road (teleporting ones excluded), in departure order.
  const std::vector<SumoVehicle>& vehicles() const { return vehicles_; }
  // Persons on foot (VehicleReads::persons), in order of first appearance: position, angle and
  // speed as SUMO reports them (signals, route and lights stay empty). A person riding a vehicle
  // is not among them (it is that vehicle's); it returns, with its serial, when it walks again.
  // Serials are drawn with the vehicles' (one space: a person's never equals a vehicle's).
  const std::vector<SumoVehicle>& persons() const { return persons_; }
  const StepEvents& events() const { return events_; }
  // CPU seconds (this thread's) the reads after each step took so far, by part: the vehicles'
  // variables, the traffic lights (their states and each vehicle's next light) and the persons.
  // Libsumo sessions only (a TraCI session's reads are SUMO's work behind the socket): zeros.
  struct ReadCost {
    double vehicles = 0.0, lights = 0.0, persons = 0.0;
  };
  const ReadCost& readCost() const { return readCost_; }
  // True while SUMO still expects vehicles or the end time is not reached.
  virtual bool running() = 0;

  // Which optional variables are read from the next read() on (default: all).
  void setReads(const VehicleReads& reads);
  const VehicleReads& reads() const { return reads_; }

  // A vType, read from SUMO on first use and cached (references stay valid).
  const SumoVehicleType& vehicleType(const std::string& typeId);
  const SumoVehicleType& vehicleType(int index) const { return types_[static_cast<std::size_t>(index)]; }
  int vehicleTypeCount() const { return static_cast<int>(types_.size()); }
  virtual std::vector<SumoLane> lanes() = 0;

  // Actions.
  // The colour the vehicle is drawn in (its own, else its type's).
  virtual Rgba color(const std::string& vehicleId) = 0;
  virtual void setColor(const std::string& vehicleId, Rgba c) = 0;
  // Brings the vehicle to `speed` linearly over `duration` s, at that rate even beyond its vType's
  // comfortable decel (SUMO's safe-speed rule still applies).
  virtual void slowDown(const std::string& vehicleId, double speed, double duration) = 0;
  // Holds the vehicle at `speed` (m/s) until called with a negative speed, which gives it back to
  // SUMO's driver model.
  virtual void setSpeed(const std::string& vehicleId, double speed) = 0;
  virtual void addPolygon(const std::string& id, const std::vector<std::pair<double, double>>& shape, Rgba c,
                          bool fill, int layer) = 0;
  // The ids of the polygons SUMO holds (to check what addPolygon drew).
  virtual std::vector<std::string> polygonIds() = 0;
  // True when SUMO says it runs with a GUI (sumo-gui).
  virtual bool hasGui() = 0;

  // Ends the session (closes SUMO or the connection); idempotent; never throws.
  virtual void close() noexcept = 0;
  // A short description for reports, e.g. "libsumo" or "libtraci localhost:8813 (client 2)".
  virtual std::string describe() const = 0;

 protected:
  Backend() = default;
  virtual void advance() = 0;
  virtual SumoVehicleType readVehicleType(const std::string& typeId) = 0;
  // The vType id of a vehicle that just appeared.
  virtual std::string readTypeId(const std::string& vehicleId) = 0;
  // The vType id of a person that just appeared.
  virtual std::string readPersonTypeId(const std::string& personId) = 0;
  // Makes persons_ the persons in `walking` (this step's persons on foot): new ones appended,
  // the rest removed; the records' values are the caller's to read.
  void applyPersons(const std::vector<std::string>& walking);
  // Applies the step's departures, teleports and arrivals to vehicles_ in place: departures are
  // appended, a teleport removes a vehicle until it is placed again (appended then), an arrival
  // removes it; a vehicle seen for the first time gets its serial and type.
  void applyEvents(const StepEvents& e);

  double time_ = 0.0;
  double deltaT_ = 0.0;
  std::vector<SumoVehicle> vehicles_;
  std::vector<SumoVehicle> persons_;
  StepEvents events_;
  VehicleReads reads_;
  std::uint64_t routeReads_ = 0;  // SumoVehicle::routeVersion's source
  ReadCost readCost_;

 private:
  void appear(const std::string& id);
  void leave(const std::string& id);
  int typeIndexOf(const std::string& typeId);
  struct Known {
    std::uint32_t serial = 0;
    int typeIndex = -1;
    bool onRoad = false;
    std::uint64_t seen = 0;  // persons: the applyPersons call that last listed it
  };
  // a new record of a vehicle or person that appeared: id, type, serial; its values are read after
  SumoVehicle record(const std::string& id, const Known& k) const;
  std::unordered_map<std::string, Known> known_;  // vehicles until they arrive
  std::unordered_map<std::string, Known> knownPersons_;  // every person seen (persons have ids of their own)
  std::uint64_t personCalls_ = 0;
  std::uint32_t nextSerial_ = 0;
  std::deque<SumoVehicleType> types_;  // a deque: references handed out stay valid
  std::unordered_map<std::string, int> typeIndex_;
};

// libsumo: starts SUMO in this process. Only one embedded SUMO can run per process.
std::unique_ptr<Backend> startLibsumo(const SumoLaunch& launch);
// libsumo, SUMO already started in this process by the caller (libsumo::Simulation::start): the
// caller steps SUMO and calls read(); close() does not close SUMO.
std::unique_ptr<Backend> attachLibsumo();
// libtraci: launches `sumo`/`sumo-gui` as a child process in its own process group (so a Ctrl-C at
// the terminal reaches us, not SUMO) and connects to it.
std::unique_ptr<Backend> launchTraci(const SumoLaunch& launch);
// libtraci: connects to a SUMO already running with --remote-port.
std::unique_ptr<Backend> attachTraci(const TraciEndpoint& endpoint);

}  // namespace st::cosim
