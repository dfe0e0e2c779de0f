// The Fig. 13 study's cases: every space plays the same physics (same collisions), the report's
// "one space" costs exactly what no space costs in stcore, and a quadtree needs fewer checks
// than all pairs once there are many balls.
#include <gtest/gtest.h>

#include <algorithm>
#include <utility>

#include <stpool/study.hpp>

namespace st::pool {
namespace {

SpaceSpec spaceOf(SpaceKind kind, int df = 5) {
  SpaceSpec s;
  s.kind = kind;
  s.decompositionFactor = df;
  s.cellSize = 4.0 * kBallRadius;
  return s;
}

TEST(Fig13Study, EverySpaceSeesTheSameCollisions) {
  for (int mobile : {2, 15}) {
    for (std::uint64_t seed : {1u, 2u}) {
      const StudyRun ns = runFig13Case(mobile, spaceOf(SpaceKind::None), seed);
      const StudyRun one = runFig13Case(mobile, spaceOf(SpaceKind::Single), seed);
      ASSERT_GT(ns.collisions, 10u);
      // no boundaries in one space: the same work as no space at all
      EXPECT_EQ(one.checks, ns.checks);
      EXPECT_EQ(one.events, ns.events);
      EXPECT_EQ(one.collisions, ns.collisions);
      for (const SpaceSpec& sp : {spaceOf(SpaceKind::Tree, 10), spaceOf(SpaceKind::Tree, 5), spaceOf(SpaceKind::Tree, 2),
                                  spaceOf(SpaceKind::Cells)}) {
        const StudyRun r = runFig13Case(mobile, sp, seed);
        EXPECT_EQ(r.collisions, ns.collisions) << toString(sp.kind) << " df " << sp.decompositionFactor;
        EXPECT_GT(r.events, ns.events);  // the regions' crossings come on top
      }
    }
  }
}

// The report's claim, in the event-driven counting: a space that subdivides itself checks fewer
// pairs than no space, at every number of moving balls (sums over seeds, as the study prints).
TEST(Fig13Study, SubdividingSpaceChecksFewerPairsThanNoSpace) {
  for (int mobile : {2, 5, 15}) {
    std::uint64_t ns = 0, df5 = 0, df10 = 0;
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      ns += runFig13Case(mobile, spaceOf(SpaceKind::None), seed).checks;
      df5 += runFig13Case(mobile, spaceOf(SpaceKind::Tree, 5), seed).checks;
      df10 += runFig13Case(mobile, spaceOf(SpaceKind::Tree, 10), seed).checks;
    }
    EXPECT_LT(df5, ns) << mobile << " moving";
    EXPECT_LT(df10, ns) << mobile << " moving";
  }
}

// The report's per-step counting against a count written here: after every event, the pairs that
// share a leaf (visited through forEachPair) with a ball moving, and no space: all such pairs.
TEST(Fig13Study, ReportCountingIsThePairsSharingALeafWithAMover) {
  for (SpaceKind kind : {SpaceKind::None, SpaceKind::Tree}) {
    SimulatorConfig cfg;
    cfg.spaceKind = kind;
    cfg.rule.decompositionFactor = 2;
    cfg.rule.maxDepth = 4;
    Simulator<2> sim({{0, 0}, {4, 2}}, cfg);
    for (const auto& [n, off] : {std::pair{Vec2(1, 0), 0.0}, {Vec2(1, 0), 4.0}, {Vec2(0, 1), 0.0}, {Vec2(0, 1), 2.0}})
      sim.addWall({n, off});
    const Vec2 at[] = {{0.5, 0.5}, {1.5, 0.5}, {2.5, 1.5}, {3.5, 1.5}, {0.5, 1.5}, {3.0, 0.4}, {2.0, 1.0}};
    for (int k = 0; k < 7; ++k) sim.addBall(at[k], k % 3 == 0 ? Vec2(0.7, 0.3 * k - 1) : Vec2::Zero(), 0.1, 1.0);
    int events = 0;
    sim.run(20.0, [&](const EventRecord&) {
      ++events;
      const double t = sim.now();
      auto moving = [&](int b) { return sim.ball(b).active && (sim.ball(b).velocityAt(t).array() != 0.0).any(); };
      std::uint64_t expected = 0;
      if (sim.space()) {
        sim.space()->forEachPair([&](int a, int b) {
          // a pair sharing several leaves is recomputed in each
          const auto& la = sim.space()->leavesOf(a);
          std::uint64_t shared = 0;
          for (int leaf : sim.space()->leavesOf(b)) shared += std::count(la.begin(), la.end(), leaf);
          if (moving(a) || moving(b)) expected += shared;
        });
      } else {
        for (int a = 0; a < 7; ++a)
          for (int b = a + 1; b < 7; ++b)
            if (sim.ball(a).active && sim.ball(b).active && (moving(a) || moving(b))) ++expected;
      }
      ASSERT_EQ(reportChecksNow(sim), expected) << toString(kind) << " event " << events;
    });
    EXPECT_GT(events, 20);
  }
}

TEST(Fig13Study, QuadtreeChecksFewerPairsInABigBox) {
  const StudyRun ns = runBoxCase(400, spaceOf(SpaceKind::None), 1, 0.5);
  const StudyRun tree = runBoxCase(400, spaceOf(SpaceKind::Tree, 5), 1, 0.5);
  EXPECT_EQ(tree.collisions, ns.collisions);
  EXPECT_GT(ns.collisions, 400u);
  // all pairs: every prediction checks ~n balls; the tree: about df
  EXPECT_LT(tree.checks * 5, ns.checks);
}

}  // namespace
}  // namespace st::pool
