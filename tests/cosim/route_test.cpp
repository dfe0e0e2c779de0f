// The routes the backend reads against the route file and SUMO's own account of where each
// vehicle is (libsumo::Vehicle::getRoadID). libsumo only: libtraci.h cannot share this
// translation unit (backend_test.cpp compares the routes libtraci reads with these).
#include <gtest/gtest.h>

#include <libsumo/libsumo.h>

#include <string>
#include <vector>

#include "test_util.hpp"
#include <stcosim/backend.hpp>
#include <stcosim/plugin.hpp>
#include <stcosim/scenario.hpp>

namespace st::cosim {
namespace {

using namespace st::cosim::test;

// The routes the backend reads are the route file's (networks/motorway/motorway.rou.xml: the
// main flows' "upstream accel downstream", the ramp's "ramp accel downstream"), the route index
// names the edge SUMO has the vehicle on, and the road-aware prediction follows them.
TEST(Backends, RoutesAreTheRouteFilesAndThePredictionFollowsThem) {
  Scenario s = loadScenario(motorway());
  s.end = 60.0;
  ASSERT_EQ(s.plugin.monitor.prediction, highway::Prediction::Road);
  const SumoLaunch launch{sumoArguments(s), false, "", ""};
  auto b = startLibsumo(launch);
  HighwayPlugin plugin(*b, s.plugin);
  EXPECT_TRUE(b->reads().route);
  const std::vector<std::string> main{"upstream", "accel", "downstream"}, ramp{"ramp", "accel", "downstream"};
  std::size_t checked = 0, onRamp = 0;
  while (b->running()) {
    b->step();
    plugin.update();
    for (const SumoVehicle& v : b->vehicles()) {
      ASSERT_EQ(v.route, v.id.rfind("ramp", 0) == 0 ? ramp : main) << v.id;
      ASSERT_GE(v.routeIndex, 0);
      const std::string road = libsumo::Vehicle::getRoadID(v.id);
      if (road[0] != ':') {
        EXPECT_EQ(v.route[static_cast<std::size_t>(v.routeIndex)], road) << v.id;
      }
      ++checked;
      onRamp += v.route == ramp;
    }
  }
  EXPECT_GT(checked, 10000u);
  EXPECT_GT(onRamp, 500u);
  const auto& c = plugin.monitor().counters();
  EXPECT_GT(c.routePredicted, 0.95 * static_cast<double>(c.roadPredicted));
  b->close();

  // the straight line has no use for them
  Scenario st = s;
  st.plugin.monitor.prediction = highway::Prediction::Straight;
  auto d = startLibsumo(launch);
  HighwayPlugin straight(*d, st.plugin);
  EXPECT_FALSE(d->reads().route);
  d->step();
  straight.update();
  for (const SumoVehicle& v : d->vehicles()) EXPECT_TRUE(v.route.empty());
  d->close();
}

}  // namespace
}  // namespace st::cosim
