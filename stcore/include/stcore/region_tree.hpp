#pragma once
// The report's space (§1.2.9, §2.6): regions that hold objects, subdivide into 2, 4 or 8 equal
// children when they hold more than the decomposition factor, and reunite when the objects
// within a divided region's bounds number the factor or fewer; a quadtree in 2-D, an octree in
// 3-D. An object lying across region walls is listed in every leaf its box (closed) touches.
//
// The tree is a function of its contents: a leaf divides iff it holds more than the factor, is
// above maxDepth and the size ratio, and some child would hold fewer objects than it (objects
// all lying across its middle cannot be separated by dividing it); every operation restores that.
//
// A ball's region events (exitTime) come from the walls of the leaves it is listed in: the first
// time its box starts to touch a leaf it is not listed in, or its listed box (grown by the
// margin it was given) stops touching one. The margin is the slop against rounding: with a
// margin m, membership is taken m beyond the ball, and a leaf is left only once the ball is 2m
// clear of it, so the update at the event always sees the change.
//
// Nodes live in one pool (std::vector) addressed by int, children in contiguous blocks reused
// through a free list.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <stcore/broadphase.hpp>
#include <stcore/tolerances.hpp>

namespace st {

template <int D>
class RegionTree {
 public:
  using Box = Aabb<D>;

  RegionTree(const Box& bounds, const SpaceRule& rule);

  const Box& bounds() const { return bounds_; }
  const SpaceRule& rule() const { return rule_; }
  // Puts a new decomposition factor (>= 1) in force: regions now holding df or fewer reunite,
  // leaves holding more divide; the objects re-listed are reported as after any restructure
  // (takeRelisted, takeWidened).
  void setDecompositionFactor(int df);

  void insert(int id, const Box& box, double margin = 0.0);
  // True if the object's leaves changed (it moved between leaves, or leaves it is in divided or
  // reunited).
  bool update(int id, const Box& box, double margin = 0.0);
  void remove(int id);
  bool contains(int id) const { return id >= 0 && id < static_cast<int>(members_.size()) && members_[id].present; }

  template <class F>
  void forEachNeighbor(int id, F&& f) const;
  template <class F>
  void forEachInBox(const Box& box, F&& f) const;
  template <class F>
  void forEachPair(F&& f) const;

  // Time from the path's start until the ball's next region event (see above); infinity if none.
  double exitTime(int id, const BallPath<D>& path) const;
  static constexpr bool kFollowsSlowingPaths = true;  // exact along BallPath::a
  // boxes are listed as they are, with the slop the region events keep against rounding
  static double listingMargin(double /*radius*/, double /*fatFraction*/) { return tol::kRegionSlop; }

  std::vector<int> leaves() const;
  Box leafBounds(int leaf) const { return nodes_[leaf].box; }
  ObjectList objectsIn(int leaf) const {
    const std::vector<int>& objs = nodes_[leaf].objects;
    return {objs.data(), objs.size(), 0};
  }
  const std::vector<int>& leavesOf(int id) const { return members_[id].leaves; }
  int depthOf(int leaf) const { return nodes_[leaf].depth; }
  int leafCount() const { return leafCount_; }
  const SpaceCounters& counters() const { return counters_; }

  // Objects whose leaves a division or a reunion rewrote while another object was inserted,
  // moved or removed, since the last call (sorted, once each): their listed boxes are as last
  // given, so a caller whose objects moved since re-files them.
  std::vector<int> takeRelisted();
  void takeRelisted(std::vector<int>& out);  // the same into out, reusing its storage
  bool hasRelisted() const { return !relisted_.empty(); }
  // Of those, the ones a reunion listed in a wider region: they may have new neighbours.
  std::vector<int> takeWidened();
  void takeWidened(std::vector<int>& out);
  bool hasWidened() const { return !widened_.empty(); }

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
    Box fat;            // the box as given, grown by the margin
    double margin = 0;
    bool present = false;
    std::vector<int> leaves;
  };

  Box listedBox(int id) const { return detail::clampBox(members_[id].fat, bounds_); }
  bool sameLeaves(int id, const Box& next) const;
  void attach(int id);
  void detach(int id);
  void addRec(int id);
  bool moveRec(int id, const Box& before);  // true if a leaf was entered or left
  void restructureAround(int id);
  void removeRec(int id);
  bool shouldSplit(int leaf) const;
  void maybeSplit(int leaf);
  void collapse(int node);
  // reunites the top-most divided ancestor of n (or n) that should no longer be divided
  void collapseUpFrom(int node);
  bool shouldCollapse(int node) const;
  int allocBlock();
  Box childBox(const Box& parent, int c) const;

  Box bounds_;
  SpaceRule rule_;
  int childCount_ = 1 << D;
  int splitAxes_ = D;  // how many of a node's longest axes a division halves
  int leafCount_ = 1;
  SpaceCounters counters_;
  std::vector<Node> nodes_;
  std::vector<int> freeBlocks_;
  std::vector<Member> members_;
  int moving_ = -1;  // the object being inserted, moved or removed (not reported as relisted)
  std::vector<int> relisted_;
  std::vector<int> widened_;
  // neighbour de-duplication stamps
  mutable std::vector<std::uint32_t> stamp_;
  mutable std::uint32_t stampNow_ = 0;
  // an update's old and new leaves (kept to reuse their storage: an update allocates nothing)
  std::vector<int> scratch_;
  std::vector<int> scratchNow_;
  std::vector<int> landed_;  // restructureAround's copy of the leaves; setDecompositionFactor's leaves
  std::vector<int> split_;   // maybeSplit's objects of the leaf it divides
};

// ---- inline templates -------------------------------------------------------------------------

template <int D>
template <class F>
void RegionTree<D>::forEachNeighbor(int id, F&& f) const {
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
template <class F>
void RegionTree<D>::forEachInBox(const Box& box, F&& f) const {
  const Box b = detail::clampBox(box, bounds_);
  if (++stampNow_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    stampNow_ = 1;
  }
  int stack[256];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!n.box.overlaps(b)) continue;
    if (n.firstChild < 0) {
      for (int other : n.objects) {
        if (stamp_[other] == stampNow_) continue;
        stamp_[other] = stampNow_;
        f(other);
      }
    } else {
      for (int c = 0; c < childCount_; ++c) stack[top++] = n.firstChild + c;
    }
  }
}

template <int D>
template <class F>
void RegionTree<D>::forEachPair(F&& f) const {
  detail::pairsFromNeighbors(*this, static_cast<int>(members_.size()), f);
}

extern template class RegionTree<2>;
extern template class RegionTree<3>;

}  // namespace st
