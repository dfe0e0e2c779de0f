#include <sthighway/vehicle.hpp>

#include <algorithm>
#include <cctype>

#include <stcore/hash.hpp>

namespace st::highway {

const char* toString(VehicleClass c) {
  switch (c) {
    case VehicleClass::Passenger: return "passenger";
    case VehicleClass::Truck: return "truck";
    case VehicleClass::Bus: return "bus";
    case VehicleClass::Motorcycle: return "motorcycle";
    case VehicleClass::Emergency: return "emergency";
    case VehicleClass::Other: return "other";
    case VehicleClass::Bicycle: return "bicycle";
    case VehicleClass::Pedestrian: return "pedestrian";
  }
  return "other";
}

VehicleClass vehicleClassFromName(std::string_view name) {
  std::string s(name);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (s == "passenger" || s == "private" || s == "taxi" || s == "evehicle" || s == "car" ||
      s == "passenger/sedan" || s == "passenger/hatchback" || s == "passenger/wagon" || s == "passenger/van")
    return VehicleClass::Passenger;
  if (s == "truck" || s == "trailer" || s == "delivery" || s == "lorry" || s == "hgv") return VehicleClass::Truck;
  if (s == "bus" || s == "coach") return VehicleClass::Bus;
  if (s == "motorcycle" || s == "moped") return VehicleClass::Motorcycle;
  if (s == "emergency" || s == "authority" || s == "army") return VehicleClass::Emergency;
  if (s == "bicycle") return VehicleClass::Bicycle;
  if (s == "pedestrian" || s == "person") return VehicleClass::Pedestrian;
  return VehicleClass::Other;
}

ClassDefaults classDefaults(VehicleClass c) {
  switch (c) {
    case VehicleClass::Passenger: return {5.0, 1.8, 1500.0};
    case VehicleClass::Truck: return {12.0, 2.55, 15000.0};
    case VehicleClass::Bus: return {12.0, 2.55, 12000.0};
    case VehicleClass::Motorcycle: return {2.2, 0.9, 250.0};
    case VehicleClass::Emergency: return {6.5, 2.2, 3500.0};
    case VehicleClass::Other: return {5.0, 1.8, 1500.0};
    case VehicleClass::Bicycle: return {1.6, 0.65, 90.0};
    case VehicleClass::Pedestrian: return {0.215, 0.478, 70.0};
  }
  return {5.0, 1.8, 1500.0};
}

double equipmentDraw(std::uint64_t seed, std::string_view id) {
  return unitInterval(splitmixMix(fnv1a(id, kHashBasis ^ seed) + kSplitmixGamma));
}

}  // namespace st::highway
