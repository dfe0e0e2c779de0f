#pragma once
// Scenes shared by the highway tests: a road with a curve and a hazard, and random traffic on it.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <sthighway/vehicle.hpp>

#include "roads.hpp"

namespace st::highway {

// A straight three-lane edge, then a two-lane left-hand curve, and a pothole.
inline RoadGeometry testRoad() {
  RoadGeometry r;
  for (int i = 0; i < 3; ++i) r.lanes.push_back(laneOf("a", i, {Vec2(0, 3.2 * i), Vec2(1200.0, 3.2 * i)}));
  for (int i = 0; i < 2; ++i) {
    const double radius = 500.0 - 3.2 * i;
    std::vector<Vec2> shape;
    for (int k = 0; k <= 20; ++k) {
      const double th = 0.8 * k / 20.0;
      shape.emplace_back(1200.0 + radius * std::sin(th), 500.0 - radius * std::cos(th));
    }
    r.lanes.push_back(laneOf("b", i, std::move(shape)));
  }
  r.hazards.push_back(Hazard{"pothole", Vec2(600.0, 3.2), 0.4});
  return r;
}

// A 15 t, 12 x 2.55 m truck.
inline void makeTruck(VehicleState& v) {
  v.vehicleClass = VehicleClass::Truck;
  v.length = 12.0;
  v.width = 2.55;
  v.mass = 15000.0;
}

// Random scenes: cars on the lanes (some off-centre, some crossing markers), in jams, straddling
// cell boundaries, at rest, some braking to a stop line; three ticks, with arrivals and departures.
inline std::vector<std::vector<VehicleState>> randomScene(std::mt19937_64& rng, double cellLength) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int n = 20 + static_cast<int>(60 * U(rng));
  const double style = U(rng);  // < 0.3 jam, < 0.6 boundaries, else spread
  const double jamAt = 50 + 1000 * U(rng);
  std::vector<VehicleState> cars;
  for (int i = 0; i < n + 8; ++i) {
    VehicleState v;
    v.id = "v";
    v.id += std::to_string(i);
    const bool curve = U(rng) < 0.2;
    const int lane = static_cast<int>((curve ? 2 : 3) * U(rng));
    double along;
    if (style < 0.3) along = jamAt + 7.0 * (i / 3) + 2 * U(rng);
    else if (style < 0.6) along = cellLength * std::floor(1200 / cellLength * U(rng)) + 6 * (U(rng) - 0.5);
    else along = 1200 * U(rng);
    const double off = (U(rng) < 0.2 ? 1.6 : 0.5) * (U(rng) - 0.5) * 2;
    if (curve) {
      const double radius = 500.0 - 3.2 * lane - off;
      const double th = std::min(0.8, along / 500.0);
      v.position = Vec2(1200 + radius * std::sin(th), 500 - radius * std::cos(th));
      v.heading = th;
    } else {
      v.position = Vec2(along, 3.2 * lane + off);
      v.heading = 0.0;
    }
    v.heading += 0.05 * (U(rng) - 0.5);
    v.speed = U(rng) < 0.2 ? 0.0 : 40 * U(rng);
    v.lateralSpeed = U(rng) < 0.5 ? 0.0 : 3 * (U(rng) - 0.5);
    v.acceleration = 8 * (U(rng) - 0.6);
    if (U(rng) < 0.15) makeTruck(v);
    const double s = U(rng);
    v.signals = s < 0.1 ? kSignalLeft : s < 0.2 ? kSignalRight : kSignalNone;
    v.equipped = U(rng) < 0.9;
    // in some jams and spread scenes a quarter of the cars brake to a red light's stop line
    // (drawn from the index, so the scenes' random stream is as before)
    if ((style < 0.15 || style > 0.85) && i % 4 == 0) v.stopDistance = 1.0 + (i * 7) % 50;
    cars.push_back(v);
  }
  std::vector<std::vector<VehicleState>> ticks(3);
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < static_cast<int>(cars.size()); ++i) {
      // the first 4 extra cars arrive at tick 1, some leave at tick 2
      if (i >= n && k == 0) continue;
      if (i % 11 == 0 && k == 2) continue;
      VehicleState v = cars[i];
      v.position += 0.2 * k * v.velocity();
      ticks[k].push_back(v);
    }
  }
  return ticks;
}

}  // namespace st::highway
