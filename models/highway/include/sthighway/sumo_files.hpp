#pragma once
// SUMO's file formats read as plain XML (no SUMO library): the network's lane geometry and the
// floating-car-data trace. Conversion of SUMO's conventions (front-bumper position, navigational
// degrees, signal bits) to ours happens here, once.
#include <cstdint>
#include <filesystem>
#include <istream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <sthighway/road.hpp>
#include <sthighway/vehicle.hpp>

namespace st::highway {

// A malformed input file: what() is "<file>:<line>: <message>".
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Lanes of a .net.xml (normal and internal edges), with their shapes and widths (SUMO's default
// 3.2 m when absent). The network's netOffset is already applied by SUMO to shapes and FCD alike.
RoadGeometry readSumoNet(const std::filesystem::path& path);

// Size and mass for vehicle types; FCD does not carry them. Unknown types use classDefaults of
// the class guessed from the type name (e.g. "truck" in the name -> Truck).
struct VehicleTypeInfo {
  VehicleClass vehicleClass = VehicleClass::Passenger;
  double length = 5.0;
  double width = 1.8;
  double mass = 1500.0;
};
using VehicleTypes = std::map<std::string, VehicleTypeInfo>;
// Reads <vType id length width vClass mass|param key="mass"> from a route/additional file.
VehicleTypes readSumoVehicleTypes(const std::filesystem::path& path);
VehicleTypeInfo guessVehicleType(const std::string& typeName);

struct FcdFrame {
  double time = 0.0;
  std::vector<VehicleState> vehicles;
};

// Streams <timestep time=".."><vehicle id x y angle speed [type acceleration signals length
// width] .../></timestep> frames. Lateral speed is not in FCD: it is estimated from the change of
// the centre across frames (0 on a vehicle's first frame).
class FcdReader {
 public:
  FcdReader(const std::filesystem::path& path, VehicleTypes types = {});
  ~FcdReader();
  // Fills the next frame; false at the end of the file. Throws InputError with file:line.
  bool next(FcdFrame& frame);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace st::highway
