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
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace st::cosim {

struct SumoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class BackendKind : std::uint8_t { Libsumo, Traci };
const char* toString(BackendKind k);

// SUMO's signal bits (TraCI "signal states"): bit 0 right blinker, bit 1 left blinker.
inline constexpr int kSumoBlinkerRight = 1;
inline constexpr int kSumoBlinkerLeft = 2;

// One vehicle on the road after a step, as SUMO reports it.
struct SumoVehicle {
  std::string id;
  std::string type;           // vType id
  double x = 0.0, y = 0.0;    // front-bumper centre (m)
  double angle = 0.0;         // navigational degrees: 0 = north, clockwise
  double speed = 0.0;         // longitudinal (m/s)
  double lateralSpeed = 0.0;  // to the left (m/s), sublane model only
  double acceleration = 0.0;  // longitudinal (m/s^2)
  int signals = 0;            // SUMO signal bits
};

// A vehicle type, read once per type and cached by the backend.
struct SumoVehicleType {
  std::string id;
  std::string vClass;            // SUMO vClass name, e.g. "passenger", "truck"
  double length = 0.0;           // m
  double width = 0.0;            // m
  std::optional<double> mass;    // from a <param key="mass"> (kg), if present
};

// A lane of the network (SUMO's centre-line shape, in driving direction).
struct SumoLane {
  std::string id;
  std::string edge;
  int index = 0;       // 0 = rightmost
  double width = 0.0;  // m
  std::vector<std::pair<double, double>> shape;
  bool internal = false;  // a junction-internal lane (id starting with ':')
};

struct SumoCollision {
  std::string collider, victim, type, lane;
  double colliderSpeed = 0.0, victimSpeed = 0.0;  // m/s
  double pos = 0.0;                               // on the lane (m)
  double time = 0.0;                              // s
};

// What happened in the last step.
struct StepEvents {
  std::vector<std::string> departed;
  std::vector<std::string> arrived;
  std::vector<std::string> teleportStarted;
  std::vector<std::string> teleportEnded;
  std::vector<SumoCollision> collisions;
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
  const StepEvents& events() const { return events_; }
  // True while SUMO still expects vehicles or the end time is not reached.
  virtual bool running() = 0;

  virtual const SumoVehicleType& vehicleType(const std::string& typeId) = 0;
  virtual std::vector<SumoLane> lanes() = 0;

  // Actions.
  // The colour the vehicle is drawn in (its own, else its type's).
  virtual Rgba color(const std::string& vehicleId) = 0;
  virtual void setColor(const std::string& vehicleId, Rgba c) = 0;
  virtual void slowDown(const std::string& vehicleId, double speed, double duration) = 0;
  virtual void addPolygon(const std::string& id, const std::vector<std::pair<double, double>>& shape, Rgba c,
                          bool fill, int layer) = 0;
  virtual bool hasGui() = 0;

  // Ends the session (closes SUMO or the connection); idempotent; never throws.
  virtual void close() noexcept = 0;
  // A short description for reports, e.g. "libsumo" or "libtraci localhost:8813 (client 2)".
  virtual std::string describe() const = 0;

 protected:
  Backend() = default;
  virtual void advance() = 0;

  double time_ = 0.0;
  double deltaT_ = 0.0;
  std::vector<SumoVehicle> vehicles_;
  StepEvents events_;
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
