#pragma once
// Safe time (§4.1, §4.3): a warning is raised when TTC <= t_safe. The default rule is the
// stopping-time argument t_safe = t_reaction + m * v_closing / (2 * F_brake), so it grows with
// momentum; F_brake depends on the vehicle class, hence a truck gets a longer safe time than a car
// at the same speed. Car-car and car-road (curb, lane marker, hazard) have their own reaction time.
#include <algorithm>
#include <array>

#include <sthighway/vehicle.hpp>

namespace st::highway {

struct SafeTimeConfig {
  double vehicleReactionTime = 1.0;  // s, car-car
  double roadReactionTime = 0.5;     // s, car-curb / lane marker / hazard
  // Braking force per VehicleClass (N), indexed by the enum. Defaults: passenger 12 kN
  // (1.5 t at 8 m/s^2), truck 75 kN (15 t at 5 m/s^2), bus 72 kN (12 t at 6 m/s^2),
  // motorcycle 2.25 kN (250 kg at 9 m/s^2), emergency 31.5 kN (3.5 t at 9 m/s^2), other 12 kN,
  // bicycle 360 N (90 kg at 4 m/s^2), pedestrian 210 N (70 kg stopping at 3 m/s^2).
  std::array<double, kVehicleClassCount> brakeForce{12000.0, 75000.0, 72000.0, 2250.0, 31500.0, 12000.0, 360.0, 210.0};

  double safeTime(double reactionTime, double mass, double closingSpeed, VehicleClass c) const {
    return safeTimeOf(reactionTime, mass, closingSpeed, 2.0 * brakeForce[static_cast<int>(c)]);
  }
  // the same rule with 2 F_brake given (for a caller that keeps it per vehicle)
  static double safeTimeOf(double reactionTime, double mass, double closingSpeed, double twiceBrakeForce) {
    return reactionTime + mass * std::max(0.0, closingSpeed) / twiceBrakeForce;
  }
  // m / (2 F_brake) of a car (s per m/s): how much its safe time grows per m/s of closing speed
  double brakeRatio(double mass, VehicleClass c) const { return mass / (2.0 * brakeForce[static_cast<int>(c)]); }
  // The safe time at closing speed `closing` from a car's brake ratio: every prune's look-ahead
  // (with the largest ratio and speed it must cover). Within rounding of safeTimeOf (m v / 2F
  // against (m / 2F) v): a caller that must hold the exact safe time grows it by
  // tol::kBoundRelativeSlop.
  static double safeTimeBound(double reactionTime, double brakeRatio, double closing) {
    return reactionTime + brakeRatio * closing;
  }
  double vehicleSafeTime(double mass, double closingSpeed, VehicleClass c) const {
    return safeTime(vehicleReactionTime, mass, closingSpeed, c);
  }
  double roadSafeTime(double mass, double closingSpeed, VehicleClass c) const {
    return safeTime(roadReactionTime, mass, closingSpeed, c);
  }
};

}  // namespace st::highway
