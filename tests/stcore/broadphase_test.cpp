// The broadphases against brute force written here (and "none", the brute force behind the
// interface, against the others), on random scenes: candidate pairs and
// box queries are exactly "shares a leaf" computed from the leaf boxes, and cover every pair of
// overlapping boxes; a region tree's event times against the analytic time a disc first touches
// the next leaf's wall (straight and slowing); and, in a running simulation, after every event,
// each leaf's members recounted from the balls' positions and the tree against a fresh build.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <stcore/simulator.hpp>
#include <stcore/space.hpp>

#include "boxes.hpp"
#include "test_scale.hpp"
#include <stcore/tolerances.hpp>

namespace st {
namespace {

using Pairs = std::set<std::pair<int, int>>;

using test::clampTo;
using test::overlapsOpen;

// A random scene: boxes of every size from a speck to most of the world, a fifth of them snapped
// to the tree's split planes and the grid's faces, some reaching past the bounds.
template <int D>
std::vector<Aabb<D>> randomScene(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> pos(-5, 105), unit(0, 1);
  std::vector<Aabb<D>> boxes;
  for (int k = 0; k < n; ++k) {
    Vec<D> c;
    for (int i = 0; i < D; ++i) c[i] = pos(rng);
    const double u = unit(rng);
    const double half = u < 0.05 ? 1e-9 : u < 0.1 ? 40.0 * unit(rng) : 0.05 + 3.0 * unit(rng);
    Aabb<D> b = boundsOf<D>(c, half);
    if (rng() % 5 == 0) {
      const double grid = (rng() & 1) ? 100.0 / 32 : 10.0;
      for (int i = 0; i < D; ++i) {
        const double cells = std::max(1.0, std::round((b.max[i] - b.min[i]) / grid));
        b.min[i] = std::round(b.min[i] / grid) * grid;
        b.max[i] = b.min[i] + cells * grid;
      }
    }
    if (rng() % 20 == 0) b.max[0] = b.min[0];  // flat
    boxes.push_back(b);
  }
  return boxes;
}

// Pairs and box visits of one space against the brute force of its own leaves.
template <int D>
::testing::AssertionResult matchesBruteForce(const Space<D>& s, const std::vector<Aabb<D>>& boxes, std::mt19937_64& rng) {
  const Aabb<D> bounds = s.bounds();
  const bool grid = s.kind() == SpaceKind::Cells;
  const std::vector<int> leaves = s.leaves();
  std::vector<Aabb<D>> leafBox;
  for (int leaf : leaves) leafBox.push_back(s.leafBounds(leaf));
  const int n = static_cast<int>(boxes.size());
  // listed leaves by brute force: closed boxes (trees, the list); a grid's cells are half open, so
  // a box ending on a face may or may not be listed beyond it: must <= listed <= may
  std::vector<std::set<int>> must(n), may(n);
  for (int id = 0; id < n; ++id) {
    const Aabb<D> b = clampTo(boxes[id], bounds);
    for (std::size_t l = 0; l < leaves.size(); ++l) {
      if (leafBox[l].overlaps(b)) may[id].insert(leaves[l]);
      if (grid ? overlapsOpen(leafBox[l], b) : leafBox[l].overlaps(b)) must[id].insert(leaves[l]);
    }
    const std::set<int> listed(s.leavesOf(id).begin(), s.leavesOf(id).end());
    if (!std::includes(listed.begin(), listed.end(), must[id].begin(), must[id].end()) ||
        !std::includes(may[id].begin(), may[id].end(), listed.begin(), listed.end()))
      return ::testing::AssertionFailure() << toString(s.kind()) << ": object " << id << " listed in the wrong leaves";
  }
  // the pairs: exactly those sharing a listed leaf, each once, a < b
  Pairs expected;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      const auto& la = s.leavesOf(a);
      const std::set<int> sa(la.begin(), la.end());
      for (int leaf : s.leavesOf(b))
        if (sa.count(leaf)) {
          expected.insert({a, b});
          break;
        }
    }
  std::vector<std::pair<int, int>> got;
  s.forEachPair([&](int a, int b) { got.push_back({a, b}); });
  const Pairs gotSet(got.begin(), got.end());
  if (gotSet.size() != got.size()) return ::testing::AssertionFailure() << toString(s.kind()) << ": a pair visited twice";
  for (const auto& [a, b] : got)
    if (!(a < b)) return ::testing::AssertionFailure() << toString(s.kind()) << ": pair not ordered";
  if (gotSet != expected)
    return ::testing::AssertionFailure() << toString(s.kind()) << ": " << gotSet.size() << " pairs, brute force " << expected.size();
  // every pair of overlapping boxes is a candidate (the truth a broadphase exists to keep)
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      if (clampTo(boxes[a], bounds).overlaps(clampTo(boxes[b], bounds)) && !gotSet.count({a, b}))
        return ::testing::AssertionFailure() << toString(s.kind()) << ": overlapping " << a << ", " << b << " not a candidate";
  // box queries: the objects of the leaves the box touches (a grid: between the open and closed)
  std::uniform_real_distribution<double> pos(-20, 120), size(0, 30);
  for (int q = 0; q < 20; ++q) {
    Vec<D> c;
    for (int i = 0; i < D; ++i) c[i] = pos(rng);
    const Aabb<D> box = clampTo(boundsOf<D>(c, size(rng)), bounds);
    std::vector<int> visit;
    s.forEachInBox(box, [&](int id) { visit.push_back(id); });
    const std::set<int> visitSet(visit.begin(), visit.end());
    if (visitSet.size() != visit.size()) return ::testing::AssertionFailure() << "box query visits an object twice";
    std::set<int> lo, hi;
    for (std::size_t l = 0; l < leaves.size(); ++l) {
      const bool closed = leafBox[l].overlaps(box);
      const bool open = grid ? overlapsOpen(leafBox[l], box) : closed;
      for (int id : s.objectsIn(leaves[l])) {
        if (closed) hi.insert(id);
        if (open) lo.insert(id);
      }
    }
    if (!std::includes(visitSet.begin(), visitSet.end(), lo.begin(), lo.end()) ||
        !std::includes(hi.begin(), hi.end(), visitSet.begin(), visitSet.end()))
      return ::testing::AssertionFailure() << toString(s.kind()) << ": box query differs from the leaves it touches";
    for (int id = 0; id < n; ++id)
      if (box.overlaps(clampTo(boxes[id], bounds)) && !grid && !visitSet.count(id))
        return ::testing::AssertionFailure() << "box query misses overlapping object " << id;
  }
  return ::testing::AssertionSuccess();
}

template <int D>
void everyBroadphaseMatchesBruteForce(unsigned seed, int scenes) {
  std::mt19937_64 rng(seed);
  const Aabb<D> world{Vec<D>::Zero(), Vec<D>::Constant(100)};
  int divided = 0;
  for (int scene = 0; scene < scenes; ++scene) {
    const int n = 5 + static_cast<int>(rng() % 60);
    const std::vector<Aabb<D>> boxes = randomScene<D>(rng, n);
    SpaceRule rule;
    rule.decompositionFactor = 1 + static_cast<int>(rng() % 6);
    rule.maxDepth = 7;
    rule.cellSize = 3.0 + static_cast<double>(rng() % 20);
    for (SpaceKind kind : {SpaceKind::Single, SpaceKind::Tree, SpaceKind::Cells}) {
      Space<D> s(kind, world, rule);
      for (int id = 0; id < n; ++id) s.insert(id, boxes[id]);
      ASSERT_TRUE(matchesBruteForce(s, boxes, rng)) << "scene " << scene;
      if (kind == SpaceKind::Tree) divided += s.divided() ? 1 : 0;
      EXPECT_EQ(s.divided(), s.leafCount() > 1);
      EXPECT_EQ(static_cast<int>(s.leaves().size()), s.leafCount());
    }
  }
  EXPECT_GT(divided, scenes / 2);  // the trees were divided, not one leaf each
}

// "none" is the brute force behind the same interface: on random scenes, after inserts, updates
// and removals, its pairs are every pair of present objects, its neighbours every other object, and
// the pairs whose boxes overlap, found through it, are those found through every other kind.
template <int D>
void noneGivesThePairsOfEveryKind(unsigned seed, int scenes) {
  std::mt19937_64 rng(seed);
  const Aabb<D> world{Vec<D>::Zero(), Vec<D>::Constant(100)};
  for (int scene = 0; scene < scenes; ++scene) {
    const int n = 5 + static_cast<int>(rng() % 60);
    std::vector<Aabb<D>> boxes = randomScene<D>(rng, n);
    const std::vector<Aabb<D>> moved = randomScene<D>(rng, n);
    std::vector<bool> present(n, true), updated(n, false);
    for (int id = 0; id < n; ++id) {
      if (rng() % 7 == 0) present[id] = false;
      else if (rng() % 3 == 0) updated[id] = true;
    }
    SpaceRule rule;
    rule.decompositionFactor = 1 + static_cast<int>(rng() % 6);
    rule.maxDepth = 7;
    rule.cellSize = 3.0 + static_cast<double>(rng() % 20);
    auto fill = [&](Space<D>& s) {
      for (int id = 0; id < n; ++id) s.insert(id, boxes[id]);
      for (int id = 0; id < n; ++id) {
        if (!present[id]) s.remove(id);
        else if (updated[id]) s.update(id, moved[id]);
      }
    };
    auto boxOf = [&](int id) { return clampTo(updated[id] ? moved[id] : boxes[id], world); };
    auto overlapping = [&](const Space<D>& s) {
      Pairs out;
      s.forEachPair([&](int a, int b) {
        if (boxOf(a).overlaps(boxOf(b))) out.insert({a, b});
      });
      return out;
    };
    Space<D> none(SpaceKind::None, world, rule);
    fill(none);
    EXPECT_EQ(none.leafCount(), 1);
    EXPECT_FALSE(none.divided());
    Pairs all;
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        if (present[a] && present[b]) all.insert({a, b});
    std::vector<std::pair<int, int>> got;
    none.forEachPair([&](int a, int b) { got.push_back({a, b}); });
    ASSERT_EQ(Pairs(got.begin(), got.end()), all) << "scene " << scene;
    ASSERT_EQ(got.size(), all.size()) << "scene " << scene;
    for (int id = 0; id < n; ++id) {
      ASSERT_EQ(none.contains(id), present[id]);
      if (!present[id]) continue;
      std::vector<int> others;
      none.forEachNeighbor(id, [&](int j) { others.push_back(j); });
      std::vector<int> expected;
      for (int j = 0; j < n; ++j)
        if (j != id && present[j]) expected.push_back(j);
      ASSERT_EQ(others, expected) << "scene " << scene << " object " << id;  // in id order
      BallPath<D> path{boxOf(id).center(), Vec<D>::Constant(3.0), 0.5};
      EXPECT_EQ(none.exitTime(id, path), std::numeric_limits<double>::infinity());
    }
    const Pairs truth = overlapping(none);
    for (SpaceKind kind : {SpaceKind::Single, SpaceKind::Tree, SpaceKind::Cells}) {
      Space<D> s(kind, world, rule);
      fill(s);
      ASSERT_EQ(overlapping(s), truth) << toString(kind) << " scene " << scene;
    }
  }
}

TEST(Broadphase, NoneGivesThePairsOfEveryKind2D) { noneGivesThePairsOfEveryKind<2>(201, test::scaledCount(300)); }
TEST(Broadphase, NoneGivesThePairsOfEveryKind3D) { noneGivesThePairsOfEveryKind<3>(202, test::scaledCount(300)); }

// (fewer scenes under the sanitizers: test_scale.hpp)
TEST(Broadphase, EveryKindMatchesBruteForce2D) { everyBroadphaseMatchesBruteForce<2>(101, test::scaledCount(1000)); }
TEST(Broadphase, EveryKindMatchesBruteForce3D) { everyBroadphaseMatchesBruteForce<3>(102, test::scaledCount(1000)); }

// A division that would leave every object in every child separates nothing: objects all lying
// across the middle stay in one leaf; one of them away divides it; back, it reunites.
TEST(Broadphase, NeverDividesWhenNoChildWouldHoldFewer) {
  SpaceRule rule;
  rule.decompositionFactor = 2;
  rule.maxDepth = 4;
  RegionTree<2> tree({{0, 0}, {100, 100}}, rule);
  for (int id = 0; id < 6; ++id) tree.insert(id, boundsOf<2>(Vec2(50 + 0.1 * id, 50), 1.0));
  EXPECT_EQ(tree.leafCount(), 1);
  EXPECT_EQ(tree.counters().subdivisions, 0u);
  tree.update(5, boundsOf<2>(Vec2(20, 20), 1.0));  // one away from the middle: now it separates
  EXPECT_GT(tree.leafCount(), 1);
  EXPECT_EQ(tree.leavesOf(5).size(), 1u);
  tree.update(5, boundsOf<2>(Vec2(50, 50), 1.0));  // back: nothing to separate, reunited
  EXPECT_EQ(tree.leafCount(), 1);
  EXPECT_EQ(tree.counters().reunions, tree.counters().subdivisions);
}

// A region event is when the ball's disc first touches the next leaf's wall: on a divided table
// a ball heading for a wall it is not yet across enters the leaf beyond at the analytic time,
// straight (distance / speed) and slowing (the smaller root of s t - b t^2 / 2 = d).
TEST(Broadphase, RegionEventAtTheAnalyticWallTime) {
  SpaceRule rule;
  rule.decompositionFactor = 1;
  rule.maxDepth = 1;  // one division: walls at x = 50 and y = 50
  RegionTree<2> tree({{0, 0}, {100, 100}}, rule);
  const double r = 0.5, m = tol::kRegionSlop;
  tree.insert(1, boundsOf<2>(Vec2(80, 80), r), m);
  tree.insert(2, boundsOf<2>(Vec2(20, 80), r), m);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> x(5, 45), y(5, 45), speed(0.1, 5), slow(0.01, 1);
  int slowed = 0;
  for (int k = 0; k < 1000; ++k) {
    const Vec2 p(x(rng), y(rng));
    tree.insert(0, boundsOf<2>(p, r), m);
    ASSERT_EQ(tree.leafCount(), 4);
    ASSERT_EQ(tree.leavesOf(0).size(), 1u);
    const double s = speed(rng);
    const Vec2 v(s, 0.0);  // toward the wall at x = 50
    const double d = 50.0 - (p.x() + r);
    const double straight = tree.exitTime(0, BallPath<2>{p, v, r});
    EXPECT_NEAR(straight, d / s, 1e-12 * (d / s)) << "case " << k;
    // slowing at b: reaches the wall iff s^2 >= 2 b d
    const double b = slow(rng);
    const double stop = s / b;
    const double t = tree.exitTime(0, BallPath<2>{p, v, r, Vec2(-b, 0.0), stop});
    if (s * s >= 2 * b * d) {
      const double exact = (s - std::sqrt(s * s - 2 * b * d)) / b;
      EXPECT_NEAR(t, exact, 1e-12 * exact) << "case " << k;
      ++slowed;
    } else {
      EXPECT_EQ(t, std::numeric_limits<double>::infinity()) << "case " << k << ": stops short of the wall";
    }
    tree.remove(0);
  }
  EXPECT_GT(slowed, 100);
  // across the wall, the leaf behind is left once the disc's box is 2 slops clear of it
  tree.insert(0, boundsOf<2>(Vec2(49.8, 20), r), m);
  ASSERT_EQ(tree.leavesOf(0).size(), 2u);
  const double leave = tree.exitTime(0, BallPath<2>{Vec2(49.8, 20), Vec2(2, 0), r});
  EXPECT_NEAR(leave, (50.0 - (49.8 - r - 2 * m)) / 2, 1e-12);
}

// In a running simulation with a tree, after every event: each ball's disc touches only leaves it
// is listed in, and it is listed only where its box reaches within the slop of; over-full leaves
// are those no division could separate; the tree is the one a fresh build from the listed boxes
// makes.
template <int D>
void membershipRecountedAfterEveryEvent(unsigned seed, int divisions, double friction) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(1, 19), vel(-3, 3), rad(0.1, 0.4);
  SimulatorConfig cfg;
  cfg.spaceKind = SpaceKind::Tree;
  cfg.rule.decompositionFactor = 3;
  cfg.rule.divisions = divisions;
  cfg.rule.maxDepth = 6;
  const Aabb<D> world{Vec<D>::Zero(), Vec<D>::Constant(20)};
  Simulator<D> sim(world, cfg);
  for (int i = 0; i < D; ++i) {
    Vec<D> n = Vec<D>::Zero();
    n[i] = 1;
    sim.addWall({n, 0.0});
    sim.addWall({n, 20.0});
  }
  std::vector<Vec<D>> placed;
  for (int k = 0; k < 40; ++k) {
    Vec<D> p, v;
    for (int i = 0; i < D; ++i) p[i] = pos(rng), v[i] = vel(rng);
    const double r = rad(rng);
    bool clear = true;
    for (const Vec<D>& q : placed) clear = clear && (q - p).norm() > 1.0;
    if (!clear) continue;
    placed.push_back(p);
    const int b = sim.addBall(p, v, r, 1.0);
    if (friction > 0) sim.setDeceleration(b, friction);
  }
  const RegionTree<D>& tree = *sim.space()->tree();
  const double slop = tol::kRegionSlop;
  int events = 0;
  std::uint64_t splits = 0;
  sim.run(30.0, [&](const EventRecord&) {
    ++events;
    const double t = sim.now();
    const std::vector<int> leaves = tree.leaves();
    for (int leaf : leaves) {
      const Aabb<D> lb = tree.leafBounds(leaf);
      const ObjectList in = tree.objectsIn(leaf);
      const std::set<int> members(in.begin(), in.end());
      for (int b = 0; b < static_cast<int>(sim.balls().size()); ++b) {
        const BallState<D>& ball = sim.ball(b);
        if (!ball.active) continue;
        const Aabb<D> now = clampTo(boundsOf<D>(ball.positionAt(t), ball.radius), world);
        const Aabb<D> reach = clampTo(boundsOf<D>(ball.positionAt(t), ball.radius + 3 * slop), world);
        if (lb.overlaps(now) && !members.count(b))
          FAIL() << "event " << events << ": ball " << b << " touches leaf " << leaf << " unlisted";
        if (members.count(b) && !lb.overlaps(reach))
          FAIL() << "event " << events << ": ball " << b << " listed in leaf " << leaf << " it has left";
      }
      if (static_cast<int>(members.size()) > cfg.rule.decompositionFactor && tree.depthOf(leaf) < cfg.rule.maxDepth) {
        // only if no child would hold fewer: every member reaches every child
        RegionTree<D> probe(lb, SpaceRule{cfg.rule.decompositionFactor, true, divisions, 1, 0.0});
        int id = 0;
        for (int b : members) probe.insert(id++, clampTo(boundsOf<D>(sim.ball(b).positionAt(t), sim.ball(b).radius + slop), lb));
        if (probe.leafCount() > 1) FAIL() << "event " << events << ": leaf " << leaf << " holds " << members.size() << " and would divide";
      }
    }
    splits = tree.counters().subdivisions;
  });
  EXPECT_GT(events, 200);
  EXPECT_GT(splits, 5u);
  EXPECT_GT(tree.counters().reunions, 5u);
}

TEST(Broadphase, TreeMembershipRecountedAfterEveryEvent2D) { membershipRecountedAfterEveryEvent<2>(11, 4, 0.0); }
TEST(Broadphase, TreeMembershipRecountedAfterEveryEventSlowing2D) { membershipRecountedAfterEveryEvent<2>(12, 4, 0.3); }
TEST(Broadphase, TreeMembershipRecountedAfterEveryEventBinary2D) { membershipRecountedAfterEveryEvent<2>(13, 2, 0.0); }
TEST(Broadphase, TreeMembershipRecountedAfterEveryEvent3D) { membershipRecountedAfterEveryEvent<3>(14, 8, 0.0); }

// One sizing rule for every grid: the target edge, doubled until the grid has at most maxCells.
TEST(Broadphase, GridCellSizeDoublesUntilTheCellsFit) {
  EXPECT_EQ(gridCellSize<2>(Vec2(100, 50), 1.0, 1e4), 1.0);        // 5000 cells
  EXPECT_EQ(gridCellSize<2>(Vec2(1000, 500), 1.0, 1e4), 8.0);      // 500000 -> 7812.5 at 8
  EXPECT_EQ(gridCellSize<3>(Vec3(100, 100, 100), 1.0, 1e3), 16.0);  // 1e6, ..., 1953 at 8, 244 at 16
}

}  // namespace
}  // namespace st
