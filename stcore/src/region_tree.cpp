#include <stcore/region_tree.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

#include <stcore/assert.hpp>

namespace st {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// sorted, once each, into out (its storage traded with the list's: neither allocates again)
void takeSorted(std::vector<int>& list, std::vector<int>& out) {
  out.clear();
  out.swap(list);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}
}  // namespace

template <int D>
RegionTree<D>::RegionTree(const Box& bounds, const SpaceRule& rule) : bounds_(bounds), rule_(rule) {
  if (!((bounds.max.array() > bounds.min.array()).all()))
    throw std::invalid_argument("space bounds must have positive extent");
  if (rule_.divisions == 0) rule_.divisions = 1 << D;
  int k = 0;
  while ((1 << k) < rule_.divisions) ++k;
  if ((1 << k) != rule_.divisions || k < 1 || k > D)
    throw std::invalid_argument("space divisions must be 2, 4" + std::string(D == 3 ? " or 8" : ""));
  if (rule_.decompositionFactor < 1) throw std::invalid_argument("decomposition factor must be >= 1");
  childCount_ = rule_.divisions;
  splitAxes_ = k;
  nodes_.push_back(Node{bounds_, -1, -1, 0, 0, {}});
}

template <int D>
std::vector<int> RegionTree<D>::leaves() const {
  std::vector<int> out;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    if (nodes_[n].firstChild < 0) out.push_back(n);
    else for (int c = 0; c < childCount_; ++c) stack.push_back(nodes_[n].firstChild + c);
  }
  std::sort(out.begin(), out.end());
  return out;
}

template <int D>
std::vector<int> RegionTree<D>::takeRelisted() {
  std::vector<int> out;
  takeRelisted(out);
  return out;
}

template <int D>
void RegionTree<D>::takeRelisted(std::vector<int>& out) {
  takeSorted(relisted_, out);
}

template <int D>
std::vector<int> RegionTree<D>::takeWidened() {
  std::vector<int> out;
  takeWidened(out);
  return out;
}

template <int D>
void RegionTree<D>::takeWidened(std::vector<int>& out) {
  takeSorted(widened_, out);
}

// ---- membership ---------------------------------------------------------------------------------

template <int D>
void RegionTree<D>::insert(int id, const Box& box, double margin) {
  if (id < 0) throw std::invalid_argument("space: negative object id");
  if (id >= static_cast<int>(members_.size())) {
    members_.resize(id + 1);
    stamp_.resize(id + 1, 0u);
  }
  Member& m = members_[id];
  if (m.present) throw std::logic_error("space: object inserted twice");
  m.present = true;
  m.fat = detail::grownBox(box, margin);
  m.margin = margin;
  moving_ = id;
  attach(id);
  moving_ = -1;
}

template <int D>
void RegionTree<D>::remove(int id) {
  if (!contains(id)) return;
  moving_ = id;
  scratch_ = members_[id].leaves;
  detach(id);
  members_[id].present = false;
  for (int old : scratch_) collapseUpFrom(old);
  moving_ = -1;
}

// True when the box touches exactly the leaves the object is listed in: all of them, and none
// other, which holds when it lies strictly inside the region its old box could roam without
// touching another (see exitTime: that region is covered by the listed leaves).
template <int D>
bool RegionTree<D>::sameLeaves(int id, const Box& next) const {
  const Member& m = members_[id];
  const Box old = listedBox(id);
  for (int leaf : m.leaves)
    if (!nodes_[leaf].box.overlaps(next)) return false;
  for (int i = 0; i < D; ++i) {
    double hi = kInf, lo = -kInf;
    for (int leaf : m.leaves) {
      const Box& lb = nodes_[leaf].box;
      if (lb.max[i] > old.max[i] && lb.max[i] < bounds_.max[i]) hi = std::min(hi, lb.max[i]);
      if (lb.min[i] < old.min[i] && lb.min[i] > bounds_.min[i]) lo = std::max(lo, lb.min[i]);
    }
    if (!(next.max[i] < hi) || !(next.min[i] > lo)) return false;
  }
  return true;
}

template <int D>
bool RegionTree<D>::update(int id, const Box& box, double margin) {
  if (!contains(id)) throw std::logic_error("space: update of an object not in the space");
  moving_ = id;
  Member& m = members_[id];
  if (nodes_[0].firstChild >= 0 && sameLeaves(id, detail::clampBox(detail::grownBox(box, margin), bounds_))) {
    // the common case (a collision, a move within its leaves): only the box changes, and with it
    // perhaps whether a full leaf it is in could now be divided
    m.fat = detail::grownBox(box, margin);
    m.margin = margin;
    bool split = false;
    if (rule_.subdivide)
      for (std::size_t k = 0; k < m.leaves.size() && !split; ++k) {
        const int leaf = m.leaves[k];
        if (static_cast<int>(nodes_[leaf].objects.size()) > rule_.decompositionFactor) {
          maybeSplit(leaf);
          split = nodes_[leaf].firstChild >= 0;
        }
      }
    if (split) ++counters_.transfers;
    moving_ = -1;
    return split;
  }
  if (nodes_[0].firstChild < 0) {
    // an undivided tree lists every object in its root before and after: only the box changes,
    // and the object moves to the back of the root's list, where the remove and insert below
    // would leave it (a division follows as there)
    m.fat = detail::grownBox(box, margin);
    m.margin = margin;
    std::vector<int>& objects = nodes_[0].objects;
    std::swap(*std::find(objects.begin(), objects.end(), id), objects.back());
    bool split = false;
    if (rule_.subdivide) {
      maybeSplit(0);
      split = nodes_[0].firstChild >= 0;
      if (split) ++counters_.transfers;  // now listed in the root's children
    }
    moving_ = -1;
    return split;
  }
  scratch_ = m.leaves;  // old membership, to count transfers
  const Box before = listedBox(id);
  m.fat = detail::grownBox(box, margin);
  m.margin = margin;
  if (!moveRec(id, before)) {
    // no leaf entered or left: no count changed, so nothing reunites; a full leaf the box no
    // longer straddles may divide (as restructureAround would)
    const std::uint64_t divisions = counters_.subdivisions;
    if (rule_.subdivide)
      for (int leaf : scratch_)
        if (static_cast<int>(nodes_[leaf].objects.size()) > rule_.decompositionFactor) maybeSplit(leaf);
    const bool split = counters_.subdivisions != divisions;
    if (split) ++counters_.transfers;
    moving_ = -1;
    return split;
  }
  std::sort(scratch_.begin(), scratch_.end());
  restructureAround(id);
  scratchNow_ = members_[id].leaves;
  std::sort(scratchNow_.begin(), scratchNow_.end());
  if (scratchNow_ != scratch_) ++counters_.transfers;
  // reunite regions the object left, now that it is listed where it belongs
  for (int old : scratch_) collapseUpFrom(old);
  moving_ = -1;
  scratchNow_ = members_[id].leaves;
  std::sort(scratchNow_.begin(), scratchNow_.end());
  return scratchNow_ != scratch_;
}

template <int D>
void RegionTree<D>::attach(int id) {
  members_[id].leaves.clear();
  addRec(id);
  restructureAround(id);
}

// After id was listed where its box lies: reunite and divide the leaves it landed in.
template <int D>
void RegionTree<D>::restructureAround(int id) {
  // the leaves it landed in, copied (divisions and reunions rewrite them)
  landed_ = members_[id].leaves;
  // lying across more children may leave a divided region with nothing it separates
  for (int leaf : landed_) collapseUpFrom(leaf);
  if (rule_.subdivide) {
    landed_ = members_[id].leaves;
    for (int leaf : landed_) maybeSplit(leaf);
  }
}

// One walk over the nodes the old or the new listed box touches: the counts change only where
// exactly one of them does, and a leaf both touch keeps the object where it is in its list.
template <int D>
bool RegionTree<D>::moveRec(int id, const Box& before) {
  const Box after = listedBox(id);
  Member& m = members_[id];
  m.leaves.clear();
  bool changed = false;
  int stack[256];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const int n = stack[--top];
    Node& node = nodes_[n];
    const bool was = node.box.overlaps(before);
    const bool is = node.box.overlaps(after);
    if (!was && !is) continue;
    if (was != is) {
      node.count += is ? 1 : -1;
      changed = true;
    }
    if (node.firstChild < 0) {
      if (is) {
        if (!was) node.objects.push_back(id);
        m.leaves.push_back(n);
      } else {
        auto it = std::find(node.objects.begin(), node.objects.end(), id);
        STCORE_ASSERT(it != node.objects.end());
        *it = node.objects.back();
        node.objects.pop_back();
      }
    } else {
      for (int c = 0; c < childCount_; ++c) stack[top++] = node.firstChild + c;
    }
  }
  return changed;
}

template <int D>
void RegionTree<D>::detach(int id) {
  removeRec(id);
  members_[id].leaves.clear();
}

template <int D>
void RegionTree<D>::addRec(int id) {
  const Box fat = listedBox(id);
  // explicit stack: nodes_ does not grow here, references stay valid
  int stack[256];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    Node& node = nodes_[stack[--top]];
    if (!node.box.overlaps(fat)) continue;
    ++node.count;
    if (node.firstChild < 0) {
      node.objects.push_back(id);
      members_[id].leaves.push_back(static_cast<int>(&node - nodes_.data()));
    } else {
      for (int c = 0; c < childCount_; ++c) stack[top++] = node.firstChild + c;
    }
  }
}

template <int D>
void RegionTree<D>::removeRec(int id) {
  const Box fat = listedBox(id);
  int stack[256];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    Node& node = nodes_[stack[--top]];
    if (!node.box.overlaps(fat)) continue;
    --node.count;
    if (node.firstChild < 0) {
      auto it = std::find(node.objects.begin(), node.objects.end(), id);
      STCORE_ASSERT(it != node.objects.end());
      *it = node.objects.back();
      node.objects.pop_back();
    } else {
      for (int c = 0; c < childCount_; ++c) stack[top++] = node.firstChild + c;
    }
  }
}

template <int D>
int RegionTree<D>::allocBlock() {
  if (!freeBlocks_.empty()) {
    const int b = freeBlocks_.back();
    freeBlocks_.pop_back();
    return b;
  }
  const int b = static_cast<int>(nodes_.size());
  nodes_.resize(nodes_.size() + childCount_);
  return b;
}

// Child c of a region: its splitAxes_ longest axes halved (ties: lowest first), bit k of c
// choosing the upper half of the k-th. With fewer than 2^D children, always splitting the root's
// longest axes would slice a square root into slivers.
template <int D>
typename RegionTree<D>::Box RegionTree<D>::childBox(const Box& parent, int c) const {
  std::array<int, D> axes;
  for (int i = 0; i < D; ++i) axes[i] = i;
  const Vec<D> ext = parent.extent();
  // longest first, ties in axis order: an insertion sort of D axes (std::stable_sort allocates a
  // buffer, once per child box of every division)
  for (int i = 1; i < D; ++i)
    for (int k = i; k > 0 && ext[axes[k]] > ext[axes[k - 1]]; --k) std::swap(axes[k], axes[k - 1]);
  const Vec<D> mid = parent.center();
  Box child = parent;
  for (int k = 0; k < splitAxes_; ++k) {
    const int axis = axes[k];
    if (c & (1 << k)) child.min[axis] = mid[axis];
    else child.max[axis] = mid[axis];
  }
  return child;
}

template <int D>
bool RegionTree<D>::shouldSplit(int leaf) const {
  const Node& node = nodes_[leaf];
  const int n = static_cast<int>(node.objects.size());
  if (n <= rule_.decompositionFactor || node.depth >= rule_.maxDepth) return false;
  // Children smaller than the smallest object cannot separate objects that overlap one another:
  // more than df mutually overlapping boxes would otherwise split their common volume down to
  // maxDepth (up to 8^12 nodes in 3-D).
  if (rule_.minChildSizeRatio > 0.0) {
    double smallest = kInf;
    for (int id : node.objects) smallest = std::min(smallest, members_[id].fat.extent().minCoeff());
    if (0.5 * node.box.extent().maxCoeff() < rule_.minChildSizeRatio * smallest) return false;
  }
  // a division that leaves every object in every child separates nothing
  for (int c = 0; c < childCount_; ++c) {
    const Box child = childBox(node.box, c);
    int in = 0;
    for (int id : node.objects) in += listedBox(id).overlaps(child) ? 1 : 0;
    if (in < n) return true;
  }
  return false;
}

template <int D>
void RegionTree<D>::maybeSplit(int leaf) {
  if (nodes_[leaf].firstChild >= 0) return;  // already divided by an earlier call
  if (!shouldSplit(leaf)) return;
  const int first = allocBlock();  // may reallocate nodes_: index, don't hold references
  Node& parent = nodes_[leaf];
  parent.firstChild = first;
  for (int c = 0; c < childCount_; ++c) {
    // field by field: a reused block keeps its lists' storage
    Node& child = nodes_[first + c];
    child.box = childBox(parent.box, c);
    child.parent = leaf;
    child.firstChild = -1;
    child.depth = parent.depth + 1;
    child.count = 0;
    child.objects.clear();
  }
  split_.clear();
  split_.swap(parent.objects);
  for (int id : split_) {
    const Box fat = listedBox(id);
    auto& leaves = members_[id].leaves;
    leaves.erase(std::find(leaves.begin(), leaves.end(), leaf));
    for (int c = 0; c < childCount_; ++c) {
      Node& child = nodes_[first + c];
      if (!child.box.overlaps(fat)) continue;
      child.objects.push_back(id);
      ++child.count;
      leaves.push_back(first + c);
    }
    if (id != moving_) relisted_.push_back(id);
  }
  ++counters_.subdivisions;
  leafCount_ += childCount_ - 1;
  for (int c = 0; c < childCount_; ++c) maybeSplit(first + c);
}

template <int D>
void RegionTree<D>::collapse(int n) {
  const int first = nodes_[n].firstChild;
  if (first < 0) return;
  for (int c = 0; c < childCount_; ++c) collapse(first + c);
  std::vector<int>& merged = nodes_[n].objects;  // empty while divided; nodes_ does not grow here
  merged.clear();
  for (int c = 0; c < childCount_; ++c) {
    Node& child = nodes_[first + c];
    for (int id : child.objects) {
      auto& leaves = members_[id].leaves;
      leaves.erase(std::find(leaves.begin(), leaves.end(), first + c));
      if (std::find(leaves.begin(), leaves.end(), n) == leaves.end()) {
        leaves.push_back(n);
        merged.push_back(id);
        // listed in more than one child: it already met all of them; otherwise it meets new ones
        widened_.push_back(id);
        if (id != moving_) relisted_.push_back(id);
      }
    }
    child.objects.clear();
    child.firstChild = -1;
    child.count = 0;
  }
  Node& node = nodes_[n];
  node.firstChild = -1;
  STCORE_ASSERT(static_cast<int>(node.objects.size()) == node.count);
  freeBlocks_.push_back(first);
  ++counters_.reunions;
  leafCount_ -= childCount_ - 1;
}

// A divided region reunites when it holds df or fewer objects, or when every object in it lies
// in every child (it would not divide now).
template <int D>
bool RegionTree<D>::shouldCollapse(int a) const {
  const Node& node = nodes_[a];
  if (node.firstChild < 0) return false;
  if (node.count <= rule_.decompositionFactor) return true;
  for (int c = 0; c < childCount_; ++c)
    if (nodes_[node.firstChild + c].count < node.count) return false;
  return true;
}

template <int D>
void RegionTree<D>::collapseUpFrom(int n) {
  int target = -1;
  for (int a = n; a >= 0; a = nodes_[a].parent)
    if (shouldCollapse(a)) target = a;
  if (target >= 0) collapse(target);
}

template <int D>
void RegionTree<D>::setDecompositionFactor(int df) {
  if (df < 1) throw std::invalid_argument("decomposition factor must be >= 1");
  const int before = rule_.decompositionFactor;
  if (df == before) return;
  rule_.decompositionFactor = df;
  if (df > before) {
    // coarser: the top-most divided regions that no longer hold more than df reunite
    std::vector<int> stack{0};
    while (!stack.empty()) {
      const int n = stack.back();
      stack.pop_back();
      if (nodes_[n].firstChild < 0) continue;
      if (shouldCollapse(n)) collapse(n);
      else for (int c = 0; c < childCount_; ++c) stack.push_back(nodes_[n].firstChild + c);
    }
  } else if (rule_.subdivide) {
    // finer: leaves holding more than df divide (a divided region holds more than the old df)
    // (the leaves in index order, as leaves() lists them, found by one pass over the pool: a
    // node is in use if it is the root or in its parent's block of children)
    landed_.clear();
    for (int n = 0; n < static_cast<int>(nodes_.size()); ++n) {
      const int p = nodes_[n].parent;
      const bool inUse = p < 0 ? n == 0 : nodes_[p].firstChild >= 0 && n >= nodes_[p].firstChild && n < nodes_[p].firstChild + childCount_;
      if (inUse && nodes_[n].firstChild < 0) landed_.push_back(n);
    }
    for (int leaf : landed_) maybeSplit(leaf);
  }
}

// ---- region events ------------------------------------------------------------------------------

template <int D>
double RegionTree<D>::exitTime(int id, const BallPath<D>& path) const {
  if (nodes_[0].firstChild < 0) return kInf;  // one leaf: a division re-lists (takeRelisted)
  const Member& m = members_[id];
  const Box fat = listedBox(id);
  double t = kInf;
  if (m.leaves.size() == 1) {
    // in one leaf: its next event is reaching a wall of it; the listed box trails the ball, so
    // the leaf is left only after the wall is reached (reachTime grows with the distance)
    const Box& lb = nodes_[m.leaves[0]].box;
    for (int i = 0; i < D; ++i) {
      const double v = path.v[i];
      if (v > 0.0 && lb.max[i] < bounds_.max[i])
        t = std::min(t, reachTime(path.p[i] + path.radius, v, path.a[i], lb.max[i], path.horizon));
      else if (v < 0.0 && lb.min[i] > bounds_.min[i])
        t = std::min(t, reachTime(path.p[i] - path.radius, v, path.a[i], lb.min[i], path.horizon));
    }
    return t;
  }
  for (int i = 0; i < D; ++i) {
    const double v = path.v[i];
    if (v == 0.0) continue;
    // the walls ahead: the nearest listed leaf's far wall beyond the listed box (a leaf there is
    // entered when the ball's box reaches it), and the nearest far wall of any listed leaf
    // (that leaf is left once the listed box, 2 margins behind the ball, passes it)
    double enter = v > 0.0 ? kInf : -kInf;
    double leave = enter;
    for (int leaf : m.leaves) {
      const Box& lb = nodes_[leaf].box;
      if (v > 0.0) {
        const double w = lb.max[i];
        if (w >= bounds_.max[i]) continue;
        leave = std::min(leave, w);
        if (w > fat.max[i]) enter = std::min(enter, w);
      } else {
        const double w = lb.min[i];
        if (w <= bounds_.min[i]) continue;
        leave = std::max(leave, w);
        if (w < fat.min[i]) enter = std::max(enter, w);
      }
    }
    const double r = path.radius;
    const double lag = r + 2.0 * m.margin;
    if (std::isfinite(enter)) t = std::min(t, reachTime(path.p[i] + (v > 0.0 ? r : -r), v, path.a[i], enter, path.horizon));
    if (std::isfinite(leave)) t = std::min(t, reachTime(path.p[i] - (v > 0.0 ? lag : -lag), v, path.a[i], leave, path.horizon));
  }
  return t;
}

template class RegionTree<2>;
template class RegionTree<3>;
static_assert(Broadphase<RegionTree<2>, 2> && Broadphase<RegionTree<3>, 3>);

}  // namespace st
