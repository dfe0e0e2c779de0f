#include <stcore/uniform_grid.hpp>

#include <cmath>
#include <stdexcept>

#include <stcore/assert.hpp>

namespace st {

template <int D>
double gridCellSize(const Vec<D>& extent, double target, double maxCells) {
  double size = target;
  auto cells = [&] {
    double n = 1.0;
    for (int i = 0; i < D; ++i) n *= extent[i] / size;
    return n;
  };
  while (cells() > maxCells) size *= 2.0;
  return size;
}

template <int D>
UniformGrid<D>::UniformGrid(const Box& bounds, double cellSize) : bounds_(bounds) {
  if (!((bounds.max.array() > bounds.min.array()).all()))
    throw std::invalid_argument("space bounds must have positive extent");
  if (!(cellSize > 0.0)) throw std::invalid_argument("cells space needs a positive cell size");
  const Vec<D> ext = bounds.extent();
  for (int i = 0; i < D; ++i) {
    dims_[i] = std::max(1, static_cast<int>(std::floor(ext[i] / cellSize)));
    cellSize_[i] = ext[i] / dims_[i];
  }
  const double total = dims_.template cast<double>().prod();
  if (total > 5e7) throw std::invalid_argument("cells space would need too many cells");
  cellCount_ = static_cast<int>(total);
  cellData_.assign(static_cast<std::size_t>(cellCount_) * stride_, 0);
}

template <int D>
void UniformGrid<D>::cellRange(const Box& b, Index& lo, Index& hi) const {
  // b is clamped to the bounds: the offsets are >= 0, where truncation is floor (and needs no libm call)
  for (int i = 0; i < D; ++i) {
    lo[i] = std::min(static_cast<int>((b.min[i] - bounds_.min[i]) / cellSize_[i]), dims_[i] - 1);
    hi[i] = std::min(static_cast<int>((b.max[i] - bounds_.min[i]) / cellSize_[i]), dims_[i] - 1);
  }
}

template <int D>
typename UniformGrid<D>::Box UniformGrid<D>::leafBounds(int leaf) const {
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
ObjectList UniformGrid<D>::objectsIn(int leaf) const {
  const int* cell = cellData_.data() + static_cast<std::ptrdiff_t>(leaf) * stride_;
  return {cell + 1, static_cast<std::size_t>(cell[0]), D};
}

template <int D>
const std::vector<int>& UniformGrid<D>::leavesOf(int id) const {
  const Member& m = members_[id];
  m.leaves.clear();
  forEachCell(m.lo, m.hi, [&](int idx, const Index&) { m.leaves.push_back(idx); });
  return m.leaves;
}

template <int D>
std::vector<int> UniformGrid<D>::leaves() const {
  std::vector<int> out(static_cast<std::size_t>(cellCount_));
  for (int i = 0; i < cellCount_; ++i) out[static_cast<std::size_t>(i)] = i;
  return out;
}

template <int D>
std::array<int, 2> UniformGrid<D>::cellBlock(const Box& box) const {
  Index lo, hi;
  cellRange(detail::clampBox(box, bounds_), lo, hi);  // as forEachInBox
  return {cellIndex(lo), cellIndex(hi)};
}

template <int D>
void UniformGrid<D>::insert(int id, const Box& box, double margin) {
  if (id < 0) throw std::invalid_argument("space: negative object id");
  if (id >= (1 << (30 - D))) throw std::length_error("cells space: object id too large");
  if (id >= static_cast<int>(members_.size())) members_.resize(id + 1);
  Member& m = members_[id];
  if (m.present) throw std::logic_error("space: object inserted twice");
  m.present = true;
  cellRange(detail::clampBox(detail::grownBox(box, margin), bounds_), m.lo, m.hi);
  m.prevLo = m.lo;
  m.prevHi = m.hi;
  forEachCell(m.lo, m.hi, [&](int idx, const Index& c) { cellPush(idx, (id << D) | cornerBits(c, m.lo)); });
  ++revision_;
}

template <int D>
void UniformGrid<D>::remove(int id) {
  if (!contains(id)) return;
  Member& m = members_[id];
  forEachCell(m.lo, m.hi, [&](int idx, const Index& c) { cellErase(idx, (id << D) | cornerBits(c, m.lo)); });
  m.present = false;
  ++revision_;
}

// Most updates (one per collision) leave the ball in the same block of cells; then nothing
// changes but the previous block (now the same). Otherwise leave the cells outside the new block,
// re-mark the cells kept whose corner bits change, and enter those outside the old.
template <int D>
void UniformGrid<D>::update(int id, const Box& box, double margin) {
  if (!contains(id)) throw std::logic_error("space: update of an object not in the space");
  Member& m = members_[id];
  Index lo, hi;
  cellRange(detail::clampBox(detail::grownBox(box, margin), bounds_), lo, hi);
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
    STCORE_ASSERT(it != cell + 1 + cell[0]);
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
void UniformGrid<D>::cellPush(int idx, int entry) {
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
void UniformGrid<D>::cellErase(int idx, int entry) {
  int* cell = cellData_.data() + static_cast<std::ptrdiff_t>(idx) * stride_;
  int* last = cell + cell[0];
  int* it = std::find(cell + 1, last + 1, entry);
  STCORE_ASSERT(it != last + 1);
  *it = *last;  // order within a cell carries no meaning
  --cell[0];
}

template <int D>
double UniformGrid<D>::exitTime(int id, const BallPath<D>& path) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // the box the tight ball may roam without touching an unlisted cell
  const Index& lo = members_[id].lo;
  const Index& hi = members_[id].hi;
  Box safe;
  for (int i = 0; i < D; ++i) {
    safe.min[i] = lo[i] == 0 ? -kInf : bounds_.min[i] + lo[i] * cellSize_[i];
    safe.max[i] = hi[i] == dims_[i] - 1 ? kInf : bounds_.min[i] + (hi[i] + 1) * cellSize_[i];
  }
  double t = kInf;
  for (int i = 0; i < D; ++i) {
    if (path.v[i] > 0.0) t = std::min(t, (safe.max[i] - (path.p[i] + path.radius)) / path.v[i]);
    else if (path.v[i] < 0.0) t = std::min(t, (safe.min[i] - (path.p[i] - path.radius)) / path.v[i]);
  }
  return std::max(t, 0.0);
}

template double gridCellSize<2>(const Vec<2>&, double, double);
template double gridCellSize<3>(const Vec<3>&, double, double);
template class UniformGrid<2>;
template class UniformGrid<3>;
static_assert(Broadphase<UniformGrid<2>, 2> && Broadphase<UniformGrid<3>, 3>);

}  // namespace st
