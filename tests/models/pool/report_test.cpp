// Every JSON the pool writes (summary.json, the animation's data) is JSON a real parser reads,
// whatever numbers the run record holds: NaN and infinities come out as null (JSON has neither).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include <stpool/game.hpp>
#include <stpool/report.hpp>
#include <stpool/scenario.hpp>

#include "pool_test_util.hpp"

namespace st::pool {
namespace {

// one ball crossing the table for a second, no pockets
Scenario oneBall() {
  Scenario s = test::oneTable(false);
  s.balls.push_back(test::ball(0, Vec2(0.6, 0.6), Vec2(3.0, 0.0)));
  s.until = 1.0;
  return s;
}

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// a played run with non-finite numbers put where a broken run could leave them
RunRecord brokenRun(Game& game, const Scenario& s) {
  RunRecord run = playScenario(game, s);
  EXPECT_FALSE(run.events.empty());
  EXPECT_FALSE(run.shots.empty());
  PoolEvent e = run.events.front();
  e.kind = PoolEventKind::Cushion;
  e.t = 0.25;
  e.p = Vec2(kNan, 0.5);
  e.v = Vec2(kInf, -kInf);
  run.events.push_back(e);
  run.shots.front().keEnd = kNan;
  run.shots.front().momentumEnd = Vec2(kInf, 1.0);
  run.wallSeconds = kInf;
  return run;
}

// what `write` makes of a played one-ball run broken by brokenRun
std::string brokenOutput(void (*write)(std::ostream&, const RunRecord&, const Game&)) {
  const Scenario s = oneBall();
  Game game(s, simulatorConfig(s));
  const RunRecord run = brokenRun(game, s);
  std::ostringstream os;
  write(os, run, game);
  return os.str();
}

// the text between "const D = " and the ";" that ends its line
std::string animationData(const std::string& html) {
  const std::string head = "const D = ";
  const auto at = html.find(head);
  EXPECT_NE(at, std::string::npos);
  const auto end = html.find(";\n", at);
  return html.substr(at + head.size(), end - at - head.size());
}

TEST(PoolReport, SummaryJsonWritesNonFiniteNumbersAsNull) {
  const std::string text = brokenOutput(writeSummaryJson);
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(text)) << text;
  EXPECT_TRUE(j["wall_time_s"].is_null());
  EXPECT_TRUE(j["shots"][0]["kinetic_energy_final_J"].is_null());
  EXPECT_TRUE(j["shots"][0]["momentum_final"][0].is_null());
  EXPECT_EQ(j["shots"][0]["momentum_final"][1].get<double>(), 1.0);
  EXPECT_EQ(j["balls"].get<int>(), 1);
}

TEST(PoolReport, AnimationDataIsJsonWithNonFiniteNumbersAsNull) {
  const std::string data = animationData(brokenOutput(writeAnimationHtml));
  nlohmann::json d;
  ASSERT_NO_THROW(d = nlohmann::json::parse(data)) << data;
  EXPECT_EQ(d["width"].get<double>(), 2.54);
  EXPECT_EQ(d["height"].get<double>(), 1.27);
  // the broken keyframe is the ball's last: [0.25, null, 0.5, null, null]
  const auto& k = d["balls"][0]["k"];
  ASSERT_GE(k.size(), 2u);
  EXPECT_EQ(k[0][1].get<double>(), 0.6);  // the first keyframe: where the ball was placed
  EXPECT_EQ(k[0][3].get<double>(), 3.0);
  const auto& last = k[k.size() - 1];
  EXPECT_EQ(last[0].get<double>(), 0.25);
  EXPECT_TRUE(last[1].is_null());
  EXPECT_EQ(last[2].get<double>(), 0.5);
  EXPECT_TRUE(last[3].is_null());
  EXPECT_TRUE(last[4].is_null());
}

}  // namespace
}  // namespace st::pool
