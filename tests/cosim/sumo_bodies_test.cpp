// The bodies the coupling gives SUMO's vehicles are SUMO's own: the straight body from its back,
// `length` metres of lane behind the front (worked out here from the lanes' shapes and the lanes
// each truck drove, as MSVehicle::getBackPosition does), to its front. libsumo only: libtraci.h
// cannot share this translation unit.
#include <gtest/gtest.h>

#include <libsumo/libsumo.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "test_util.hpp"
#include <stcosim/backend.hpp>
#include <stcosim/plugin.hpp>
#include <stcosim/scenario.hpp>

namespace st::cosim {
namespace {

using namespace st::cosim::test;

// The point `offset` metres along a lane, as SUMO places it (its shape scaled to its length).
Vec2 lanePoint(const std::string& lane, double offset) {
  const auto shape = libsumo::Lane::getShape(lane).value;
  double shapeLength = 0.0;
  for (std::size_t k = 1; k < shape.size(); ++k)
    shapeLength += std::hypot(shape[k].x - shape[k - 1].x, shape[k].y - shape[k - 1].y);
  double left = offset * shapeLength / libsumo::Lane::getLength(lane);
  for (std::size_t k = 1; k < shape.size(); ++k) {
    const Vec2 a(shape[k - 1].x, shape[k - 1].y), b(shape[k].x, shape[k].y);
    const double seg = (b - a).norm();
    if (left <= seg || k + 1 == shape.size()) return a + (seg > 0.0 ? left / seg : 0.0) * (b - a);
    left -= seg;
  }
  return Vec2(shape.front().x, shape.front().y);
}

// Trucks turning at networks/intersection's corners (5.6 m and more, 10 m trucks): each step's
// body from the coupling against SUMO's back, for every truck whose back is found on a lane it
// drove, over the scenario's 600 s.
TEST(SumoBodies, ATruckInTheJunctionIsSumosBackToFront) {
  Scenario s = loadScenario(sourceDir() / "networks/intersection/scenario.yaml");
  const SumoLaunch launch{sumoArguments(s), false, "", ""};
  auto b = startLibsumo(launch);
  HighwayPlugin plugin(*b, s.plugin);
  struct Driven {
    std::vector<std::string> lanes;  // in order
    double changedAt = -1e9;         // its odometer at its last lane change (m)
  };
  std::map<std::string, Driven> driven;  // per truck
  std::size_t checked = 0, curved = 0;
  double worst = 0.0, worstFull = 0.0;
  while (b->running()) {
    b->step();
    plugin.update();
    const auto& vehicles = b->vehicles();
    for (std::size_t i = 0; i < vehicles.size(); ++i) {
      const highway::VehicleState& v = plugin.states()[i];
      if (v.vehicleClass != highway::VehicleClass::Truck) continue;
      const std::string lane = libsumo::Vehicle::getLaneID(v.id);
      const double pos = libsumo::Vehicle::getLanePosition(v.id);
      const double odometer = libsumo::Vehicle::getDistance(v.id);
      Driven& d = driven[v.id];
      // a lane change (onto a lane the last one does not lead to: on an edge, or just behind a
      // junction) moves the back onto the new lane's predecessors (SUMO's further lanes), which it
      // did not drive: its samples are left out until it has driven its length on
      if (!d.lanes.empty() && d.lanes.back() != lane) {
        bool leads = false;
        for (const libsumo::TraCIConnection& c : libsumo::Lane::getLinks(d.lanes.back()))
          leads = leads || c.approachedLane == lane || c.approachedInternal == lane;
        if (!leads) d.changedAt = odometer;
      }
      if (d.lanes.empty() || d.lanes.back() != lane) d.lanes.push_back(lane);
      const auto& lanes = d.lanes;
      // SUMO's back: `length` of lane behind the front, back through the lanes it came by
      const double length = libsumo::Vehicle::getLength(v.id);
      double back = pos - length;
      std::size_t on = lanes.size() - 1;
      while (back < 0.0 && on > 0) back += libsumo::Lane::getLength(lanes[--on]);
      if (back < 0.0 || odometer - d.changedAt < length) continue;  // behind its insertion, or a lane change
      const Vec2 sumoBack = lanePoint(lanes[on], back);
      const libsumo::TraCIPosition f = libsumo::Vehicle::getPosition(v.id);
      const Vec2 front(f.x, f.y);
      if ((front - sumoBack).norm() < length - 0.5) ++curved;
      // the back worked out here is SUMO's: its angle points from it to the front
      const Vec2 chord = front - sumoBack;
      const double angle = 90.0 - std::atan2(chord.y(), chord.x()) * 180.0 / 3.141592653589793;
      ASSERT_NEAR(std::remainder(libsumo::Vehicle::getAngle(v.id) - angle, 360.0), 0.0, 0.2) << v.id << " at " << b->time();
      const Vec2 u = v.direction();
      worst = std::max(worst, (v.position - 0.5 * v.length * u - sumoBack).norm());
      worstFull = std::max(worstFull, (front - length * u - sumoBack).norm());
      ++checked;
    }
  }
  b->close();
  EXPECT_GT(checked, 2000u);
  EXPECT_GT(curved, 100u);  // in a turn, its chord half a metre or more short of its length
  EXPECT_LT(worst, 0.1) << "laid at full length: " << worstFull;
  EXPECT_GT(worstFull, 1.0);
  std::printf("trucks: %zu steps, %zu in a turn; back off SUMO's by at most %.3f m (full length: %.3f m)\n", checked,
              curved, worst, worstFull);
}

}  // namespace
}  // namespace st::cosim
