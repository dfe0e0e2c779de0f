#pragma once
// Objects that never move (lane segments, radio sites), bucketed once into uniform cells and
// packed cell by cell: the broadphase for a fixed set queried many times. Where UniformGrid keeps
// room in every cell for objects that come and go, this grid stores each cell's list end to end,
// so one crowded cell (a junction) costs only its own entries.
//
// Each cell lists, in increasing id, the objects whose box touches it. The grid's cells have the
// edge gridCellSize(extent, target), from an origin on until they cover the extent; a box reaching
// past them is listed in the border cells it reaches over.
#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

#include <stcore/uniform_grid.hpp>

namespace st {

template <int D>
class StaticGrid {
 public:
  using Box = Aabb<D>;
  using Index = Eigen::Array<int, D, 1>;

  StaticGrid() = default;
  // Cells of about `target` (coarser if `extent` would need more than maxCells) from `origin`.
  StaticGrid(const Vec<D>& origin, const Vec<D>& ext, double target, double maxCells = kMaxGridCells)
      : origin_(origin) {
    if (!((ext.array() >= 0.0).all()) || !(target > 0.0))
      throw std::invalid_argument("static grid: bounds need a non-negative extent and cells a positive size");
    cellSize_ = gridCellSize<D>(ext, target, maxCells);
    for (int i = 0; i < D; ++i) dims_[i] = std::max(1, static_cast<int>(std::ceil(ext[i] / cellSize_)));
    cellCount_ = dims_.prod();
  }

  // Lists objects 0..count-1: boxOf(i) gives object i's box, or nullopt for an id not listed.
  template <class BoxOf>
  void build(int count, BoxOf&& boxOf);

  double cellSize() const { return cellSize_; }
  const Vec<D>& origin() const { return origin_; }
  const Index& dims() const { return dims_; }
  int cellCount() const { return cellCount_; }
  bool empty() const { return entries_.empty(); }

  // The cell p lies in, unclamped: outside the grid when p is outside the bounds.
  Index cellOf(const Vec<D>& p) const {
    const Vec<D> g = (p - origin_) / cellSize_;
    Index c;
    for (int i = 0; i < D; ++i) c[i] = static_cast<int>(std::floor(g[i]));
    return c;
  }
  bool inGrid(const Index& c) const { return (c >= 0).all() && (c < dims_).all(); }
  // The objects listed in cell c, in increasing id; none outside the grid.
  std::span<const int> objectsIn(const Index& c) const {
    if (!inGrid(c)) return {};
    return objectsIn(cellIndex(c));
  }
  // The objects listed in cell k (0 <= k < cellCount()), in increasing id.
  std::span<const int> objectsIn(int k) const {
    return {entries_.data() + start_[k], static_cast<std::size_t>(start_[k + 1] - start_[k])};
  }
  // f(id) once for every object whose cell block touches the cells `box` touches.
  template <class F>
  void forEachInBox(const Box& box, F&& f) const;
  // f(a, b), a < b, once for every two objects listed in a common cell.
  template <class F>
  void forEachPair(F&& f) const;

 private:
  int cellIndex(const Index& c) const {
    int k = 0;
    for (int i = D - 1; i >= 0; --i) k = k * dims_[i] + c[i];
    return k;
  }
  // the block of cells a box touches, clamped to the grid
  void block(const Box& b, Index& lo, Index& hi) const {
    for (int i = 0; i < D; ++i) {
      lo[i] = std::clamp(static_cast<int>(std::floor((b.min[i] - origin_[i]) / cellSize_)), 0, dims_[i] - 1);
      hi[i] = std::clamp(static_cast<int>(std::floor((b.max[i] - origin_[i]) / cellSize_)), 0, dims_[i] - 1);
    }
  }
  template <class F>
  static void forEachCell(const Index& lo, const Index& hi, F&& f) {
    Index c = lo;
    while (true) {
      f(c);
      int k = 0;
      for (; k < D; ++k) {
        if (++c[k] <= hi[k]) break;
        c[k] = lo[k];
      }
      if (k == D) break;
    }
  }

  Vec<D> origin_ = Vec<D>::Zero();
  double cellSize_ = 1.0;
  Index dims_ = Index::Ones();
  int cellCount_ = 1;
  std::vector<int> start_ = std::vector<int>(2, 0);  // cell k's entries: [start_[k], start_[k+1])
  std::vector<int> entries_;
  std::vector<Index> lo_, hi_;  // each object's block (lo > hi: not listed)
};

template <int D>
template <class BoxOf>
void StaticGrid<D>::build(int count, BoxOf&& boxOf) {
  if (count < 0) throw std::invalid_argument("static grid: negative object count");
  lo_.assign(static_cast<std::size_t>(count), Index::Ones());
  hi_.assign(static_cast<std::size_t>(count), Index::Zero());
  std::vector<int> fill(static_cast<std::size_t>(cellCount_) + 1, 0);
  for (int i = 0; i < count; ++i) {
    const std::optional<Box> b = boxOf(i);
    if (!b) continue;
    block(*b, lo_[i], hi_[i]);
    forEachCell(lo_[i], hi_[i], [&](const Index& c) { ++fill[cellIndex(c) + 1]; });
  }
  for (int k = 0; k < cellCount_; ++k) fill[k + 1] += fill[k];
  start_ = fill;
  entries_.assign(static_cast<std::size_t>(start_.back()), 0);
  for (int i = 0; i < count; ++i) {
    if ((lo_[i] > hi_[i]).any()) continue;
    forEachCell(lo_[i], hi_[i], [&](const Index& c) { entries_[fill[cellIndex(c)]++] = i; });
  }
}

// An object of the walked block [lo, hi] is met first in the cell where its own block and the
// walked one start: along every axis, the larger of the two blocks' first cells.
template <int D>
template <class F>
void StaticGrid<D>::forEachInBox(const Box& box, F&& f) const {
  if (entries_.empty()) return;
  Index lo, hi;
  block(box, lo, hi);
  forEachCell(lo, hi, [&](const Index& c) {
    for (int id : objectsIn(c))
      if ((c == lo_[id].max(lo)).all()) f(id);
  });
}

template <int D>
template <class F>
void StaticGrid<D>::forEachPair(F&& f) const {
  for (int a = 0; a < static_cast<int>(lo_.size()); ++a) {
    if ((lo_[a] > hi_[a]).any()) continue;
    forEachCell(lo_[a], hi_[a], [&](const Index& c) {
      for (int b : objectsIn(c))
        if (b > a && (c == lo_[a].max(lo_[b])).all()) f(a, b);
    });
  }
}

}  // namespace st
