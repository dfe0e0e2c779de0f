#pragma once
// SUMO's file formats read as plain XML (no SUMO library): the network's lane geometry and the
// floating-car-data trace. SUMO's conventions become ours in sumo_conversion.hpp, as for every
// other source.
#include <cstdint>
#include <filesystem>
#include <istream>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <sthighway/frame_source.hpp>
#include <sthighway/road.hpp>
#include <sthighway/sumo_conversion.hpp>
#include <sthighway/sumo_signals.hpp>
#include <sthighway/vehicle.hpp>

namespace st::highway {

// A malformed input file: what() is "<file>:<line>: <message>".
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Lanes of a .net.xml (normal and internal edges), with their shapes and widths (SUMO's default
// 3.2 m when absent). The network's netOffset is already applied by SUMO to shapes and FCD alike.
// `leftOut`, if given, receives the ids of the lanes the geometry leaves out (sidewalks, bicycle
// lanes): a trace may still name them.
// `trafficLights`, if given, receives the number of traffic lights (<tlLogic> programs' ids).
RoadGeometry readSumoNet(const std::filesystem::path& path, std::vector<std::string>* leftOut = nullptr,
                         int* trafficLights = nullptr);

// Size and mass for vehicle types; FCD does not carry them (toVehicleTypeInfo's rule, as a live
// run reads them from SUMO). A trace's types no vType describes: guessVehicleType.
using VehicleTypes = std::map<std::string, VehicleTypeInfo>;
// Reads <vType id length width vClass decel mass|param key="mass"> from a route/additional file.
VehicleTypes readSumoVehicleTypes(const std::filesystem::path& path);

// Each vehicle's route (its edges) from a SUMO route file: SUMO's --vehroute-output (the last
// <route> of a vehicle, the one it finished on: a rerouted vehicle's earlier ones are replaced) or
// a plain route file (<vehicle route="ID"> with a top-level <route id edges>, or a nested <route
// edges>). Flows and trips are no routes (--vehroute-output writes a flow's vehicles one by one).
using VehicleRoutes = std::unordered_map<std::string, std::vector<std::string>>;
VehicleRoutes readSumoRoutes(const std::filesystem::path& path);

// A trace's frame: the vehicles at one time step (a FrameSource's frame).
using FcdFrame = Frame;

// What a trace must agree with, checked vehicle by vehicle (an InputError names file:line):
// positions inside the network's bounds grown by kOutsideMargin, lanes the network has, types
// the vType file defines. Whatever is not set is not checked; speeds and sizes no vehicle has are
// always errors.
struct FcdChecks {
  static constexpr double kOutsideMargin = 1000.0;  // m around the lanes' bounding box
  bool bounded = false;
  Vec2 lo = Vec2::Zero(), hi = Vec2::Zero();  // the lanes' bounding box
  std::vector<std::string> lanes;             // sorted lane ids
  bool lanesChecked = false;                  // a lane outside `lanes` is an error (even when it is empty)
  bool typesComplete = false;                 // a type outside the given VehicleTypes is an error
  std::string typesFile;                      // named in that error
  std::string netFile;                        // named in the bounds and lane errors
};
// The checks against a network read by readSumoNet (its lanes and the ones it left out).
FcdChecks fcdChecksFor(const RoadGeometry& road, const std::vector<std::string>& leftOut, std::string netFile);
// Speeds (m/s), accelerations (m/s^2) and vehicle sizes (m) beyond these are input errors.
inline constexpr double kFcdMaxSpeed = 200.0;
inline constexpr double kFcdMaxAcceleration = 1000.0;
inline constexpr double kFcdMaxSize = 1000.0;
// A heading (rad) beyond +-this is no heading (1e300 was taken; sin and cos lose their digits).
inline constexpr double kMaxHeading = 1000.0;
// A timestep's time beyond +-this (s, 31 years) is an input error (1e300 was a run of 1e300 s).
inline constexpr double kFcdMaxTime = 1e9;
// A network's coordinates beyond +-this (m: SUMO moves a network's origin near its lanes), lane
// widths beyond kNetMaxLaneWidth (m) and lengths beyond kNetMaxCoordinate are input errors.
inline constexpr double kNetMaxCoordinate = 1e7;
inline constexpr double kNetMaxLaneWidth = 100.0;

// Streams <timestep time=".."><vehicle id x y angle speed [type acceleration signals length
// width lane posLat] .../></timestep> frames, each vehicle through toVehicleState as a live run
// converts it. Lateral speed is not in FCD: in the sublane model it is the change of posLat over
// the step (0 on a vehicle's first frame, without posLat, or off its lane's edge). A file without
// a single <timestep> is an error (not an FCD trace), and so is a directory. Given the network
// (road, which must outlive the reader), a vehicle's lane attribute becomes its index into
// road->lanes (VehicleState::lane; -1 for a lane road lacks). A <person> on foot (not nested in
// a <vehicle>: a passenger is its vehicle's) is read alike into the same frame, after its
// predecessors in the file, with its type's body (SUMO's pedestrian defaults when the type is
// unknown), no lane, not equipped, handles drawn with the vehicles'.
class FcdReader final : public FrameSource {
 public:
  FcdReader(const std::filesystem::path& path, VehicleTypes types = {}, FcdChecks checks = {},
            const RoadGeometry* road = nullptr);
  ~FcdReader() override;
  // Fills the next frame; false at the end of the file. Throws InputError with file:line.
  bool next(FcdFrame& frame) override;
  // Reads each vehicle's next traffic light (or where it gives way) from recorded states
  // (sumo_signals.hpp), from its lane and `pos` (with `needLanes` the trace must have both
  // attributes; else a record without them has none); both must outlive the reader.
  void useSignals(const SignalLinks* links, SignalStates* states, bool needLanes = true);
  // Gives each vehicle its route from its current edge on (VehicleState::route, as a live run
  // reads it; the lane attribute places it on its route), and its next light the link between
  // its edge and the route's next. Needs the reader's network; `routes` must outlive the reader.
  void useRoutes(const VehicleRoutes* routes);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace st::highway
