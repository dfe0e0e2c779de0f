// Vehicles departing, arriving and teleporting within a step: at every step the backend's vehicle
// list is exactly SUMO's own list of vehicles on the road (libsumo::Vehicle::getIDList, which leaves
// out vehicles while they teleport). libsumo only: libtraci.h cannot share this translation unit.
#include <gtest/gtest.h>

#include <libsumo/libsumo.h>

#include <algorithm>
#include <map>
#include <set>

#include "test_util.hpp"
#include <stcosim/backend.hpp>
#include <stcosim/scenario.hpp>

namespace st::cosim {
namespace {

using namespace st::cosim::test;

TEST(Backends, VehicleListFollowsDeparturesArrivalsAndTeleports) {
  // a ramp car stuck at the end of the acceleration lane for 1 s is teleported past it (at
  // t = 112.7 s with seed 42: the teleport starts and ends within one step) while vehicles depart
  // and arrive; collisions would be resolved by teleporting too
  Scenario s = loadScenario(motorway());
  s.end = 130.0;
  s.collisionAction = "teleport";
  s.sumoArgs.insert(s.sumoArgs.end(), {"--time-to-teleport", "1"});
  auto b = startLibsumo(SumoLaunch{sumoArguments(s), false, "", ""});
  std::size_t departed = 0, arrived = 0, teleportStarts = 0, teleportEnds = 0, steps = 0;
  std::map<std::string, std::uint32_t> serialOf;  // until arrival
  std::size_t keptThroughTeleport = 0;
  while (b->running()) {
    b->step();
    ++steps;
    const StepEvents& ev = b->events();
    departed += ev.departed.size();
    arrived += ev.arrived.size();
    teleportStarts += ev.teleportStarted.size();
    teleportEnds += ev.teleportEnded.size();
    std::vector<std::string> ours;
    for (const auto& v : b->vehicles()) ours.push_back(v.id);
    std::vector<std::string> sumo = libsumo::Vehicle::getIDList();
    std::sort(ours.begin(), ours.end());
    std::sort(sumo.begin(), sumo.end());
    ASSERT_EQ(ours, sumo) << "t = " << b->time();
    // the list is updated in place: every value is this step's, as SUMO's getters give it; a
    // vehicle keeps its serial through a teleport, serials on the road are distinct
    std::set<std::uint32_t> serials;
    for (const auto& id : ev.teleportEnded) keptThroughTeleport += serialOf.count(id);  // seen before
    for (const auto& v : b->vehicles()) {
      const auto p = libsumo::Vehicle::getPosition(v.id);
      ASSERT_EQ(v.x, p.x) << v.id;
      ASSERT_EQ(v.y, p.y) << v.id;
      ASSERT_EQ(v.angle, libsumo::Vehicle::getAngle(v.id)) << v.id;
      ASSERT_EQ(v.speed, libsumo::Vehicle::getSpeed(v.id)) << v.id;
      ASSERT_EQ(v.acceleration, libsumo::Vehicle::getAcceleration(v.id)) << v.id;
      ASSERT_EQ(v.signals, libsumo::Vehicle::getSignals(v.id)) << v.id;
      ASSERT_EQ(v.type, libsumo::Vehicle::getTypeID(v.id)) << v.id;
      ASSERT_EQ(b->vehicleType(v.typeIndex).id, v.type) << v.id;
      ASSERT_TRUE(serials.insert(v.serial).second) << v.id;
      const auto [it, fresh] = serialOf.try_emplace(v.id, v.serial);
      ASSERT_EQ(it->second, v.serial) << v.id;
    }
    for (const auto& id : ev.arrived) serialOf.erase(id);
  }
  b->close();
  EXPECT_EQ(steps, 1300u);
  EXPECT_GT(departed, 150u);
  EXPECT_GT(arrived, 20u);
  EXPECT_GT(teleportStarts, 0u);
  EXPECT_GT(teleportEnds, 0u);
  EXPECT_GT(keptThroughTeleport, 0u);
}

}  // namespace
}  // namespace st::cosim
