#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <stcore/space.hpp>

namespace st {
namespace {

// Every object is listed in exactly the leaves its (fat) box touches.
template <int D>
void expectExactMembership(const Space<D>& s, const std::vector<Aabb<D>>& boxes, const std::vector<bool>& present) {
  const auto leaves = s.leaves();
  for (int id = 0; id < static_cast<int>(boxes.size()); ++id) {
    if (!present[id]) continue;
    std::set<int> expected;
    Aabb<D> b = boxes[id];
    b.min = b.min.cwiseMax(s.bounds().min).cwiseMin(s.bounds().max);
    b.max = b.max.cwiseMin(s.bounds().max).cwiseMax(s.bounds().min);
    for (int leaf : leaves)
      if (s.leafBounds(leaf).overlaps(b)) expected.insert(leaf);
    std::set<int> actual(s.leavesOf(id).begin(), s.leavesOf(id).end());
    ASSERT_EQ(actual, expected) << "object " << id;
    for (int leaf : actual) {
      const auto& objs = s.objectsIn(leaf);
      ASSERT_EQ(std::count(objs.begin(), objs.end(), id), 1);
    }
  }
  for (int leaf : leaves) {
    ASSERT_LE(s.depthOf(leaf), s.rule().maxDepth);
    for (int id : s.objectsIn(leaf)) ASSERT_TRUE(present[id]);
  }
}

template <int D>
void randomOps(SpaceKind kind, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0, 100), size(0.1, 4);
  Aabb<D> world{Vec<D>::Zero(), Vec<D>::Constant(100)};
  SpaceRule rule;
  rule.decompositionFactor = 3;
  rule.cellSize = 10;
  Space<D> s(kind, world, rule);
  const int n = 200;
  std::vector<Aabb<D>> boxes(n);
  std::vector<bool> present(n, false);
  auto randomBox = [&] {
    Vec<D> c;
    for (int k = 0; k < D; ++k) c[k] = pos(rng);
    return boundsOf<D>(c, size(rng));
  };
  for (int step = 0; step < 3000; ++step) {
    const int id = static_cast<int>(rng() % n);
    const int op = static_cast<int>(rng() % 3);
    if (!present[id]) {
      boxes[id] = randomBox();
      s.insert(id, boxes[id]);
      present[id] = true;
    } else if (op == 0) {
      s.remove(id);
      present[id] = false;
    } else {
      boxes[id] = randomBox();
      s.update(id, boxes[id]);
    }
    if (step % 50 == 0) expectExactMembership(s, boxes, present);
  }
  expectExactMembership(s, boxes, present);
  // emptying the tree reunites everything into the root
  for (int id = 0; id < n; ++id)
    if (present[id]) s.remove(id), present[id] = false;
  EXPECT_EQ(s.leaves().size(), kind == SpaceKind::Cells ? 1000u / (D == 2 ? 10u : 1u) : 1u);
  if (kind == SpaceKind::Tree) {
    EXPECT_GT(s.counters().subdivisions, 0u);
    EXPECT_EQ(s.counters().subdivisions, s.counters().reunions);
  }
}

TEST(Space, TreeInvariants2D) { randomOps<2>(SpaceKind::Tree, 1); }
TEST(Space, TreeInvariants3D) { randomOps<3>(SpaceKind::Tree, 2); }
TEST(Space, CellsInvariants2D) { randomOps<2>(SpaceKind::Cells, 3); }
TEST(Space, CellsInvariants3D) { randomOps<3>(SpaceKind::Cells, 4); }

}  // namespace
}  // namespace st
