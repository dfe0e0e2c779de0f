// What one scenario can ask of the machine is bounded, and a run can be stopped: each ends with a
// message naming the key, and what was played before stays in the record.
#include <gtest/gtest.h>

#include <stpool/game.hpp>
#include <stpool/report.hpp>
#include <stpool/scenario.hpp>

namespace st::pool {
namespace {

// One ball bouncing between the cushions without friction: events for as long as it is asked.
const char* kBouncer = R"(table: {width: 2.54, height: 1.27, pockets: false}
balls: [{number: 0, position: [0.6, 0.6], velocity: [3.0, 0.0]}]
until: 1e12
)";

TEST(PoolLimits, AHugeTimeLimitStopsAtTheEventBoundNamingUntil) {
  // until: 1e12 ran for a minute, then died of std::bad_alloc naming nothing
  const Scenario s = parseScenario(kBouncer, "s.yaml");
  Game game(s, simulatorConfig(s));
  const RunRecord run = playScenario(game, s);
  EXPECT_EQ(run.events.size(), kMaxEvents);
  EXPECT_EQ(run.error.rfind("until: stopped after 2000000 events at t = ", 0), 0u) << run.error;
  // the events kept are the run's first ones: a cushion hit every (2.54 - 2r) / 3 s up to the last
  std::size_t cushions = 0;
  for (const PoolEvent& e : run.events) cushions += e.kind == PoolEventKind::Cushion ? 1 : 0;
  const double period = (2.54 - 2.0 * s.balls[0].radius) / 3.0;
  EXPECT_NEAR(static_cast<double>(cushions), run.events.back().t / period, 2.0);
}

TEST(PoolLimits, AStopRequestEndsTheRunAtAnEvent) {
  const Scenario s = parseScenario(kBouncer, "s.yaml");
  Game game(s, simulatorConfig(s));
  int polls = 0;
  const RunRecord run = playScenario(game, s, 100.0, [&] { return ++polls > 10; });
  EXPECT_EQ(run.events.size(), 10u);
  EXPECT_EQ(run.error.rfind("interrupted at t = ", 0), 0u) << run.error;
}

TEST(PoolLimits, ACellSizeTooSmallForTheTableNamesTheKey) {
  try {
    parseScenario("table: {width: 2.54, height: 1.27}\nrack: standard\nspace: {kind: cells, cell_size: 1e-9}\n", "s.yaml");
    FAIL() << "accepted";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("s.yaml:3:33: space.cell_size: too small for the table", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace st::pool
