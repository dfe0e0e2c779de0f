// StaticGrid against brute force written here: on random scenes (2-D and 3-D, boxes from a speck
// to most of the grid, some past its edges, some not listed) each cell lists exactly the boxes
// that touch it (a cell being half open, the border cells reaching out to infinity), in
// increasing id; pairs and box queries are exactly "shares a cell", each once, and cover every
// two overlapping boxes.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <stcore/static_grid.hpp>

namespace st {
namespace {

template <int D>
struct Scene {
  Vec<D> origin, extent;
  double target = 1.0;
  std::vector<std::optional<Aabb<D>>> boxes;
};

template <int D>
Scene<D> randomScene(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Scene<D> s;
  for (int i = 0; i < D; ++i) {
    s.origin[i] = -50.0 + 100.0 * unit(rng);
    s.extent[i] = 1.0 + 60.0 * unit(rng);
  }
  s.target = 0.5 + 8.0 * unit(rng);
  for (int k = 0; k < n; ++k) {
    if (rng() % 10 == 0) {
      s.boxes.push_back(std::nullopt);
      continue;
    }
    Aabb<D> b;
    const double u = unit(rng);
    for (int i = 0; i < D; ++i) {
      const double c = s.origin[i] + s.extent[i] * (-0.2 + 1.4 * unit(rng));
      const double half = u < 0.1 ? 0.0 : u < 0.2 ? 0.6 * s.extent[i] * unit(rng) : 2.0 * unit(rng);
      b.min[i] = c - half;
      b.max[i] = c + half;
    }
    s.boxes.push_back(b);
  }
  return s;
}

// Does the closed box touch cell c? Along each axis the cell is [o + c s, o + (c + 1) s), the
// first reaching down to -infinity and the last up to +infinity.
template <int D>
bool touches(const Aabb<D>& b, const Eigen::Array<int, D, 1>& c, const StaticGrid<D>& g) {
  for (int i = 0; i < D; ++i) {
    const double lo = g.origin()[i] + c[i] * g.cellSize(), hi = g.origin()[i] + (c[i] + 1) * g.cellSize();
    const bool first = c[i] == 0, last = c[i] == g.dims()[i] - 1;
    if (!last && !(b.min[i] < hi)) return false;
    if (!first && !(b.max[i] >= lo)) return false;
  }
  return true;
}

template <int D>
std::vector<Eigen::Array<int, D, 1>> allCells(const StaticGrid<D>& g) {
  std::vector<Eigen::Array<int, D, 1>> out;
  Eigen::Array<int, D, 1> c = Eigen::Array<int, D, 1>::Zero();
  while (true) {
    out.push_back(c);
    int k = 0;
    for (; k < D; ++k) {
      if (++c[k] < g.dims()[k]) break;
      c[k] = 0;
    }
    if (k == D) break;
  }
  return out;
}

template <int D>
void checkScene(const Scene<D>& s) {
  StaticGrid<D> g(s.origin, s.extent, s.target);
  const int n = static_cast<int>(s.boxes.size());
  g.build(n, [&](int i) { return s.boxes[i]; });
  // the cells cover the extent at the target size or coarser
  for (int i = 0; i < D; ++i) ASSERT_GE(g.dims()[i] * g.cellSize(), s.extent[i]);
  ASSERT_GE(g.cellSize(), s.target);

  const auto cells = allCells(g);
  ASSERT_EQ(static_cast<int>(cells.size()), g.cellCount());
  std::vector<std::vector<int>> truth(cells.size());
  std::set<std::pair<int, int>> pairs;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    for (int i = 0; i < n; ++i)
      if (s.boxes[i] && touches(*s.boxes[i], cells[k], g)) truth[k].push_back(i);
    const auto listed = g.objectsIn(cells[k]);
    ASSERT_EQ(std::vector<int>(listed.begin(), listed.end()), truth[k]) << "cell " << k;
    for (std::size_t a = 0; a < truth[k].size(); ++a)
      for (std::size_t b = a + 1; b < truth[k].size(); ++b) pairs.insert({truth[k][a], truth[k][b]});
  }
  std::multiset<std::pair<int, int>> got;
  g.forEachPair([&](int a, int b) {
    EXPECT_LT(a, b);
    got.insert({a, b});
  });
  EXPECT_EQ(got, (std::multiset<std::pair<int, int>>(pairs.begin(), pairs.end())));
  // every two overlapping boxes share a cell
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      if (s.boxes[a] && s.boxes[b] && s.boxes[a]->overlaps(*s.boxes[b])) {
        EXPECT_TRUE(pairs.count({a, b})) << a << " " << b;
      }

  // box queries (each box of the scene as the query): each object sharing a cell with it, once
  for (int q = 0; q < n; ++q) {
    if (!s.boxes[q]) continue;
    const Aabb<D>& box = *s.boxes[q];
    std::set<int> want;
    for (std::size_t k = 0; k < cells.size(); ++k)
      if (touches(box, cells[k], g)) want.insert(truth[k].begin(), truth[k].end());
    std::multiset<int> seen;
    g.forEachInBox(box, [&](int id) { seen.insert(id); });
    EXPECT_EQ(seen, (std::multiset<int>(want.begin(), want.end())));
  }
  // a point's cell, and nothing outside the grid
  for (const Eigen::Array<int, D, 1>& c : cells) {
    Vec<D> p;
    for (int i = 0; i < D; ++i) p[i] = s.origin[i] + (c[i] + 0.5) * g.cellSize();
    EXPECT_TRUE((g.cellOf(p) == c).all());
  }
  EXPECT_FALSE(g.inGrid(g.cellOf(s.origin - Vec<D>::Constant(1e-3))));
  EXPECT_TRUE(g.objectsIn(g.cellOf(s.origin - Vec<D>::Constant(g.cellSize()))).empty());
}

TEST(StaticGrid, CellsListExactlyTheBoxesThatTouchThem2D) {
  std::mt19937_64 rng(11);
  for (int scene = 0; scene < 300; ++scene) {
    const Scene<2> s = randomScene<2>(rng, 1 + static_cast<int>(rng() % 60));
    checkScene(s);
    if (HasFatalFailure()) return;
  }
}

TEST(StaticGrid, CellsListExactlyTheBoxesThatTouchThem3D) {
  std::mt19937_64 rng(12);
  for (int scene = 0; scene < 100; ++scene) {
    const Scene<3> s = randomScene<3>(rng, 1 + static_cast<int>(rng() % 40));
    checkScene(s);
    if (HasFatalFailure()) return;
  }
}

TEST(StaticGrid, CoarsensToStayWithinTheCellBudget) {
  StaticGrid<2> g(Vec2(0, 0), Vec2(1e5, 1e5), 1.0, 1e6);
  EXPECT_LE(g.cellCount(), 1e6 * 1.01);
  EXPECT_GE(g.cellSize(), 100.0);
  g.build(1, [](int) { return std::optional<Aabb<2>>(Aabb<2>{Vec2(5e4, 5e4), Vec2(5e4, 5e4)}); });
  EXPECT_EQ(g.objectsIn(g.cellOf(Vec2(5e4, 5e4))).size(), 1u);
  // an empty grid answers nothing
  StaticGrid<2> none;
  EXPECT_TRUE(none.empty());
  EXPECT_TRUE(none.objectsIn(none.cellOf(Vec2(0.5, 0.5))).empty());
}

}  // namespace
}  // namespace st
