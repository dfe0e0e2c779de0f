#include <stcore/space.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <stdexcept>

namespace st {

bool parseSpaceKind(const std::string& text, SpaceKind& out) {
  if (text == "none") out = SpaceKind::None;
  else if (text == "single") out = SpaceKind::Single;
  else if (text == "tree" || text == "quadtree" || text == "octree") out = SpaceKind::Tree;
  else if (text == "cells") out = SpaceKind::Cells;
  else return false;
  return true;
}

const char* toString(SpaceKind kind) {
  switch (kind) {
    case SpaceKind::None: return "none";
    case SpaceKind::Single: return "single";
    case SpaceKind::Tree: return "tree";
    case SpaceKind::Cells: return "cells";
  }
  return "?";
}

template <int D>
Space<D>::Space(SpaceKind kind, const Box& bounds, const SpaceRule& rule)
    : kind_(kind), bounds_(bounds), rule_(rule) {
  if (!((bounds.max.array() > bounds.min.array()).all()))
    throw std::invalid_argument("space bounds must have positive extent");
  if (rule_.divisions == 0) rule_.divisions = 1 << D;
  int k = 0;
  while ((1 << k) < rule_.divisions) ++k;
  if ((1 << k) != rule_.divisions || k < 1 || k > D)
    throw std::invalid_argument("space divisions must be 2, 4" + std::string(D == 3 ? " or 8" : ""));
  if (rule_.decompositionFactor < 1) throw std::invalid_argument("decomposition factor must be >= 1");
  childCount_ = rule_.divisions;
  // split along the k longest axes of the root (cells stay as square as the root allows)
  std::vector<int> axes(D);
  for (int i = 0; i < D; ++i) axes[i] = i;
  const Vec<D> ext = bounds.extent();
  std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return ext[a] > ext[b]; });
  splitAxes_.assign(axes.begin(), axes.begin() + k);

  if (kind_ == SpaceKind::Cells) {
    if (!(rule_.cellSize > 0.0)) throw std::invalid_argument("cells space needs a positive cell size");
    for (int i = 0; i < D; ++i) {
      dims_[i] = std::max(1, static_cast<int>(std::floor(ext[i] / rule_.cellSize)));
      cellSize_[i] = ext[i] / dims_[i];
    }
    const double total = dims_.template cast<double>().prod();
    if (total > 5e7) throw std::invalid_argument("cells space would need too many cells");
    cellCount_ = static_cast<int>(total);
    cellData_.assign(static_cast<std::size_t>(cellCount_) * stride_, 0);
  } else {
    nodes_.push_back(Node{bounds_, -1, -1, 0, 0, {}});
  }
  if (kind_ == SpaceKind::Single) rule_.subdivide = false;
}

template <int D>
typename Space<D>::Box Space<D>::clampToBounds(const Box& b) const {
  Box c;
  c.min = b.min.cwiseMax(bounds_.min).cwiseMin(bounds_.max);
  c.max = b.max.cwiseMin(bounds_.max).cwiseMax(bounds_.min);
  return c;
}

template <int D>
void Space<D>::cellRange(const Box& b, Index& lo, Index& hi) const {
  // b is clamped to the bounds: the offsets are >= 0, where truncation is floor (and needs no libm call)
  for (int i = 0; i < D; ++i) {
    lo[i] = std::min(static_cast<int>((b.min[i] - bounds_.min[i]) / cellSize_[i]), dims_[i] - 1);
    hi[i] = std::min(static_cast<int>((b.max[i] - bounds_.min[i]) / cellSize_[i]), dims_[i] - 1);
  }
}

template <int D>
typename Space<D>::Box Space<D>::leafBounds(int leaf) const {
  if (kind_ != SpaceKind::Cells) return nodes_[leaf].box;
  Box b;
  int rest = leaf;
  for (int i = 0; i < D; ++i) {
    const int c = rest % dims_[i];
    rest /= dims_[i];
    b.min[i] = bounds_.min[i] + c * cellSize_[i];
    b.max[i] = (c == dims_[i] - 1) ? bounds_.max[i] : bounds_.min[i] + (c + 1) * cellSize_[i];
  }
  return b;
}

template <int D>
ObjectList Space<D>::objectsIn(int leaf) const {
  if (kind_ == SpaceKind::Cells) {
    const int* cell = cellData_.data() + static_cast<std::ptrdiff_t>(leaf) * stride_;
    return {cell + 1, static_cast<std::size_t>(cell[0]), D};
  }
  const std::vector<int>& objs = nodes_[leaf].objects;
  return {objs.data(), objs.size(), 0};
}

template <int D>
const std::vector<int>& Space<D>::leavesOf(int id) const {
  const Member& m = members_[id];
  if (kind_ == SpaceKind::Cells) {
    m.leaves.clear();
    forEachCell(m.lo, m.hi, [&](int idx, const Index&) { m.leaves.push_back(idx); });
  }
  return m.leaves;
}

template <int D>
std::vector<int> Space<D>::leaves() const {
  std::vector<int> out;
  if (kind_ == SpaceKind::Cells) {
    for (int i = 0; i < cellCount_; ++i) out.push_back(i);
    return out;
  }
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
std::array<int, 2> Space<D>::cellBlock(const Box& box) const {
  if (kind_ != SpaceKind::Cells) return {-1, -1};
  Index lo, hi;
  cellRange(clampToBounds(box), lo, hi);  // as forEachInBox
  return {cellIndex(lo), cellIndex(hi)};
}

template <int D>
int Space<D>::depthOf(int leaf) const {
  return kind_ == SpaceKind::Cells ? 0 : nodes_[leaf].depth;
}

template <int D>
std::vector<int> Space<D>::takeWidened() {
  std::vector<int> out;
  out.swap(widened_);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// ---- membership ---------------------------------------------------------------------------------

template <int D>
void Space<D>::insert(int id, const Box& box, double margin) {
  assert(id >= 0);
  if (kind_ == SpaceKind::Cells && id >= (1 << (30 - D))) throw std::length_error("cells space: object id too large");
  if (id >= static_cast<int>(members_.size())) {
    members_.resize(id + 1);
    if (kind_ != SpaceKind::Cells) stamp_.resize(id + 1, 0u);
  }
  Member& m = members_[id];
  if (m.present) throw std::logic_error("space: object inserted twice");
  m.present = true;
  m.fat = {box.min.array() - margin, box.max.array() + margin};
  attach(id);
  ++revision_;
}

template <int D>
void Space<D>::remove(int id) {
  if (!contains(id)) return;
  detach(id, true);
  members_[id].present = false;
  ++revision_;
}

template <int D>
void Space<D>::update(int id, const Box& box, double margin) {
  if (!contains(id)) throw std::logic_error("space: update of an object not in the space");
  if (kind_ == SpaceKind::Cells) {
    updateCells(id, {box.min.array() - margin, box.max.array() + margin});
    return;
  }
  ++revision_;
  if (nodes_[0].firstChild < 0) {
    // an undivided tree lists every object in its root before and after: only the box changes,
    // and the object moves to the back of the root's list, where the remove and insert below
    // would leave it (a split follows as there)
    members_[id].fat = {box.min.array() - margin, box.max.array() + margin};
    std::vector<int>& objects = nodes_[0].objects;
    std::swap(*std::find(objects.begin(), objects.end(), id), objects.back());
    if (rule_.subdivide) {
      maybeSplit(0);
      if (nodes_[0].firstChild >= 0) ++counters_.transfers;  // now listed in the root's children
    }
    if (kind_ == SpaceKind::Tree) collapseUpFrom(0);
    return;
  }
  scratch_ = members_[id].leaves;  // old membership, to count transfers
  std::sort(scratch_.begin(), scratch_.end());
  detach(id, false);
  members_[id].fat = {box.min.array() - margin, box.max.array() + margin};
  attach(id);
  scratchNow_ = members_[id].leaves;
  std::sort(scratchNow_.begin(), scratchNow_.end());
  if (scratchNow_ != scratch_) ++counters_.transfers;
  // reunite regions the object left, now that it is listed where it belongs
  if (kind_ == SpaceKind::Tree)
    for (int old : scratch_) collapseUpFrom(old);
}

// Cells: most updates (one per collision) leave the ball in the same block of cells; then nothing
// changes but the previous block (now the same). Otherwise leave the cells outside the new block,
// re-mark the cells kept whose corner bits change, and enter those outside the old.
template <int D>
void Space<D>::updateCells(int id, const Box& fat) {
  Member& m = members_[id];
  Index lo, hi;
  cellRange(clampToBounds(fat), lo, hi);
  m.prevLo = m.lo;
  m.prevHi = m.hi;
  if ((lo == m.lo).all() && (hi == m.hi).all()) return;
  ++revision_;
  auto within = [](const Index& c, const Index& a, const Index& b) { return (c >= a).all() && (c <= b).all(); };
  forEachCell(m.lo, m.hi, [&](int idx, const Index& c) {
    const int old = (id << D) | cornerBits(c, m.lo);
    if (!within(c, lo, hi)) {
      cellErase(idx, old);
      return;
    }
    const int now = (id << D) | cornerBits(c, lo);
    if (now == old) return;
    int* cell = cellData_.data() + static_cast<std::ptrdiff_t>(idx) * stride_;
    int* it = std::find(cell + 1, cell + 1 + cell[0], old);
    assert(it != cell + 1 + cell[0]);
    *it = now;
  });
  forEachCell(lo, hi, [&](int idx, const Index& c) {
    if (!within(c, m.lo, m.hi)) cellPush(idx, (id << D) | cornerBits(c, lo));
  });
  m.lo = lo;
  m.hi = hi;
  ++counters_.transfers;
}

template <int D>
void Space<D>::cellPush(int idx, int entry) {
  if (cellData_[static_cast<std::size_t>(idx) * stride_] == stride_ - 1) {
    // full: double every cell's room (cells are few times fuller than average at most)
    const int wider = 2 * stride_;
    std::vector<int> data(static_cast<std::size_t>(cellCount_) * wider, 0);
    for (std::size_t c = 0; c < static_cast<std::size_t>(cellCount_); ++c)
      std::copy_n(cellData_.begin() + c * stride_, stride_, data.begin() + c * wider);
    cellData_.swap(data);
    stride_ = wider;
  }
  int* cell = cellData_.data() + static_cast<std::ptrdiff_t>(idx) * stride_;
  cell[++cell[0]] = entry;
}

template <int D>
void Space<D>::cellErase(int idx, int entry) {
  int* cell = cellData_.data() + static_cast<std::ptrdiff_t>(idx) * stride_;
  int* last = cell + cell[0];
  int* it = std::find(cell + 1, last + 1, entry);
  assert(it != last + 1);
  *it = *last;  // order within a cell carries no meaning
  --cell[0];
}

template <int D>
void Space<D>::attach(int id) {
  Member& m = members_[id];
  if (kind_ == SpaceKind::Cells) {
    cellRange(clampToBounds(m.fat), m.lo, m.hi);
    m.prevLo = m.lo;
    m.prevHi = m.hi;
    forEachCell(m.lo, m.hi, [&](int idx, const Index& c) { cellPush(idx, (id << D) | cornerBits(c, m.lo)); });
    return;
  }
  m.leaves.clear();
  addRec(0, id);
  if (rule_.subdivide) {
    // the leaves it landed in, copied (splits rewrite them); an undivided tree has one, the root
    if (m.leaves.size() == 1) {
      maybeSplit(m.leaves[0]);
    } else {
      const std::vector<int> landed = m.leaves;
      for (int leaf : landed) maybeSplit(leaf);
    }
  }
}

template <int D>
void Space<D>::detach(int id, bool allowCollapse) {
  Member& m = members_[id];
  if (kind_ == SpaceKind::Cells) {
    forEachCell(m.lo, m.hi, [&](int idx, const Index& c) { cellErase(idx, (id << D) | cornerBits(c, m.lo)); });
    return;
  }
  if (!allowCollapse) {
    removeRec(0, id);
    m.leaves.clear();
    return;
  }
  const std::vector<int> old = m.leaves;
  removeRec(0, id);
  m.leaves.clear();
  for (int leaf : old) collapseUpFrom(leaf);
}

template <int D>
void Space<D>::addRec(int n, int id) {
  const Box fat = clampToBounds(members_[id].fat);
  // explicit stack: nodes_ does not grow here, references stay valid
  int stack[256];
  int top = 0;
  stack[top++] = n;
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
void Space<D>::removeRec(int n, int id) {
  const Box fat = clampToBounds(members_[id].fat);
  int stack[256];
  int top = 0;
  stack[top++] = n;
  while (top > 0) {
    Node& node = nodes_[stack[--top]];
    if (!node.box.overlaps(fat)) continue;
    --node.count;
    if (node.firstChild < 0) {
      auto it = std::find(node.objects.begin(), node.objects.end(), id);
      assert(it != node.objects.end());
      *it = node.objects.back();
      node.objects.pop_back();
    } else {
      for (int c = 0; c < childCount_; ++c) stack[top++] = node.firstChild + c;
    }
  }
}

template <int D>
int Space<D>::allocBlock() {
  if (!freeBlocks_.empty()) {
    const int b = freeBlocks_.back();
    freeBlocks_.pop_back();
    return b;
  }
  const int b = static_cast<int>(nodes_.size());
  nodes_.resize(nodes_.size() + childCount_);
  return b;
}

template <int D>
void Space<D>::maybeSplit(int leaf) {
  if (nodes_[leaf].firstChild >= 0) return;  // already split by an earlier call
  if (static_cast<int>(nodes_[leaf].objects.size()) <= rule_.decompositionFactor) return;
  if (nodes_[leaf].depth >= rule_.maxDepth) return;
  // Children smaller than the smallest object cannot separate objects that overlap one another:
  // more than df mutually overlapping boxes would otherwise split their common volume down to
  // maxDepth (up to 8^12 nodes in 3-D).
  if (rule_.minChildSizeRatio > 0.0) {
    double smallest = std::numeric_limits<double>::infinity();
    for (int id : nodes_[leaf].objects) smallest = std::min(smallest, members_[id].fat.extent().minCoeff());
    if (0.5 * nodes_[leaf].box.extent().maxCoeff() < rule_.minChildSizeRatio * smallest) return;
  }
  const int first = allocBlock();  // may reallocate nodes_: index, don't hold references
  Node& parent = nodes_[leaf];
  parent.firstChild = first;
  const Vec<D> mid = parent.box.center();
  // split this node's longest axes (ties: lowest first): with fewer than 2^D children, always
  // splitting the root's longest axes would slice a square root into slivers
  std::array<int, D> axes;
  for (int i = 0; i < D; ++i) axes[i] = i;
  const Vec<D> ext = parent.box.extent();
  std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return ext[a] > ext[b]; });
  for (int c = 0; c < childCount_; ++c) {
    Node& child = nodes_[first + c];
    child = Node{parent.box, leaf, -1, parent.depth + 1, 0, {}};
    for (std::size_t k = 0; k < splitAxes_.size(); ++k) {
      const int axis = axes[k];
      if (c & (1 << k)) child.box.min[axis] = mid[axis];
      else child.box.max[axis] = mid[axis];
    }
  }
  std::vector<int> objs;
  objs.swap(parent.objects);
  for (int id : objs) {
    const Box fat = clampToBounds(members_[id].fat);
    auto& leaves = members_[id].leaves;
    leaves.erase(std::find(leaves.begin(), leaves.end(), leaf));
    for (int c = 0; c < childCount_; ++c) {
      Node& child = nodes_[first + c];
      if (!child.box.overlaps(fat)) continue;
      child.objects.push_back(id);
      ++child.count;
      leaves.push_back(first + c);
    }
  }
  ++counters_.subdivisions;
  for (int c = 0; c < childCount_; ++c) maybeSplit(first + c);
}

template <int D>
void Space<D>::collapse(int n) {
  const int first = nodes_[n].firstChild;
  if (first < 0) return;
  for (int c = 0; c < childCount_; ++c) collapse(first + c);
  std::vector<int> merged;
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
      }
    }
    child.objects.clear();
    child.firstChild = -1;
    child.count = 0;
  }
  Node& node = nodes_[n];
  node.firstChild = -1;
  node.objects = std::move(merged);
  assert(static_cast<int>(node.objects.size()) == node.count);
  freeBlocks_.push_back(first);
  ++counters_.reunions;
}

template <int D>
void Space<D>::collapseUpFrom(int n) {
  // the top-most ancestor (or n itself) that is divided and holds df or fewer objects
  int target = -1;
  for (int a = n; a >= 0; a = nodes_[a].parent)
    if (nodes_[a].firstChild >= 0 && nodes_[a].count <= rule_.decompositionFactor) target = a;
  if (target >= 0) collapse(target);
}

template <int D>
double Space<D>::exitTime(int id, const Vec<D>& p, const Vec<D>& v, double r) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (kind_ == SpaceKind::Single) return kInf;
  if (kind_ == SpaceKind::Tree && nodes_[0].firstChild < 0 && !rule_.subdivide) return kInf;
  // the box the tight ball may roam without touching an unlisted leaf
  Box safe;
  if (kind_ == SpaceKind::Cells) {
    const Index& lo = members_[id].lo;
    const Index& hi = members_[id].hi;
    for (int i = 0; i < D; ++i) {
      safe.min[i] = lo[i] == 0 ? -kInf : bounds_.min[i] + lo[i] * cellSize_[i];
      safe.max[i] = hi[i] == dims_[i] - 1 ? kInf : bounds_.min[i] + (hi[i] + 1) * cellSize_[i];
    }
  } else {
    safe = members_[id].fat;
    for (int i = 0; i < D; ++i) {
      if (safe.min[i] <= bounds_.min[i]) safe.min[i] = -kInf;
      if (safe.max[i] >= bounds_.max[i]) safe.max[i] = kInf;
    }
  }
  double t = kInf;
  for (int i = 0; i < D; ++i) {
    if (v[i] > 0.0) t = std::min(t, (safe.max[i] - (p[i] + r)) / v[i]);
    else if (v[i] < 0.0) t = std::min(t, (safe.min[i] - (p[i] - r)) / v[i]);
  }
  return std::max(t, 0.0);
}

template class Space<2>;
template class Space<3>;

}  // namespace st
