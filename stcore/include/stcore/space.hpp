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
#include <cstdint>
#include <algorithm>
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
  // Calls f(object) once for every object listed in a leaf the box touches.
  template <class F>
  void forEachInBox(const Box& box, F&& f) const;

  // Time from now until a ball (center p, radius r, velocity v) that was last updated into this
  // space could touch a leaf it is not listed in; infinity if never.
  double exitTime(int id, const Vec<D>& p, const Vec<D>& v, double r) const;

  // Leaf regions id is listed in.
  const std::vector<int>& leavesOf(int id) const { return members_[id].leaves; }
  Box leafBounds(int leaf) const;
  const std::vector<int>& objectsIn(int leaf) const;
  // All current leaves (for drawing and invariant checks).
  std::vector<int> leaves() const;
  int depthOf(int leaf) const;

  // Objects whose membership grew because regions reunited since the last call: they may have
  // new neighbours. The simulator re-predicts them.
  std::vector<int> takeWidened();
  bool hasWidened() const { return !widened_.empty(); }

  const SpaceCounters& counters() const { return counters_; }

 private:
  struct Node {
    Box box;
    int parent = -1;
    int firstChild = -1;  // -1 for a leaf
    int depth = 0;
    int count = 0;        // distinct objects whose box overlaps this node
    std::vector<int> objects;  // leaves only
  };
  struct Member {
    Box fat;
    std::vector<int> leaves;
    bool present = false;
    // cells kind: the listed block of cells, so updates and exit times need not recompute it
    Eigen::Array<int, D, 1> lo = Eigen::Array<int, D, 1>::Zero();
    Eigen::Array<int, D, 1> hi = Eigen::Array<int, D, 1>::Zero();
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
  void cellRange(const Box& b, Eigen::Array<int, D, 1>& lo, Eigen::Array<int, D, 1>& hi) const;
  int cellIndex(const Eigen::Array<int, D, 1>& c) const;

  void attach(int id);
  void detach(int id, bool allowCollapse);
  void updateCells(int id, const Box& fat);

  SpaceKind kind_;
  Box bounds_;
  SpaceRule rule_;
  int childCount_ = 1 << D;
  std::vector<int> splitAxes_;
  SpaceCounters counters_;
  std::vector<Node> nodes_;
  std::vector<int> freeBlocks_;
  std::vector<Member> members_;
  std::vector<int> widened_;
  // cells
  Eigen::Array<int, D, 1> dims_;
  Vec<D> cellSize_;
  std::vector<std::vector<int>> cells_;
  // neighbour de-duplication stamps
  mutable std::vector<std::uint32_t> stamp_;
  mutable std::uint32_t stampNow_ = 0;
  std::vector<int> scratch_;
};

// ---- inline templates -------------------------------------------------------------------------

template <int D>
template <class F>
void Space<D>::forEachNeighbor(int id, F&& f) const {
  if (++stampNow_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    stampNow_ = 1;
  }
  stamp_[id] = stampNow_;
  for (int leaf : members_[id].leaves) {
    for (int other : objectsIn(leaf)) {
      if (stamp_[other] == stampNow_) continue;
      stamp_[other] = stampNow_;
      f(other);
    }
  }
}

template <int D>
template <class F>
void Space<D>::forEachInBox(const Box& box, F&& f) const {
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
  const Box b = clampToBounds(box);
  if (kind_ == SpaceKind::Cells) {
    Eigen::Array<int, D, 1> lo, hi;
    cellRange(b, lo, hi);
    Eigen::Array<int, D, 1> c = lo;
    while (true) {
      visitLeaf(cells_[cellIndex(c)]);
      int k = 0;
      for (; k < D; ++k) {
        if (++c[k] <= hi[k]) break;
        c[k] = lo[k];
      }
      if (k == D) break;
    }
    return;
  }
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
