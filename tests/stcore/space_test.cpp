// Space invariants after random insert / move / remove sequences, checked against brute force:
//   - every object is listed in exactly the leaves its (fat, clamped) box touches, once each;
//   - the tree is the canonical one for its contents: identical leaves and membership to a space
//     freshly built from the same boxes (so every region over the decomposition factor is divided
//     and every divided region over it: splits and reunions both happened when they had to);
//   - subdivisions - reunions equals the number of divided regions; leaves tile the bounds;
//   - forEachNeighbor is exactly "shares a leaf", each once, and so covers every overlapping pair;
//   - forEachInBox is exactly the objects of the leaves the box touches, a superset of the
//     objects whose boxes overlap it;
//   - objects that may have gained neighbours through a reunion are reported by takeWidened;
//   - exitTime is safe: until then the moving ball touches only leaves it is listed in.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <stcore/space.hpp>

#include "boxes.hpp"

namespace st {
namespace {

template <int D>
using Key = std::array<double, 2 * D>;  // a leaf, named by its box

// uniform in [-1, 1]^D from the test's own generator
template <int D>
Vec<D> jitter(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Vec<D> v;
  for (int i = 0; i < D; ++i) v[i] = u(rng);
  return v;
}

template <int D>
Key<D> keyOf(const Aabb<D>& b) {
  Key<D> k;
  for (int i = 0; i < D; ++i) k[i] = b.min[i], k[D + i] = b.max[i];
  return k;
}

using test::clampTo;
using test::overlapsOpen;

// What a test object is: its box and margin as last given to the space.
template <int D>
struct Obj {
  Aabb<D> box;
  double margin = 0;
  bool present = false;
  Aabb<D> fat() const { return {box.min.array() - margin, box.max.array() + margin}; }
};

// Leaves and membership, by leaf box, independent of node numbering.
template <int D>
struct Snapshot {
  std::set<Key<D>> leaves;
  std::map<int, std::set<Key<D>>> membership;
  bool operator==(const Snapshot&) const = default;
};

template <int D>
Snapshot<D> snapshot(const Space<D>& s, const std::vector<Obj<D>>& objs) {
  Snapshot<D> snap;
  for (int leaf : s.leaves()) snap.leaves.insert(keyOf(s.leafBounds(leaf)));
  for (int id = 0; id < static_cast<int>(objs.size()); ++id) {
    if (!objs[id].present) continue;
    auto& m = snap.membership[id];
    for (int leaf : s.leavesOf(id)) m.insert(keyOf(s.leafBounds(leaf)));
  }
  return snap;
}

template <int D>
std::set<int> bruteNeighbors(const Space<D>& s, int id) {
  std::set<int> out;
  for (int leaf : s.leavesOf(id))
    for (int other : s.objectsIn(leaf))
      if (other != id) out.insert(other);
  return out;
}

template <int D>
::testing::AssertionResult checkInvariants(const Space<D>& s, const std::vector<Obj<D>>& objs, std::mt19937_64& rng) {
  const auto leaves = s.leaves();
  const Aabb<D> bounds = s.bounds();
  const bool cells = s.kind() == SpaceKind::Cells;
  // leaves tile the bounds: no two share interior, and their volumes add up
  double volume = 0;
  for (int leaf : leaves) volume += s.leafBounds(leaf).extent().prod();
  if (std::abs(volume - bounds.extent().prod()) > 1e-9 * bounds.extent().prod())
    return ::testing::AssertionFailure() << "leaf volumes " << volume << " do not tile the bounds";
  if (leaves.size() <= 300)
    for (std::size_t i = 0; i < leaves.size(); ++i)
      for (std::size_t j = i + 1; j < leaves.size(); ++j)
        if (overlapsOpen(s.leafBounds(leaves[i]), s.leafBounds(leaves[j])))
          return ::testing::AssertionFailure() << "leaves " << leaves[i] << " and " << leaves[j] << " overlap";
  // membership, both ways
  for (int id = 0; id < static_cast<int>(objs.size()); ++id) {
    if (!objs[id].present) {
      if (s.contains(id)) return ::testing::AssertionFailure() << "removed object " << id << " still present";
      continue;
    }
    const Aabb<D> fat = clampTo(objs[id].fat(), bounds);
    const std::set<int> actual(s.leavesOf(id).begin(), s.leavesOf(id).end());
    if (actual.size() != s.leavesOf(id).size()) return ::testing::AssertionFailure() << "object " << id << " lists a leaf twice";
    if (actual.empty()) return ::testing::AssertionFailure() << "object " << id << " is in no leaf";
    for (int leaf : leaves) {
      const Aabb<D> lb = s.leafBounds(leaf);
      const bool listed = actual.count(leaf) > 0;
      // trees: closed boxes, exactly. Cells are half-open: a box ending exactly on a cell face
      // may or may not be listed in the cell beyond it, but any shared interior must be.
      const bool must = cells ? overlapsOpen(lb, fat) : lb.overlaps(fat);
      const bool may = lb.overlaps(fat);
      if ((must && !listed) || (listed && !may))
        return ::testing::AssertionFailure() << "object " << id << (listed ? " listed in" : " missing from")
                                             << " leaf " << leaf << " at depth " << s.depthOf(leaf);
      const auto& in = s.objectsIn(leaf);
      if (std::count(in.begin(), in.end(), id) != (listed ? 1 : 0))
        return ::testing::AssertionFailure() << "leaf " << leaf << " and object " << id << " disagree";
    }
  }
  for (int leaf : leaves)
    for (int id : s.objectsIn(leaf))
      if (id >= static_cast<int>(objs.size()) || !objs[id].present)
        return ::testing::AssertionFailure() << "leaf " << leaf << " lists absent object " << id;
  if (s.kind() == SpaceKind::Tree) {
    // over-full leaves only at the depth limit or where no child would hold fewer (every member
    // reaches every child: a division separates nothing); divided regions = subdivisions - reunions
    for (int leaf : leaves) {
      const ObjectList in = s.objectsIn(leaf);
      if (static_cast<int>(in.size()) <= s.rule().decompositionFactor || s.depthOf(leaf) >= s.rule().maxDepth) continue;
      SpaceRule once = s.rule();
      once.maxDepth = 1;
      Space<D> probe(SpaceKind::Tree, s.leafBounds(leaf), once);
      int k = 0;
      for (int id : in) probe.insert(k++, clampTo(objs[id].fat(), s.leafBounds(leaf)));
      if (probe.divided())
        return ::testing::AssertionFailure() << "leaf " << leaf << " holds " << in.size() << " objects and would divide";
    }
    const auto divided = static_cast<std::uint64_t>((leaves.size() - 1) / (s.rule().divisions - 1));
    if (s.counters().subdivisions - s.counters().reunions != divided)
      return ::testing::AssertionFailure() << "subdivisions " << s.counters().subdivisions << " - reunions "
                                           << s.counters().reunions << " != divided regions " << divided;
    // canonical: a fresh space holding the same boxes has the same leaves and membership
    SpaceRule rule = s.rule();
    rule.autoFactor = false;  // the factor in force, fixed
    Space<D> fresh(s.kind(), bounds, rule);
    for (int id = 0; id < static_cast<int>(objs.size()); ++id)
      if (objs[id].present) fresh.insert(id, objs[id].box, objs[id].margin);
    if (!(snapshot(fresh, objs) == snapshot(s, objs)))
      return ::testing::AssertionFailure() << "tree differs from a fresh build of the same boxes (" << s.leaves().size()
                                           << " vs " << fresh.leaves().size() << " leaves)";
  }
  // neighbours: exactly "shares a leaf", each once; covers all overlapping fat boxes
  for (int id = 0; id < static_cast<int>(objs.size()); ++id) {
    if (!objs[id].present) continue;
    std::vector<int> got;
    s.forEachNeighbor(id, [&](int other) { got.push_back(other); });
    const std::set<int> gotSet(got.begin(), got.end());
    if (gotSet.size() != got.size()) return ::testing::AssertionFailure() << "neighbour reported twice for " << id;
    if (gotSet != bruteNeighbors(s, id)) return ::testing::AssertionFailure() << "neighbours of " << id << " differ from shared leaves";
    if (cells) {  // the gathered list is the visited one
      std::vector<int> gathered(1 << 16);
      const int n = s.gatherNeighbors(id, gathered.data(), static_cast<int>(gathered.size()));
      if (n < 0) return ::testing::AssertionFailure() << "neighbours of " << id << " do not fit 2^16";
      gathered.resize(static_cast<std::size_t>(n));
      if (gathered != got) return ::testing::AssertionFailure() << "gathered neighbours of " << id << " differ from visited";
    }
    const Aabb<D> fat = clampTo(objs[id].fat(), bounds);
    for (int other = 0; other < static_cast<int>(objs.size()); ++other)
      if (other != id && objs[other].present && fat.overlaps(clampTo(objs[other].fat(), bounds)) && !gotSet.count(other))
        return ::testing::AssertionFailure() << "overlapping objects " << id << " and " << other << " are not neighbours";
  }
  // box queries, some reaching outside the bounds
  std::uniform_real_distribution<double> pos(-10, 110), size(0, 30);
  for (int q = 0; q < 20; ++q) {
    Vec<D> c;
    for (int i = 0; i < D; ++i) c[i] = pos(rng);
    const Aabb<D> box = boundsOf<D>(c, size(rng));
    std::vector<int> got;
    s.forEachInBox(box, [&](int other) { got.push_back(other); });
    const std::set<int> gotSet(got.begin(), got.end());
    if (gotSet.size() != got.size()) return ::testing::AssertionFailure() << "box query reported an object twice";
    if (cells) {  // the gathered box query is the visited one
      std::vector<int> gathered(1 << 16);
      const int n = s.gatherInBox(box, gathered.data(), static_cast<int>(gathered.size()));
      if (n < 0) return ::testing::AssertionFailure() << "box query does not fit 2^16";
      gathered.resize(static_cast<std::size_t>(n));
      if (gathered != got) return ::testing::AssertionFailure() << "gathered box query differs from visited";
    }
    const Aabb<D> clamped = clampTo(box, bounds);
    std::set<int> expected;
    for (int leaf : leaves)
      if (s.leafBounds(leaf).overlaps(clamped))
        for (int id : s.objectsIn(leaf)) expected.insert(id);
    for (int id = 0; id < static_cast<int>(objs.size()); ++id)
      if (objs[id].present && clamped.overlaps(clampTo(objs[id].fat(), bounds)) && !gotSet.count(id))
        return ::testing::AssertionFailure() << "box query misses overlapping object " << id;
    // cells visit the half-open cell range, trees the closed leaves: between the two
    for (int id : gotSet)
      if (!expected.count(id)) return ::testing::AssertionFailure() << "box query returns " << id << " from no touched leaf";
    if (!cells && gotSet != expected) return ::testing::AssertionFailure() << "box query differs from touched leaves";
  }
  return ::testing::AssertionSuccess();
}

struct OpsConfig {
  SpaceKind kind = SpaceKind::Tree;
  int divisions = 0;
  int df = 3;
  int objects = 150;
  int steps = 2000;
  int checkEvery = 50;
  bool autoFactor = false;
  double regionCost = 100.0;  // auto: the cost of a region event, in pair checks
};

template <int D>
void randomOps(const OpsConfig& cfg, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-2, 102), size(0.05, 3), unit(0, 1);
  const Aabb<D> world{Vec<D>::Zero(), Vec<D>::Constant(100)};
  SpaceRule rule;
  rule.decompositionFactor = cfg.df;
  rule.divisions = cfg.divisions;
  rule.cellSize = 10;
  rule.maxDepth = 8;
  rule.autoFactor = cfg.autoFactor;
  rule.autoRegionCost = cfg.regionCost;
  Space<D> s(cfg.kind, world, rule);
  std::vector<Obj<D>> objs(cfg.objects);
  auto randomBox = [&](const Aabb<D>* near) {
    Vec<D> c;
    for (int k = 0; k < D; ++k) c[k] = pos(rng);
    if (near) c = near->center() + 0.5 * jitter<D>(rng);  // a small move
    Aabb<D> b = boundsOf<D>(c, size(rng));
    // now and then snap to the tree's split planes and the cell faces (multiples of 100/64, 2.5)
    if (rng() % 5 == 0) {
      const double grid = (rng() & 1) ? 100.0 / 64 : 2.5;
      for (int i = 0; i < D; ++i) {
        const double w = std::max(1.0, std::round((b.max[i] - b.min[i]) / grid));
        b.min[i] = std::round(b.min[i] / grid) * grid;
        b.max[i] = b.min[i] + w * grid;
      }
    }
    return b;
  };
  int clusterLeft = 0;
  for (int step = 0; step < cfg.steps; ++step) {
    const int id = static_cast<int>(rng() % objs.size());
    Obj<D>& o = objs[id];
    // remember who shared a leaf with whom, to check the widened report
    std::vector<std::set<int>> before(objs.size());
    for (int j = 0; j < static_cast<int>(objs.size()); ++j)
      if (objs[j].present) before[j] = bruteNeighbors(s, j);
    const int op = static_cast<int>(rng() % 4);
    if (!o.present) {
      // phases of crowding: inserts pile into one corner, forcing deep splits, later dispersed
      if (clusterLeft == 0 && rng() % 200 == 0) clusterLeft = 40;
      o.box = randomBox(nullptr);
      if (clusterLeft > 0) {
        --clusterLeft;
        o.box = boundsOf<D>(Vec<D>(Vec<D>::Constant(20) + (D == 2 ? 3.0 : 8.0) * jitter<D>(rng)), size(rng));
      }
      o.margin = unit(rng) < 0.5 ? 0.0 : 0.5 * unit(rng);
      s.insert(id, o.box, o.margin);
      o.present = true;
    } else if (op == 0) {
      s.remove(id);
      o.present = false;
    } else {
      const Aabb<D> old = o.box;
      o.box = randomBox(op == 1 ? &old : nullptr);
      s.update(id, o.box, o.margin);
      // the neighbours the update brought are among those forEachNeighborGained reports, once each
      std::vector<int> gained;
      s.forEachNeighborGained(id, [&](int other) { gained.push_back(other); });
      const std::set<int> gainedSet(gained.begin(), gained.end());
      ASSERT_EQ(gainedSet.size(), gained.size()) << "step " << step << ": a gained neighbour reported twice";
      ASSERT_FALSE(gainedSet.count(id)) << "step " << step;
      for (int k : bruteNeighbors(s, id)) {
        if (before[id].count(k)) continue;
        ASSERT_TRUE(gainedSet.count(k)) << "step " << step << ": " << id << " gained " << k << " unreported";
      }
    }
    // every new pair of leaf-sharers (other than with the object just changed) has one member
    // reported as widened, so the simulator re-predicts it
    const std::vector<int> widened = s.takeWidened();
    for (int j = 0; j < static_cast<int>(objs.size()); ++j) {
      if (!objs[j].present || j == id) continue;
      for (int k : bruteNeighbors(s, j)) {
        if (k == id || before[j].count(k)) continue;
        const bool reported = std::binary_search(widened.begin(), widened.end(), j) ||
                              std::binary_search(widened.begin(), widened.end(), k);
        ASSERT_TRUE(reported) << "step " << step << ": " << j << " and " << k << " now share a leaf, neither reported";
      }
    }
    if (step % cfg.checkEvery == 0) {
      ASSERT_TRUE(checkInvariants(s, objs, rng)) << "step " << step;
    }
  }
  ASSERT_TRUE(checkInvariants(s, objs, rng));
  if (cfg.autoFactor) {
    ASSERT_NE(s.tuner(), nullptr);
    EXPECT_GT(s.tuner()->factorChanges(), 0u);  // it did move the factor
  }
  if (cfg.kind == SpaceKind::Tree) {
    EXPECT_GT(s.counters().subdivisions, 10u);
    EXPECT_GT(s.counters().reunions, 10u);
  }
  if (cfg.kind != SpaceKind::Single) {
    EXPECT_GT(s.counters().transfers, 100u);
  } else {
    EXPECT_EQ(s.counters().transfers, 0u);  // one region: membership never changes
  }
  // emptying the space reunites everything into the root
  for (int id = 0; id < static_cast<int>(objs.size()); ++id)
    if (objs[id].present) s.remove(id), objs[id].present = false;
  ASSERT_TRUE(checkInvariants(s, objs, rng));
  if (cfg.kind == SpaceKind::Tree) {
    EXPECT_EQ(s.leaves().size(), 1u);
    EXPECT_EQ(s.counters().subdivisions, s.counters().reunions);
  }
}

TEST(Space, QuadtreeFourDivisions) { randomOps<2>({SpaceKind::Tree, 4, 3}, 1); }
TEST(Space, QuadtreeTwoDivisions) { randomOps<2>({SpaceKind::Tree, 2, 3}, 2); }
TEST(Space, QuadtreeDecompositionFactorOne) { randomOps<2>({SpaceKind::Tree, 4, 1, 60, 1500}, 3); }
TEST(Space, OctreeEightDivisions) { randomOps<3>({SpaceKind::Tree, 8, 4, 150, 1200}, 4); }
TEST(Space, OctreeTwoAndFourDivisions) {
  randomOps<3>({SpaceKind::Tree, 2, 3, 100, 1000}, 5);
  randomOps<3>({SpaceKind::Tree, 4, 3, 100, 1000}, 6);
}
// decomposition_factor: auto: the factor changes while objects move; every invariant above holds
// (neighbours and pairs against brute force, the tree against a fresh build at the factor in force)
// (region events cheap here, so it divides finer; dear, so it reunites)
TEST(Space, QuadtreeAutoFactor) { randomOps<2>({SpaceKind::Tree, 4, 3, 150, 3000, 50, true, 5.0}, 31); }
TEST(Space, OctreeAutoFactor) { randomOps<3>({SpaceKind::Tree, 8, 4, 150, 2000, 50, true, 5.0}, 32); }
TEST(Space, QuadtreeAutoFactorCoarsens) { randomOps<2>({SpaceKind::Tree, 4, 3, 150, 3000, 50, true, 5000.0}, 33); }
TEST(Space, Cells2D) { randomOps<2>({SpaceKind::Cells}, 7); }
TEST(Space, Cells3D) { randomOps<3>({SpaceKind::Cells, 0, 3, 100, 1000}, 8); }
TEST(Space, Single) { randomOps<2>({SpaceKind::Single, 0, 3, 60, 600}, 9); }

// Subdivide then reunite: crowding a region splits it; removing the crowd restores exactly the
// leaves and membership there were before, and every subdivision was undone by one reunion.
template <int D>
void splitThenReunite(int divisions, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0, 100), size(0.1, 2);
  const Aabb<D> world{Vec<D>::Zero(), Vec<D>::Constant(100)};
  SpaceRule rule;
  rule.decompositionFactor = 4;
  rule.divisions = divisions;
  rule.maxDepth = 9;
  Space<D> s(SpaceKind::Tree, world, rule);
  std::vector<Obj<D>> objs(300);
  auto place = [&](int id, const Vec<D>& c, double r) {
    objs[id] = {boundsOf<D>(c, r), 0.1, true};
    s.insert(id, objs[id].box, objs[id].margin);
  };
  for (int id = 0; id < 60; ++id) {
    Vec<D> c;
    for (int i = 0; i < D; ++i) c[i] = pos(rng);
    place(id, c, size(rng));
  }
  const Snapshot<D> base = snapshot(s, objs);
  const SpaceCounters c0 = s.counters();
  for (int round = 0; round < 3; ++round) {
    // crowd: many more objects, clustered, so regions split several levels down
    const Vec<D> centre = Vec<D>::Constant(15 + 25 * round);
    for (int id = 60; id < 300; ++id) place(id, centre + 10 * jitter<D>(rng), size(rng));
    ASSERT_TRUE(checkInvariants(s, objs, rng));
    EXPECT_GT(s.leaves().size(), base.leaves.size() + 20);
    // move the crowd around: transfers, splits and reunions interleave
    const auto t0 = s.counters().transfers;
    for (int id = 60; id < 300; ++id) {
      objs[id].box = boundsOf<D>(Vec<D>(objs[id].box.center() + 2 * jitter<D>(rng)), size(rng));
      s.update(id, objs[id].box, objs[id].margin);
    }
    EXPECT_GT(s.counters().transfers, t0);
    ASSERT_TRUE(checkInvariants(s, objs, rng));
    // disperse in random order
    std::vector<int> order;
    for (int id = 60; id < 300; ++id) order.push_back(id);
    std::shuffle(order.begin(), order.end(), rng);
    for (int id : order) s.remove(id), objs[id].present = false;
    ASSERT_TRUE(snapshot(s, objs) == base) << "round " << round << ": membership not restored";
    EXPECT_EQ(s.counters().subdivisions - c0.subdivisions, s.counters().reunions - c0.reunions);
  }
  EXPECT_GT(s.counters().subdivisions, c0.subdivisions + 50);
}

TEST(Space, SubdivideThenReuniteRestoresMembership2D) {
  splitThenReunite<2>(4, 21);
  splitThenReunite<2>(2, 22);
}
TEST(Space, SubdivideThenReuniteRestoresMembership3D) { splitThenReunite<3>(8, 23); }

// A cells space's box visit is a function of the block of cells the box touches: boxes with one
// block visit the same objects in the same order, and the block names its first and last cell.
TEST(Space, CellBlockKeysTheBoxVisit) {
  SpaceRule rule;
  rule.cellSize = 10;
  Space<2> cells(SpaceKind::Cells, {{0, 0}, {100, 100}}, rule);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(0.0, 100.0);
  for (int id = 0; id < 200; ++id) cells.insert(id, boundsOf<2>(Vec2(U(rng), U(rng)), 0.05 * U(rng)));
  auto visit = [&](const Aabb<2>& box) {
    std::vector<int> out;
    cells.forEachInBox(box, [&](int id) { out.push_back(id); });
    return out;
  };
  const Aabb<2> a{{21, 33}, {48, 61}}, b{{20.5, 30.1}, {49.9, 69.9}}, c{{19.9, 30.1}, {49.9, 69.9}};
  EXPECT_EQ(cells.cellBlock(a), (std::array<int, 2>{3 * 10 + 2, 6 * 10 + 4}));  // cells (2, 3) .. (4, 6)
  EXPECT_EQ(cells.cellBlock(a), cells.cellBlock(b));
  EXPECT_EQ(visit(a), visit(b));
  EXPECT_NE(cells.cellBlock(a), cells.cellBlock(c));
  // outside the bounds: clamped, as the visit is
  EXPECT_EQ(cells.cellBlock({{-50, -50}, {5, 5}}), (std::array<int, 2>{0, 0}));
  const Space<2> tree(SpaceKind::Tree, {{0, 0}, {100, 100}}, SpaceRule{});
  EXPECT_EQ(tree.cellBlock(a), (std::array<int, 2>{-1, -1}));
}

// A visit kept under (cellBlock, revision) is the visit made afresh whenever the key matches,
// through random inserts, moves and removals; moves within the same cells keep the revision.
TEST(Space, RevisionKeysCachedVisits) {
  SpaceRule rule;
  rule.cellSize = 10;
  Space<2> cells(SpaceKind::Cells, {{0, 0}, {100, 100}}, rule);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(0, 100), rad(0.2, 6), unit(0, 1);
  auto visit = [&](const Aabb<2>& box) {
    std::vector<int> out;
    cells.forEachInBox(box, [&](int id) { out.push_back(id); });
    return out;
  };
  struct Cached {
    std::array<int, 2> block;
    std::uint64_t revision;
    std::vector<int> ids;
  };
  std::vector<Aabb<2>> boxes;
  for (int k = 0; k < 8; ++k) boxes.push_back(boundsOf<2>(Vec2(pos(rng), pos(rng)), 4 * rad(rng)));
  std::vector<Cached> cache(boxes.size());
  for (std::size_t k = 0; k < boxes.size(); ++k) cache[k] = {cells.cellBlock(boxes[k]), cells.revision(), visit(boxes[k])};
  std::vector<bool> present(40, false);
  std::vector<Vec2> at(40, Vec2::Zero());
  int hits = 0;
  for (int step = 0; step < 4000; ++step) {
    const int id = static_cast<int>(unit(rng) * 40);
    // mostly small moves (most keep their cells), some jumps
    at[id] = present[id] && unit(rng) < 0.8 ? Vec2(at[id] + Vec2(unit(rng) - 0.5, unit(rng) - 0.5)) : Vec2(pos(rng), pos(rng));
    const Aabb<2> box = boundsOf<2>(at[id], 1.0);
    if (!present[id]) {
      cells.insert(id, box);
      present[id] = true;
    } else if (unit(rng) < 0.1) {
      cells.remove(id);
      present[id] = false;
    } else {
      cells.update(id, box);
    }
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      if (unit(rng) < 0.05) boxes[k] = boundsOf<2>(Vec2(pos(rng), pos(rng)), 4 * rad(rng));
      const std::array<int, 2> block = cells.cellBlock(boxes[k]);
      if (block == cache[k].block && cells.revision() == cache[k].revision) {
        ++hits;
        ASSERT_EQ(cache[k].ids, visit(boxes[k])) << "step " << step;
      } else {
        cache[k] = {block, cells.revision(), visit(boxes[k])};
      }
    }
  }
  // a move within the cells an object already touches changes nothing a visit sees
  cells.insert(99, boundsOf<2>(Vec2(55, 55), 1));
  const std::uint64_t before = cells.revision();
  cells.update(99, boundsOf<2>(Vec2(54, 56), 2));
  EXPECT_EQ(cells.revision(), before);
  cells.update(99, boundsOf<2>(Vec2(59.5, 55), 1));  // across into the next cell
  EXPECT_NE(cells.revision(), before);
  EXPECT_GT(hits, 1000);
}

TEST(Space, TransfersCountMembershipChangesOnly) {
  SpaceRule rule;
  rule.cellSize = 10;
  Space<2> cells(SpaceKind::Cells, {{0, 0}, {100, 100}}, rule);
  cells.insert(0, boundsOf<2>(Vec2(5, 5), 1));
  const auto& c = cells.counters();
  cells.update(0, boundsOf<2>(Vec2(5, 5), 1));  // same box
  cells.update(0, boundsOf<2>(Vec2(4, 6), 2));  // moved inside its cell
  EXPECT_EQ(c.transfers, 0u);
  cells.update(0, boundsOf<2>(Vec2(9.5, 5), 1));  // now across into the next cell
  EXPECT_EQ(c.transfers, 1u);
  EXPECT_EQ(cells.leavesOf(0).size(), 2u);
  cells.update(0, boundsOf<2>(Vec2(55, 55), 1));  // far away
  EXPECT_EQ(c.transfers, 2u);

  // a tree split by a crowd in one quadrant: moving within a leaf is no transfer
  rule.decompositionFactor = 2;
  Space<2> tree(SpaceKind::Tree, {{0, 0}, {100, 100}}, rule);
  tree.insert(0, boundsOf<2>(Vec2(10, 10), 1));
  tree.insert(1, boundsOf<2>(Vec2(30, 30), 1));
  tree.insert(2, boundsOf<2>(Vec2(10, 30), 1));
  tree.insert(3, boundsOf<2>(Vec2(80, 80), 1));
  const std::uint64_t splits = tree.counters().subdivisions;
  EXPECT_GE(splits, 1u);
  tree.update(3, boundsOf<2>(Vec2(75, 70), 1));
  EXPECT_EQ(tree.counters().transfers, 0u);
  EXPECT_EQ(tree.counters().subdivisions, splits);
  tree.update(3, boundsOf<2>(Vec2(20, 20), 1));  // into the crowded quadrant
  EXPECT_EQ(tree.counters().transfers, 1u);
}

// exitTime: until then, the ball's own box touches only leaves it is listed in; for cells it is
// also exact (just after it the ball reaches a new cell, unless it leaves the bounds first).
template <int D>
void exitTimeIsSafe(SpaceKind kind, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0, 100), rad(0.2, 3), vel(-5, 5), unit(0, 1);
  const Aabb<D> world{Vec<D>::Zero(), Vec<D>::Constant(100)};
  SpaceRule rule;
  rule.decompositionFactor = 3;
  rule.cellSize = 7;
  rule.maxDepth = 6;
  Space<D> s(kind, world, rule);
  const int n = 200;
  std::vector<Vec<D>> p(n), v(n);
  std::vector<double> r(n);
  for (int id = 0; id < n; ++id) {
    for (int i = 0; i < D; ++i) p[id][i] = pos(rng), v[id][i] = vel(rng);
    if (id % 10 == 0) v[id][0] = 0;  // moving along an axis plane now and then
    r[id] = rad(rng);
    s.insert(id, boundsOf<D>(p[id], r[id]), unit(rng) * r[id]);
  }
  int exact = 0;
  const std::vector<int> leaves = s.leaves();
  std::vector<Aabb<D>> leafBoxes;
  for (int leaf : leaves) leafBoxes.push_back(s.leafBounds(leaf));
  for (int id = 0; id < n; ++id) {
    const double T = s.exitTime(id, p[id], v[id], r[id]);
    ASSERT_GE(T, 0.0);
    if (kind == SpaceKind::Single) {
      EXPECT_EQ(T, std::numeric_limits<double>::infinity());
      continue;
    }
    const std::set<int> listed(s.leavesOf(id).begin(), s.leavesOf(id).end());
    const double horizon = std::isfinite(T) ? T : 100.0;
    for (int k = 0; k <= 32; ++k) {
      const double t = horizon * k / 32.0 * (1 - 1e-12);
      const Aabb<D> box = clampTo(boundsOf<D>(Vec<D>(p[id] + v[id] * t), r[id]), world);
      for (std::size_t l = 0; l < leaves.size(); ++l)
        if (leafBoxes[l].overlaps(box) && !listed.count(leaves[l]))
          FAIL() << "ball " << id << " touches unlisted leaf " << leaves[l] << " at t=" << t << " < exit " << T;
    }
    // exact for cells: just after, the ball reaches a new cell (when still inside the bounds)
    const Vec<D> after = p[id] + v[id] * (T * (1 + 1e-9) + 1e-12);
    if (kind == SpaceKind::Cells && std::isfinite(T) && world.contains(after)) {
      const Aabb<D> box = clampTo(boundsOf<D>(after, r[id]), world);
      bool reachesNew = false;
      for (std::size_t l = 0; l < leaves.size(); ++l)
        reachesNew |= overlapsOpen(leafBoxes[l], box) && !listed.count(leaves[l]);
      EXPECT_TRUE(reachesNew) << "ball " << id << ": exit time " << T << " is not when it reaches a new cell";
      ++exact;
    }
  }
  if (kind == SpaceKind::Cells) {
    EXPECT_GT(exact, n / 4);
  }
}

TEST(Space, ExitTimeIsSafe) {
  exitTimeIsSafe<2>(SpaceKind::Tree, 31);
  exitTimeIsSafe<3>(SpaceKind::Tree, 32);
  exitTimeIsSafe<2>(SpaceKind::Cells, 33);
  exitTimeIsSafe<3>(SpaceKind::Cells, 34);
  exitTimeIsSafe<2>(SpaceKind::Single, 35);
}

// With fewer children than 2^D a division splits only some axes; it must pick the node's longest
// ones, or a square root degenerates into slivers (all objects of a strip become neighbours).
template <int D>
double worstLeafAspect(int divisions, unsigned seed) {
  std::mt19937_64 rng(seed);
  SpaceRule rule;
  rule.decompositionFactor = 2;
  rule.divisions = divisions;
  rule.maxDepth = 10;
  Space<D> s(SpaceKind::Tree, {Vec<D>::Zero(), Vec<D>::Constant(100)}, rule);
  for (int id = 0; id < 300; ++id) {
    Vec<D> c = 50 * (Vec<D>::Ones() + jitter<D>(rng));
    s.insert(id, boundsOf<D>(c, 0.2));
  }
  double worst = 1;
  for (int leaf : s.leaves()) {
    const Vec<D> e = s.leafBounds(leaf).extent();
    worst = std::max(worst, e.maxCoeff() / e.minCoeff());
  }
  return worst;
}

TEST(Space, PartialDivisionsKeepLeavesSquare) {
  EXPECT_LE(worstLeafAspect<2>(2, 41), 2.0);
  EXPECT_LE(worstLeafAspect<3>(2, 42), 2.0);
  EXPECT_LE(worstLeafAspect<3>(4, 43), 2.0);
}

TEST(Space, RejectsBadRules) {
  const Aabb<2> world{Vec2::Zero(), Vec2::Constant(1)};
  SpaceRule rule;
  rule.divisions = 8;  // more than 2^D
  EXPECT_THROW(Space<2>(SpaceKind::Tree, world, rule), std::invalid_argument);
  rule.divisions = 3;
  EXPECT_THROW(Space<2>(SpaceKind::Tree, world, rule), std::invalid_argument);
  rule = SpaceRule{};
  EXPECT_THROW(Space<2>(SpaceKind::Cells, world, rule), std::invalid_argument);  // no cell size
  EXPECT_THROW(Space<2>(SpaceKind::Tree, Aabb<2>{Vec2::Zero(), Vec2(1, 0)}, rule), std::invalid_argument);
  SpaceKind k;
  EXPECT_TRUE(parseSpaceKind("octree", k) && k == SpaceKind::Tree);
  EXPECT_FALSE(parseSpaceKind("kdtree", k));
}


// decomposition_factor: auto for a caller that keeps neighbour lists (the arm's monitor): it
// re-files an object only when its box leaves the fat box, tests every list every round and tells
// the space each round (Space::noteRound). The rounds close the tuner's windows although updates
// are rare, and the factor goes to the least cost the tuner's model counts, C = visits + c events
// (list entries tested, and re-filings that changed an object's leaves), measured here for every
// fixed factor on the same scene (the objects' moves do not depend on the space).
struct ListedScene {
  std::uint64_t visits = 0;
  std::uint64_t events = 0;
  std::uint64_t rounds = 0;
  int factorAtEnd = 0;
  std::uint64_t factorChanges = 0;
  double cost(double c) const { return static_cast<double>(visits) + c * static_cast<double>(events); }
};

ListedScene listedScene(int df, bool autoFactor, double regionCost) {
  constexpr int kObjects = 400, kRounds = 1200;
  constexpr double kMargin = 1.0;
  std::mt19937_64 rng(71);
  std::uniform_real_distribution<double> pos(5, 95), size(0.5, 2.0);
  const Aabb<3> world{Vec3::Zero(), Vec3::Constant(100)};
  SpaceRule rule;
  rule.decompositionFactor = df;
  rule.maxDepth = 6;
  rule.autoFactor = autoFactor;
  rule.autoRegionCost = regionCost;
  Space<3> s(SpaceKind::Tree, world, rule);
  std::vector<Vec3> centre(kObjects), velocity(kObjects);
  std::vector<double> half(kObjects);
  std::vector<Aabb<3>> fat(kObjects);
  std::vector<std::vector<int>> lists(kObjects);
  std::vector<std::uint64_t> filedAt(kObjects);
  std::uint64_t clock = 0;
  auto boxOf = [&](int id) { return boundsOf<3>(centre[id], half[id]); };
  auto gather = [&](int id) {
    lists[id].clear();
    s.forEachNeighbor(id, [&](int j) { lists[id].push_back(j); });
  };
  for (int id = 0; id < kObjects; ++id) {
    for (int k = 0; k < 3; ++k) centre[id][k] = pos(rng);
    velocity[id] = 0.15 * jitter<3>(rng);
    half[id] = size(rng);
    const Aabb<3> b = boxOf(id);
    fat[id] = {b.min.array() - kMargin, b.max.array() + kMargin};
    s.insert(id, b, kMargin);
    filedAt[id] = ++clock;
  }
  for (int id = 0; id < kObjects; ++id) gather(id);
  ListedScene out;
  for (int round = 0; round < kRounds; ++round) {
    // move (bouncing off the walls); re-file an object whose box left its fat box
    for (int id = 0; id < kObjects; ++id) {
      centre[id] += velocity[id];
      for (int k = 0; k < 3; ++k)
        if (centre[id][k] < 5 || centre[id][k] > 95) velocity[id][k] = -velocity[id][k];
      const Aabb<3> b = boxOf(id);
      if ((b.min.array() >= fat[id].min.array()).all() && (b.max.array() <= fat[id].max.array()).all()) continue;
      fat[id] = {b.min.array() - kMargin, b.max.array() + kMargin};
      if (s.update(id, b, kMargin)) ++out.events;
      filedAt[id] = ++clock;
      gather(id);
    }
    // test every list: a pair whose fat boxes overlap is in the list of its more recently filed
    // member (gathered when it was filed, or since, after a change of factor)
    std::uint64_t visits = 0;
    for (int id = 0; id < kObjects; ++id) visits += lists[id].size();
    out.visits += visits;
    ++out.rounds;
    if (s.noteRound(kObjects, visits))
      for (int id = 0; id < kObjects; ++id) gather(id);
    if (round % 200 == 0) {
      for (int i = 0; i < kObjects; ++i)
        for (int j = 0; j < kObjects; ++j)
          if (filedAt[j] < filedAt[i] && fat[i].overlaps(fat[j])) {
            EXPECT_NE(std::find(lists[i].begin(), lists[i].end(), j), lists[i].end())
                << "df " << df << (autoFactor ? " auto" : "") << ": " << j << " missing from " << i << "'s list";
          }
    }
  }
  out.factorAtEnd = s.rule().decompositionFactor;
  out.factorChanges = s.tuner() ? s.tuner()->factorChanges() : 0;
  return out;
}

TEST(Space, AutoFactorFromRoundsOfKeptLists) {
  for (double c : {3.0, 300.0, 3000.0}) {  // best fixed df 2, 8, 32
    double best = std::numeric_limits<double>::infinity();
    int bestDf = 0;
    std::map<int, double> fixed;
    for (int df : {2, 4, 8, 16, 32, 64, 128}) {
      fixed[df] = listedScene(df, false, c).cost(c);
      if (fixed[df] < best) best = fixed[df], bestDf = df;
    }
    const ListedScene a = listedScene(0, true, c);
    std::string table;
    for (const auto& [df, cost] : fixed) table += " " + std::to_string(df) + ": " + std::to_string(cost / best);
    SCOPED_TRACE("region cost " + std::to_string(c) + ", best fixed df " + std::to_string(bestDf) + ", cost / best:" +
                 table + "; auto ends at df " + std::to_string(a.factorAtEnd) + ", cost / best " +
                 std::to_string(a.cost(c) / best));
    EXPECT_GT(a.factorChanges, 0u);  // the rounds closed windows: the factor moved from its start
    EXPECT_LE(a.cost(c), 1.1 * best);
    EXPECT_TRUE(a.factorAtEnd >= bestDf / 2 && a.factorAtEnd <= 2 * bestDf);
  }
}

}  // namespace
}  // namespace st
