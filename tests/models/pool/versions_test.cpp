// Version I (one space, or none) and version II (dynamic quadtree, any df; uniform cells) must
// play the same shot: the space only decides who checks whom, never what happens.
#include <gtest/gtest.h>

#include <stpool/game.hpp>
#include <stpool/rack.hpp>

#include "pool_test_util.hpp"

namespace st::pool {
namespace {

using test::physical;

struct Variant {
  SpaceKind kind;
  int df;
  double margin = -1.0;  // cells' fat-box margin (space.margin; -1: the pool's automatic default)
  int maxDepth = -1;     // space.max_depth (-1: the pool's automatic depth)
};

const Variant kVariants[] = {{SpaceKind::None, 0},  {SpaceKind::Single, 0}, {SpaceKind::Tree, 1},
                             {SpaceKind::Tree, 2},  {SpaceKind::Tree, 5},   {SpaceKind::Tree, 10},
                             {SpaceKind::Tree, 5, -1.0, 1}, {SpaceKind::Tree, 2, -1.0, 8}, {SpaceKind::Cells, 0},
                             {SpaceKind::Cells, 0, 3.0}};

SimulatorConfig configOf(const Variant& v) {
  SpaceSpec s;
  s.kind = v.kind;
  if (v.df > 0) s.decompositionFactor = v.df;
  s.cellSize = 0.15;
  s.margin = v.margin;
  s.maxDepth = v.maxDepth;
  return simulatorConfig(s, TableSpec{}, {});
}

Scenario gappedBreak(std::uint64_t seed) {
  Scenario s;
  s.name = "break";
  Rng rng(seed);
  RackSpec rack;
  rack.gap = 2e-5;
  s.balls = standardRack(makeTable(s.table), rack, rng);
  return s;
}

// A ball-ball event is found by whichever of the two balls predicted it (a space may show the pair
// to only one of them): name it by the lower handle first.
PoolEvent canonical(PoolEvent e) {
  if (e.kind == PoolEventKind::Ball && e.other < e.ball) {
    std::swap(e.ball, e.other);
    std::swap(e.p, e.otherP);
    std::swap(e.v, e.otherV);
  }
  return e;
}

void expectSame(std::vector<PoolEvent> a, std::vector<PoolEvent> b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (auto& e : a) e = canonical(e);
  for (auto& e : b) e = canonical(e);
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].kind, b[i].kind) << what << " event " << i;
    ASSERT_EQ(a[i].ball, b[i].ball) << what << " event " << i;
    ASSERT_EQ(a[i].other, b[i].other) << what << " event " << i;
    // bit-identical: the same pair predicted from the same local times gives the same double
    ASSERT_EQ(a[i].t, b[i].t) << what << " event " << i;
    ASSERT_EQ(a[i].p, b[i].p) << what << " event " << i;
    ASSERT_EQ(a[i].v, b[i].v) << what << " event " << i;
    ASSERT_EQ(a[i].otherP, b[i].otherP) << what << " event " << i;
    ASSERT_EQ(a[i].otherV, b[i].otherV) << what << " event " << i;
  }
}

TEST(PoolVersions, GappedBreakIdenticalInEverySpace) {
  const Scenario s = gappedBreak(42);
  Shot shot;
  shot.velocity = Vec2(8.0, 0.0);
  std::vector<PoolEvent> reference;
  for (const Variant& v : kVariants) {
    Game g(s, configOf(v));
    std::vector<PoolEvent> ev;
    g.play(shot, 10.0, [&](const PoolEvent& e) { ev.push_back(e); });
    ev = physical(ev);
    if (reference.empty()) {
      reference = ev;
      ASSERT_GT(reference.size(), 80u);
      continue;
    }
    expectSame(reference, ev, std::string(toString(v.kind)) + " df " + std::to_string(v.df) + " margin " + std::to_string(v.margin));
  }
}

// The exact frozen rack (gap 0: neighbours touch up to roundoff, many contacts at once) is the
// degenerate case; the spaces must still agree on it event for event.
TEST(PoolVersions, FrozenRackBreakIdenticalInEverySpace) {
  Scenario s;
  s.name = "frozen";
  Rng rng(1);
  s.balls = standardRack(makeTable(s.table), RackSpec{}, rng);
  Shot shot;
  shot.velocity = Vec2(8.0, 0.0);
  std::vector<PoolEvent> reference;
  for (const Variant& v : kVariants) {
    Game g(s, configOf(v));
    std::vector<PoolEvent> ev;
    const ShotSummary sum = g.play(shot, 10.0, [&](const PoolEvent& e) { ev.push_back(e); });
    EXPECT_NEAR(sum.energyDrift(), 0.0, 1e-9);
    ev = physical(ev);
    if (reference.empty()) {
      reference = ev;
      ASSERT_GT(reference.size(), 80u);
      continue;
    }
    expectSame(reference, ev, std::string(toString(v.kind)) + " df " + std::to_string(v.df) + " margin " + std::to_string(v.margin));
  }
}

// 50 shots in a row, each from where the previous one left the balls: random ball, speed and
// direction (seeded), 3 s each.
TEST(PoolVersions, FiftyRandomShotsIdenticalInEverySpace) {
  const Scenario s = gappedBreak(7);
  std::vector<std::vector<PoolEvent>> runs;
  std::size_t pocketedRef = 0;
  for (const Variant& v : kVariants) {
    Game g(s, configOf(v));
    Rng rng(2024);
    std::vector<PoolEvent> ev;
    for (int k = 0; k < 50; ++k) {
      std::vector<int> onTable;
      for (int i = 0; i < static_cast<int>(g.specs().size()); ++i)
        if (g.simulator().ball(i).active) onTable.push_back(g.specs()[i].number);
      if (onTable.empty()) break;
      Shot shot;
      shot.ball = onTable[static_cast<std::size_t>(rng.uniform() * static_cast<double>(onTable.size()))];
      const double speed = rng.uniform(0.5, 8.0), angle = rng.uniform(0.0, 6.283185307179586);
      shot.velocity = speed * Vec2(std::cos(angle), std::sin(angle));
      g.play(shot, 3.0, [&](const PoolEvent& e) { ev.push_back(e); });
    }
    runs.push_back(physical(ev));
    if (runs.size() == 1) {
      pocketedRef = g.pocketed().size();
      EXPECT_GT(pocketedRef, 3u);
      ASSERT_GT(runs[0].size(), 400u);
    } else {
      EXPECT_EQ(g.pocketed().size(), pocketedRef);
      expectSame(runs[0], runs.back(), std::string(toString(v.kind)) + " df " + std::to_string(v.df) + " margin " + std::to_string(v.margin));
    }
  }
}

}  // namespace
}  // namespace st::pool
