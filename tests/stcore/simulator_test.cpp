#include <gtest/gtest.h>

#include <stcore/simulator.hpp>

namespace st {
namespace {

TEST(Simulator, TwoBallsHeadOn) {
  SimulatorConfig cfg;
  cfg.spaceKind = SpaceKind::Tree;
  Simulator<2> sim({{0, 0}, {10, 10}}, cfg);
  sim.addBall({2, 5}, {1, 0}, 0.5, 1.0);
  sim.addBall({8, 5}, {-1, 0}, 0.5, 1.0);
  std::vector<EventRecord> events;
  sim.run(2.5, [&](const EventRecord& e) {
    if (e.kind != EventKind::Boundary) events.push_back(e);
  });
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, EventKind::BallBall);
  EXPECT_NEAR(events[0].t, 2.5, 1e-12);
}

}  // namespace
}  // namespace st
