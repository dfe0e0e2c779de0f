#pragma once
// Fixed uniform cells over the bounds, never divided: the broadphase for many objects of about
// one size (hard disks, cars on a network). An object is listed in the block of cells its box
// (grown by its margin: a "fat" box, so that small moves change nothing) touches.
//
// One flat array, stride_ ints per cell: [count, entry...]. An entry is (object << D) | bits, bit k
// set when the cell is the first of the object's block along axis k, so a walk over another block
// meets each object once (at the first cell both blocks share) without marking it. A cell that
// outgrows the stride doubles it for all.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <stcore/broadphase.hpp>

namespace st {

// The most cells a grid over a whole network gets (4e6: 16 MB of cell heads at most).
inline constexpr double kMaxGridCells = 4e6;

// The edge of a uniform grid's cells: `target`, doubled until the grid over `extent` has at most
// `maxCells` cells. The one sizing rule of every grid in stsim.
template <int D>
double gridCellSize(const Vec<D>& extent, double target, double maxCells = kMaxGridCells);

template <int D>
class UniformGrid {
 public:
  using Box = Aabb<D>;
  using Index = Eigen::Array<int, D, 1>;

  UniformGrid(const Box& bounds, double cellSize);

  const Box& bounds() const { return bounds_; }

  void insert(int id, const Box& box, double margin = 0.0);
  void update(int id, const Box& box, double margin = 0.0);
  void remove(int id);
  bool contains(int id) const { return id >= 0 && id < static_cast<int>(members_.size()) && members_[id].present; }

  template <class F>
  void forEachNeighbor(int id, F&& f) const;
  // The objects forEachNeighbor would visit, written to out in its order without a branch per
  // entry; how many, or -1 if more than `room` entries had to be looked at.
  int gatherNeighbors(int id, int* out, int room) const;
  // The objects forEachInBox would visit, written to out in its order, a row of cells along the
  // first axis at a time (contiguous cells, the other axes' corner bits fixed); how many, or -1 if
  // more than `room` entries had to be looked at.
  int gatherInBox(const Box& box, int* out, int room) const;
  // The objects of the cells entered by id's last update: a superset of its new neighbours.
  template <class F>
  void forEachNeighborGained(int id, F&& f) const;
  template <class F>
  void forEachInBox(const Box& box, F&& f) const;
  template <class F>
  void forEachPair(F&& f) const;
  // The first and last cell of the block a box touches: what forEachInBox visits depends on the
  // box through this block only (the same objects in the same order while the grid is unchanged).
  std::array<int, 2> cellBlock(const Box& box) const;
  // Changes whenever an insert, remove or update changes an object's block: with cellBlock, the
  // key of a cached visit.
  std::uint64_t revision() const { return revision_; }

  // Time until the ball's box first touches a cell outside its listed block (the path's
  // acceleration is not used: the straight path from the same state reaches every wall first,
  // a safe early bound); infinity if never.
  double exitTime(int id, const BallPath<D>& path) const;
  // fat boxes: a margin of fatFraction * radius around each ball (fewer region events, more
  // candidates)
  static double listingMargin(double radius, double fatFraction) { return fatFraction * radius; }

  std::vector<int> leaves() const;
  Box leafBounds(int cell) const;
  ObjectList objectsIn(int cell) const;
  // The cells id is listed in (filled on demand, valid until the next call).
  const std::vector<int>& leavesOf(int id) const;
  int depthOf(int /*cell*/) const { return 0; }
  int leafCount() const { return cellCount_; }
  const Index& dims() const { return dims_; }
  const SpaceCounters& counters() const { return counters_; }

 private:
  struct Member {
    // the listed block of cells, and the block before the last update (first: all an update reads)
    Index lo = Index::Zero();
    Index hi = Index::Zero();
    Index prevLo = Index::Zero();
    Index prevHi = Index::Zero();
    bool present = false;
    mutable std::vector<int> leaves;  // a cache for leavesOf
  };

  void cellRange(const Box& b, Index& lo, Index& hi) const;
  int cellIndex(const Index& c) const {
    int idx = 0;
    for (int i = D - 1; i >= 0; --i) idx = idx * dims_[i] + c[i];
    return idx;
  }
  // bit k set when c[k] == lo[k]: c is the block's first cell along axis k
  static int cornerBits(const Index& c, const Index& lo) {
    int bits = 0;
    for (int k = 0; k < D; ++k) bits |= (c[k] == lo[k] ? 1 : 0) << k;
    return bits;
  }
  // f(cell index, cell coordinates) for every cell of the block [lo, hi]
  template <class F>
  void forEachCell(const Index& lo, const Index& hi, F&& f) const;
  // f(entry) for every entry of a cell block touched by [lo, hi] that is listed there for the
  // first cell the two blocks share: each object once, without marks
  template <class F>
  void forEachEntryOnce(const Index& lo, const Index& hi, F&& f) const;
  void cellPush(int idx, int entry);
  void cellErase(int idx, int entry);

  Box bounds_;
  Index dims_;
  Vec<D> cellSize_;
  int cellCount_ = 0;
  int stride_ = 8;
  std::vector<int> cellData_;
  std::vector<Member> members_;
  SpaceCounters counters_;
  std::uint64_t revision_ = 0;
};

// ---- inline templates -------------------------------------------------------------------------

template <int D>
template <class F>
void UniformGrid<D>::forEachCell(const Index& lo, const Index& hi, F&& f) const {
  Index c = lo;
  while (true) {
    f(cellIndex(c), c);
    int k = 0;
    for (; k < D; ++k) {
      if (++c[k] <= hi[k]) break;
      c[k] = lo[k];
    }
    if (k == D) break;
  }
}

// An object listed in cell c of the walked block [lo, hi] is met there first iff c is the first
// cell, along every axis, of the overlap of its block with [lo, hi]: c[k] is lo[k] or the object's own lo.
template <int D>
template <class F>
void UniformGrid<D>::forEachEntryOnce(const Index& lo, const Index& hi, F&& f) const {
  constexpr int kAll = (1 << D) - 1;
  forEachCell(lo, hi, [&](int idx, const Index& c) {
    const int bits = cornerBits(c, lo);
    const int* cell = cellData_.data() + static_cast<std::ptrdiff_t>(idx) * stride_;
    const int n = cell[0];
    for (int k = 1; k <= n; ++k)
      if (((cell[k] | bits) & kAll) == kAll) f(cell[k]);
  });
}

template <int D>
template <class F>
void UniformGrid<D>::forEachNeighbor(int id, F&& f) const {
  const Member& m = members_[id];
  forEachEntryOnce(m.lo, m.hi, [&](int entry) {
    const int other = entry >> D;
    if (other != id) f(other);
  });
}

template <int D>
inline int UniformGrid<D>::gatherNeighbors(int id, int* out, int room) const {
  constexpr int kAll = (1 << D) - 1;
  const Member& m = members_[id];
  int n = 0;
  bool fits = true;
  forEachCell(m.lo, m.hi, [&](int idx, const Index& c) {
    const int* cell = cellData_.data() + static_cast<std::ptrdiff_t>(idx) * stride_;
    const int count = cell[0];
    if (n + count > room) fits = false;
    if (!fits) return;
    const int bits = cornerBits(c, m.lo);
    for (int k = 1; k <= count; ++k) {
      const int other = cell[k] >> D;
      out[n] = other;
      n += static_cast<int>((((cell[k] | bits) & kAll) == kAll) & (other != id));
    }
  });
  return fits ? n : -1;
}

template <int D>
inline int UniformGrid<D>::gatherInBox(const Box& box, int* out, int room) const {
  constexpr int kAll = (1 << D) - 1;
  Index lo, hi;
  cellRange(detail::clampBox(box, bounds_), lo, hi);
  int n = 0;
  Index c = lo;
  while (true) {
    int rowBits = 0;
    for (int k = 1; k < D; ++k) rowBits |= (c[k] == lo[k] ? 1 : 0) << k;
    const int* cell = cellData_.data() + static_cast<std::ptrdiff_t>(cellIndex(c)) * stride_;
    for (int x = lo[0]; x <= hi[0]; ++x, cell += stride_) {
      const int count = cell[0];
      if (n + count > room) return -1;
      const int bits = rowBits | (x == lo[0] ? 1 : 0);
      for (int k = 1; k <= count; ++k) {
        out[n] = cell[k] >> D;
        n += static_cast<int>(((cell[k] | bits) & kAll) == kAll);
      }
    }
    int k = 1;
    for (; k < D; ++k) {
      if (++c[k] <= hi[k]) break;
      c[k] = lo[k];
    }
    if (k == D) break;
  }
  return n;
}

template <int D>
template <class F>
void UniformGrid<D>::forEachNeighborGained(int id, F&& f) const {
  // the cells entered: an object met first in one of them may be new; one met first in a cell
  // kept shares that cell with id and was a neighbour already
  constexpr int kAll = (1 << D) - 1;
  const Member& m = members_[id];
  if ((m.lo == m.prevLo).all() && (m.hi == m.prevHi).all()) return;
  forEachCell(m.lo, m.hi, [&](int idx, const Index& c) {
    if ((c >= m.prevLo).all() && (c <= m.prevHi).all()) return;
    const int bits = cornerBits(c, m.lo);
    const int* cell = cellData_.data() + static_cast<std::ptrdiff_t>(idx) * stride_;
    const int n = cell[0];
    for (int k = 1; k <= n; ++k) {
      if (((cell[k] | bits) & kAll) != kAll) continue;
      const int other = cell[k] >> D;
      if (other != id) f(other);
    }
  });
}

template <int D>
template <class F>
void UniformGrid<D>::forEachInBox(const Box& box, F&& f) const {
  Index lo, hi;
  cellRange(detail::clampBox(box, bounds_), lo, hi);
  forEachEntryOnce(lo, hi, [&](int entry) { f(entry >> D); });
}

template <int D>
template <class F>
void UniformGrid<D>::forEachPair(F&& f) const {
  detail::pairsFromNeighbors(*this, static_cast<int>(members_.size()), f);
}

extern template class UniformGrid<2>;
extern template class UniformGrid<3>;

}  // namespace st
