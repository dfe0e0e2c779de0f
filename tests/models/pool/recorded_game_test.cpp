// A game played through the Game API and written out (writeScenarioYaml: the layout plus the
// shots taken) replays through `stsim pool` to the same events bit for bit: what `stsim pool
// serve` offers as a download.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <sstream>

#include <stpool/game.hpp>
#include <stpool/report.hpp>
#include <stpool/scenario.hpp>
#include <stpool/scenario_writer.hpp>

#include "pool_test_util.hpp"

namespace st::pool {
namespace {

using test::runStsim;
using test::slurp;
using test::tempDir;

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(const Vec2& a, const Vec2& b) { return sameBits(a.x(), b.x()) && sameBits(a.y(), b.y()); }

Shot polar(int ball, double speed, double degrees, double until = -1.0) {
  const double rad = degrees * std::numbers::pi / 180.0;
  return Shot{ball, speed * Vec2(std::cos(rad), std::sin(rad)), until};
}

// Plays `shots` on a Game built from `layout` as a caller of the API would (not through
// playScenario), records the events, writes layout + shots, replays that file with the CLI and
// returns both events.csv texts. A shot whose ball was pocketed strikes the lowest-numbered ball
// still on the table instead, as a player would.
std::pair<std::string, std::string> playAndReplay(Scenario layout, std::vector<Shot> shots, const std::string& name) {
  layout.shots.clear();
  Game game(layout, simulatorConfig(layout));
  RunRecord rec;
  for (Shot& shot : shots) {
    for (int h = game.handleOf(shot.ball); h >= 0 && !game.simulator().ball(h).active; h = -1)
      for (const BallSpec& b : game.specs())
        if (game.simulator().ball(game.handleOf(b.number)).active) {
          shot.ball = b.number;
          break;
        }
    const double limit = shot.until > 0 ? shot.until : layout.until;
    rec.shots.push_back(game.play(shot, limit, [&](const PoolEvent& e) { rec.events.push_back(e); }));
  }
  std::ostringstream played;
  writeEventsCsv(played, rec, game);

  Scenario recorded = layout;
  recorded.shots = shots;
  const auto dir = tempDir("recorded_" + name);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "game.yaml") << [&] {
    std::ostringstream os;
    writeScenarioYaml(os, recorded);
    return os.str();
  }();
  const auto r = runStsim("pool " + (dir / "game.yaml").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.code, 0) << r.out;
  return {played.str(), slurp(dir / "out" / "events.csv")};
}

TEST(RecordedGame, FrictionRackOnTheQuadtreeReplaysBitForBit) {
  // practice.yaml: a seeded gapped rack, rolling resistance, version II; odd angles so that
  // nothing is round
  const Scenario base = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/practice.yaml");
  const auto [played, replayed] =
      playAndReplay(base, {polar(0, 7.3, 0.37), polar(0, 2.1, 101.3), Shot{0, Vec2(-1.3, 0.4123), -1.0}}, "friction");
  EXPECT_GT(std::count(played.begin(), played.end(), '\n'), 300);
  EXPECT_EQ(played, replayed);
}

TEST(RecordedGame, TimeLimitsOtherBallsAndVersionOneReplayBitForBit) {
  // frictionless: shots end at their own limits (the balls are stopped where they stand) and the
  // second strikes ball 5, wherever the first left it
  Scenario base = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/break.yaml");
  base.space.kind = SpaceKind::Single;
  base.until = 3.0;
  const auto [played, replayed] = playAndReplay(base, {polar(0, 8.7, -0.9, 1.7), polar(5, 3.3, 211.0)}, "limits");
  EXPECT_NE(played.find(",stop,"), std::string::npos);
  EXPECT_EQ(played, replayed);
}

TEST(RecordedGame, WrittenScenarioReadsBackToTheSameBits) {
  Scenario s = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/practice.yaml");
  s.name = "a \"quoted\" name: with colons";
  s.balls[3].velocity = Vec2(0.1, -1.0 / 3.0);
  s.balls[4].colour = Colour::Black;
  s.shots = {polar(0, 7.3, 0.37, 2.5), Shot{3, Vec2(1e-9, -std::numbers::pi), -1.0}};
  s.space.maxDepth = 7;
  std::ostringstream os;
  writeScenarioYaml(os, s);
  const Scenario back = parseScenario(os.str(), "written.yaml");
  EXPECT_EQ(back.name, s.name);
  ASSERT_EQ(back.balls.size(), s.balls.size());
  for (std::size_t i = 0; i < s.balls.size(); ++i) {
    EXPECT_EQ(back.balls[i].number, s.balls[i].number);
    EXPECT_TRUE(sameBits(back.balls[i].position, s.balls[i].position)) << i;
    EXPECT_TRUE(sameBits(back.balls[i].velocity, s.balls[i].velocity)) << i;
    EXPECT_TRUE(sameBits(back.balls[i].radius, s.balls[i].radius)) << i;
    EXPECT_EQ(back.balls[i].colour, s.balls[i].colour);
    EXPECT_EQ(back.balls[i].pattern, s.balls[i].pattern);
  }
  ASSERT_EQ(back.shots.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(back.shots[k].ball, s.shots[k].ball);
    EXPECT_TRUE(sameBits(back.shots[k].velocity, s.shots[k].velocity)) << k;
    EXPECT_TRUE(sameBits(back.shots[k].until, s.shots[k].until)) << k;
  }
  EXPECT_TRUE(sameBits(back.friction, s.friction));
  EXPECT_TRUE(sameBits(back.until, s.until));
  EXPECT_EQ(back.space.kind, s.space.kind);
  EXPECT_EQ(back.space.decompositionFactor, s.space.decompositionFactor);
  EXPECT_EQ(back.space.maxDepth, s.space.maxDepth);
  // a cells space keeps its own keys (a quadtree's file has none of them: the reader refuses them)
  s.space.kind = SpaceKind::Cells;
  s.space.cellSize = 0.1 / 3.0;
  s.space.margin = 3.0;
  std::ostringstream cells;
  writeScenarioYaml(cells, s);
  const Scenario backCells = parseScenario(cells.str(), "written.yaml");
  EXPECT_EQ(backCells.space.kind, SpaceKind::Cells);
  EXPECT_TRUE(sameBits(backCells.space.cellSize, s.space.cellSize));
  EXPECT_TRUE(sameBits(backCells.space.margin, s.space.margin));
}

TEST(RecordedGame, ShotVelocityKeyAndItsErrors) {
  const char* table = "table: {width: 2.54, height: 1.27}\nballs:\n  - {number: 0, position: [0.6, 0.6]}\n";
  const Scenario s = parseScenario(std::string(table) + "shots:\n  - {velocity: [1.5, -0.25]}\n", "v.yaml");
  ASSERT_EQ(s.shots.size(), 1u);
  EXPECT_EQ(s.shots[0].velocity, Vec2(1.5, -0.25));
  auto error = [&](const std::string& shots) {
    try {
      parseScenario(std::string(table) + shots, "v.yaml");
    } catch (const ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_NE(error("shots:\n  - {velocity: [1, 0], speed: 1, angle: 0}\n").find("shots[0]: give one of cue, speed and angle, or velocity"),
            std::string::npos);
  EXPECT_NE(error("shots:\n  - {velocity: [1]}\n").find("shots[0].velocity: must be a pair"), std::string::npos);
  EXPECT_NE(error("shots:\n  - {velocity: [.nan, 0]}\n").find("shots[0].velocity[0]: must be finite"), std::string::npos);
  EXPECT_NE(error("shots:\n  - {velocity: [2000, 0]}\n").find("shots[0]: speed must be at most 1000 m/s"), std::string::npos);
}

}  // namespace
}  // namespace st::pool
