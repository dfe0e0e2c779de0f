// The Fig. 13 study's cases: every space plays the same physics (same collisions), the report's
// "one space" costs exactly what no space costs in stcore, and a quadtree needs fewer checks
// than all pairs once there are many balls.
#include <gtest/gtest.h>

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
