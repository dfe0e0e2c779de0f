#pragma once
// The report's Space (§1.2.9, §2.6): regions that hold objects, subdivide past a decomposition
// factor and reunite below it. One dimension-generic class, three kinds:
//   Single  one region, never divided (the report's version I with one space);
//   Tree    the dynamic quadtree (2-D) / octree (3-D) of version II;
//   Cells   fixed uniform cells, no subdivision.
// (The report's "no space" is not a space: callers test every pair themselves.)
//
// An object is listed in every leaf region its box touches. Boxes are kept "fat" (grown by a
// margin) so that an object moving a little does not change membership; the space tells the
// caller how long the current membership stays valid for a moving ball (exitTime).
// Nodes live in one pool (std::vector) addressed by int, children in contiguous blocks reused
// through a free list.
#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <array>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <stcore/shapes.hpp>

namespace st {

enum class SpaceKind { None, Single, Tree, Cells };

// Parses "none", "single", "tree"/"quadtree"/"octree", "cells"; returns false if unknown.
bool parseSpaceKind(const std::string& text, SpaceKind& out);
const char* toString(SpaceKind kind);

// The report's Rule (§1.2.11).
struct SpaceRule {
  int decompositionFactor = 5;  // a leaf holding more objects than this subdivides
  bool subdivide = true;        // false: the space never divides
  int divisions = 0;            // children per division: 2, 4 or 8 (<= 2^D); 0 means 2^D
  int maxDepth = 12;            // a leaf this deep never divides (objects that overlap all children)
  double cellSize = 0.0;        // Cells kind: edge length of a cell (m)
  // A leaf does not divide when half its longest edge is shorter than this times the smallest
  // (fat) object box it holds: children that small cannot separate objects that overlap,
  // and dense clusters of more than df objects would split down to maxDepth. 0: only maxDepth.
  double minChildSizeRatio = 0.0;
};

struct SpaceCounters {
  std::uint64_t subdivisions = 0;
  std::uint64_t reunions = 0;
  std::uint64_t transfers = 0;  // membership changes of an object (the report's TransferObject)
};

// The objects listed in one leaf: a view, valid until the space changes. Cells store each entry as
// (object << D) | corner bits (see Space::cellData_); the view yields the objects.
class ObjectList {
 public:
  class iterator {
   public:
    using iterator_category = std::input_iterator_tag;
    using iterator_concept = std::forward_iterator_tag;
    using value_type = int;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = int;
    iterator() = default;
    iterator(const int* p, int shift) : p_(p), shift_(shift) {}
    int operator*() const { return *p_ >> shift_; }
    iterator& operator++() {
      ++p_;
      return *this;
    }
    iterator operator++(int) {
      iterator old = *this;
      ++p_;
      return old;
    }
    bool operator==(const iterator& o) const { return p_ == o.p_; }

   private:
    const int* p_ = nullptr;
    int shift_ = 0;
  };
  ObjectList(const int* first, std::size_t count, int shift) : first_(first), count_(count), shift_(shift) {}
  iterator begin() const { return {first_, shift_}; }
  iterator end() const { return {first_ + count_, shift_}; }
  std::size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  int operator[](std::size_t k) const { return first_[k] >> shift_; }

 private:
  const int* first_;
  std::size_t count_;
  int shift_;
};

template <int D>
class Space {
 public:
  using Box = Aabb<D>;

  Space(SpaceKind kind, const Box& bounds, const SpaceRule& rule);

  SpaceKind kind() const { return kind_; }
  const SpaceRule& rule() const { return rule_; }
  const Box& bounds() const { return bounds_; }

  // Objects are identified by the caller's dense ids (0, 1, 2, ...). `margin` grows the box.
  void insert(int id, const Box& box, double margin = 0.0);
  void update(int id, const Box& box, double margin = 0.0);
  void remove(int id);
  bool contains(int id) const { return id < static_cast<int>(members_.size()) && members_[id].present; }

  // Calls f(other) once for every other object sharing a leaf with id.
  template <class F>
  void forEachNeighbor(int id, F&& f) const;
  // Cells kind: the objects forEachNeighbor would visit, written to out in its order without a
  // branch per entry; how many, or -1 if more than `room` entries had to be looked at.
  int gatherNeighbors(int id, int* out, int room) const;
  // Calls f(other) once for every other object that may share a leaf with id since id's last
  // update and may not have before it: a superset of the new neighbours (cells: the objects of
  // the cells entered; trees: every neighbour).
  template <class F>
  void forEachNeighborGained(int id, F&& f) const;
  // Calls f(object) once for every object listed in a leaf the box touches.
  template <class F>
  void forEachInBox(const Box& box, F&& f) const;
  // Cells kind: the first and last cell of the block of cells a box touches. What forEachInBox
  // visits depends on the box through this block only (the same objects in the same order while
  // the space is unchanged), so a caller may keep what it found per block. Trees: {-1, -1}.
  std::array<int, 2> cellBlock(const Box& box) const;
  // Changes whenever an insert, remove or update may change what forEachInBox visits (cells: an
  // object's block of cells changed): with cellBlock, the key of a cached visit.
  std::uint64_t revision() const { return revision_; }

  // Time from now until a ball (center p, radius r, velocity v) that was last updated into this
  // space could touch a leaf it is not listed in; infinity if never.
  double exitTime(int id, const Vec<D>& p, const Vec<D>& v, double r) const;

  // Leaf regions id is listed in (cells: filled on demand, valid until the next call).
  const std::vector<int>& leavesOf(int id) const;
  Box leafBounds(int leaf) const;
  ObjectList objectsIn(int leaf) const;
  // All current leaves (for drawing and invariant checks).
  std::vector<int> leaves() const;
  int depthOf(int leaf) const;

  // Objects whose membership grew because regions reunited since the last call: they may have
  // new neighbours. The simulator re-predicts them.
  std::vector<int> takeWidened();
  bool hasWidened() const { return !widened_.empty(); }

  const SpaceCounters& counters() const { return counters_; }
  // True while a tree is subdivided (its root has children); Single and Cells never are.
  bool divided() const { return kind_ == SpaceKind::Tree && !nodes_.empty() && nodes_[0].firstChild >= 0; }

 private:
  struct Node {
    Box box;
    int parent = -1;
    int firstChild = -1;  // -1 for a leaf
    int depth = 0;
    int count = 0;        // distinct objects whose box overlaps this node
    std::vector<int> objects;  // leaves only
  };
  using Index = Eigen::Array<int, D, 1>;
  struct Member {
    // cells kind: the listed block of cells, and the block before the last update (first: all a
    // cells update reads)
    Index lo = Index::Zero();
    Index hi = Index::Zero();
    Index prevLo = Index::Zero();
    Index prevHi = Index::Zero();
    bool present = false;
    Box fat;  // trees (cells: as inserted)
    // trees: the leaves; cells: a cache for leavesOf (the block above is the membership)
    mutable std::vector<int> leaves;
  };

  Box clampToBounds(const Box& b) const;
  int childCount() const { return childCount_; }
  // tree
  void addRec(int node, int id);
  void removeRec(int node, int id);
  void maybeSplit(int leaf);
  void collapse(int node);
  void collapseUpFrom(int node);
  int allocBlock();
  // cells
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

  void attach(int id);
  void detach(int id, bool allowCollapse);
  void updateCells(int id, const Box& fat);

  SpaceKind kind_;
  Box bounds_;
  SpaceRule rule_;
  int childCount_ = 1 << D;
  std::vector<int> splitAxes_;
  SpaceCounters counters_;
  std::uint64_t revision_ = 0;
  std::vector<Node> nodes_;
  std::vector<int> freeBlocks_;
  std::vector<Member> members_;
  std::vector<int> widened_;
  // cells: one flat array, stride_ ints per cell: [count, entry...]. An entry is
  // (object << D) | bits, bit k set when the cell is the first of the object's block along axis k,
  // so a walk over another block meets each object once (at the first cell both blocks share)
  // without marking it. A cell that outgrows the stride doubles it for all.
  Index dims_;
  Vec<D> cellSize_;
  int cellCount_ = 0;
  int stride_ = 8;
  std::vector<int> cellData_;
  // trees: neighbour de-duplication stamps
  mutable std::vector<std::uint32_t> stamp_;
  mutable std::uint32_t stampNow_ = 0;
  // trees: an update's old and new leaves (kept to reuse their storage: an update allocates nothing)
  std::vector<int> scratch_;
  std::vector<int> scratchNow_;
};

// ---- inline templates -------------------------------------------------------------------------

template <int D>
template <class F>
void Space<D>::forEachCell(const Index& lo, const Index& hi, F&& f) const {
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
void Space<D>::forEachEntryOnce(const Index& lo, const Index& hi, F&& f) const {
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
void Space<D>::forEachNeighbor(int id, F&& f) const {
  if (kind_ == SpaceKind::Cells) {
    const Member& m = members_[id];
    forEachEntryOnce(m.lo, m.hi, [&](int entry) {
      const int other = entry >> D;
      if (other != id) f(other);
    });
    return;
  }
  if (++stampNow_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    stampNow_ = 1;
  }
  stamp_[id] = stampNow_;
  for (int leaf : members_[id].leaves) {
    for (int other : nodes_[leaf].objects) {
      if (stamp_[other] == stampNow_) continue;
      stamp_[other] = stampNow_;
      f(other);
    }
  }
}

template <int D>
int Space<D>::gatherNeighbors(int id, int* out, int room) const {
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
template <class F>
void Space<D>::forEachNeighborGained(int id, F&& f) const {
  if (kind_ != SpaceKind::Cells) {
    forEachNeighbor(id, f);
    return;
  }
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
void Space<D>::forEachInBox(const Box& box, F&& f) const {
  const Box b = clampToBounds(box);
  if (kind_ == SpaceKind::Cells) {
    Index lo, hi;
    cellRange(b, lo, hi);
    forEachEntryOnce(lo, hi, [&](int entry) { f(entry >> D); });
    return;
  }
  if (++stampNow_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    stampNow_ = 1;
  }
  auto visitLeaf = [&](const std::vector<int>& objs) {
    for (int other : objs) {
      if (stamp_[other] == stampNow_) continue;
      stamp_[other] = stampNow_;
      f(other);
    }
  };
  // iterative tree walk
  int stackBuf[256];
  int top = 0;
  stackBuf[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stackBuf[--top]];
    if (!n.box.overlaps(b)) continue;
    if (n.firstChild < 0) {
      visitLeaf(n.objects);
    } else {
      for (int c = 0; c < childCount_; ++c) stackBuf[top++] = n.firstChild + c;
    }
  }
}

extern template class Space<2>;
extern template class Space<3>;

}  // namespace st
