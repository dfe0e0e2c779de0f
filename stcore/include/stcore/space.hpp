#pragma once
// A broadphase picked at run time (broadphase.hpp): brute force ("none"), the single list, the
// region tree or the uniform grid behind one value type, for callers that take the kind from a
// scenario and never branch on it. Each call forwards to the implementation; an optional
// capability (broadphase.hpp's refinements: the grid's gathered neighbours and block keys, the
// tree's relisted objects) answers with its documented default where the implementation lacks it.
#include <array>
#include <cstdint>
#include <type_traits>
#include <variant>
#include <vector>

#include <stcore/broadphase.hpp>
#include <stcore/brute_force.hpp>
#include <stcore/factor_tuner.hpp>
#include <stcore/region_tree.hpp>
#include <stcore/single_list.hpp>
#include <stcore/uniform_grid.hpp>

namespace st {

template <int D>
class Space {
 public:
  using Box = Aabb<D>;

  // None (brute force), Single, Tree or Cells (rule.cellSize); throws std::invalid_argument on a
  // bad rule or bounds.
  Space(SpaceKind kind, const Box& bounds, const SpaceRule& rule);

  SpaceKind kind() const { return kind_; }
  const SpaceRule& rule() const { return rule_; }
  const Box& bounds() const { return bounds_; }

  // Objects are identified by the caller's dense ids (0, 1, 2, ...). `margin` grows the box.
  void insert(int id, const Box& box, double margin = 0.0) {
    visit([&](auto& s) { s.insert(id, box, margin); });
    ++revision_;
    if (tuning_) {
      if (id >= static_cast<int>(centre_.size())) centre_.resize(id + 1, Vec<D>::Zero());
      centre_[id] = box.center();
      ++objects_;
    }
  }
  // True if the object's leaves (cells: its block) may have changed.
  bool update(int id, const Box& box, double margin = 0.0);
  void remove(int id) {
    if (!contains(id)) return;
    visit([&](auto& s) { s.remove(id); });
    ++revision_;
    if (tuning_) --objects_;
  }
  bool contains(int id) const {
    return visit([&](const auto& s) { return s.contains(id); });
  }

  // Calls f(other) once for every other object sharing a leaf with id.
  template <class F>
  void forEachNeighbor(int id, F&& f) const {
    if (tuning_) {
      std::uint64_t visits = 0;
      std::get<RegionTree<D>>(impl_).forEachNeighbor(id, [&](int j) {
        ++visits;
        f(j);
      });
      tuner_.noteQuery(visits);
      return;
    }
    visit([&](const auto& s) { s.forEachNeighbor(id, f); });
  }
  // auto: a round of `queries` neighbour queries answered from lists the caller kept (each entry
  // of a list it tests is a visit), e.g. a monitor's cycle; true if the factor in force changed,
  // and with it what forEachNeighbor visits (a caller keeping lists gathers them again). Other
  // spaces: nothing.
  bool noteRound(std::uint64_t queries, std::uint64_t visits) {
    if (!tuning_) return false;
    tuner_.noteRound(queries, visits);
    return decideIfFull();
  }
  // Cells: the objects forEachNeighbor would visit, written to out in its order; how many, or -1
  // if more than `room` entries had to be looked at. Other kinds: -1 (visit them instead).
  int gatherNeighbors(int id, int* out, int room) const {
    return visit([&](const auto& s) {
      if constexpr (GathersNeighbors<std::decay_t<decltype(s)>>) return s.gatherNeighbors(id, out, room);
      else return -1;
    });
  }
  // Cells: the objects forEachInBox would visit, written to out in its order; how many, or -1 if
  // more than `room` entries had to be looked at. Other kinds: -1 (visit them instead).
  int gatherInBox(const Box& box, int* out, int room) const {
    return visit([&](const auto& s) {
      if constexpr (GathersInBox<std::decay_t<decltype(s)>, D>) return s.gatherInBox(box, out, room);
      else return -1;
    });
  }
  // True if forEachNeighborGained names fewer than every neighbour (cells): a caller then checks
  // those after an update; otherwise it compares the leaves before and after (leavesOf).
  bool reportsGainedNeighbors() const { return reportsGains_; }
  // Calls f(other) once for every object that may share a leaf with id since id's last update
  // and may not have before it: a superset of the new neighbours (cells: the objects of the cells
  // entered; the others: every neighbour).
  template <class F>
  void forEachNeighborGained(int id, F&& f) const {
    visit([&](const auto& s) {
      if constexpr (ReportsGainedNeighbors<std::decay_t<decltype(s)>>) s.forEachNeighborGained(id, f);
      else forEachNeighbor(id, f);
    });
  }
  // Calls f(object) once for every object listed in a leaf the box touches.
  template <class F>
  void forEachInBox(const Box& box, F&& f) const {
    visit([&](const auto& s) { s.forEachInBox(box, f); });
  }
  // Calls f(a, b), a < b, once for every pair of objects sharing a leaf.
  template <class F>
  void forEachPair(F&& f) const {
    visit([&](const auto& s) { s.forEachPair(f); });
  }
  // Cells: the first and last cell of the block of cells a box touches. What forEachInBox visits
  // depends on the box through this block only, so a caller may keep what it found per block.
  // Other kinds: {-1, -1}.
  std::array<int, 2> cellBlock(const Box& box) const {
    return visit([&](const auto& s) {
      if constexpr (KeysVisitsByBlock<std::decay_t<decltype(s)>, D>) return s.cellBlock(box);
      else return std::array<int, 2>{-1, -1};
    });
  }
  // Changes whenever an insert, remove or update may change what forEachInBox visits (cells: an
  // object's block of cells changed): with cellBlock, the key of a cached visit.
  std::uint64_t revision() const { return revision_; }

  // Time from the path's start until the ball, last updated into this space, has its next region
  // event (the tree: it touches a leaf it is not listed in or leaves one; cells: it touches a cell
  // outside its block); infinity if never.
  double exitTime(int id, const BallPath<D>& path) const {
    return visit([&](const auto& s) { return s.exitTime(id, path); });
  }
  double exitTime(int id, const Vec<D>& p, const Vec<D>& v, double r) const { return exitTime(id, BallPath<D>{p, v, r}); }
  // True if exitTime follows a slowing path exactly (the tree); otherwise it ignores BallPath::a,
  // and a caller passes the straight path from now, which reaches every wall first.
  bool followsSlowingPaths() const { return followsSlowing_; }
  // The margin a ball of this radius is listed with: the tree's slop, the grid's fat boxes
  // (fatFraction * radius), nothing for the others.
  double listingMargin(double radius, double fatFraction) const {
    return visit([&](const auto& s) { return s.listingMargin(radius, fatFraction); });
  }

  // Leaf regions id is listed in (cells: filled on demand, valid until the next call).
  const std::vector<int>& leavesOf(int id) const {
    return visit([&](const auto& s) -> const std::vector<int>& { return s.leavesOf(id); });
  }
  Box leafBounds(int leaf) const {
    return visit([&](const auto& s) { return s.leafBounds(leaf); });
  }
  ObjectList objectsIn(int leaf) const {
    return visit([&](const auto& s) { return s.objectsIn(leaf); });
  }
  // All current leaves (for drawing and invariant checks), and how many there are.
  std::vector<int> leaves() const {
    return visit([&](const auto& s) { return s.leaves(); });
  }
  int leafCount() const {
    return visit([&](const auto& s) { return s.leafCount(); });
  }
  int depthOf(int leaf) const {
    return visit([&](const auto& s) { return s.depthOf(leaf); });
  }
  // True while the space has more than one region: a divided tree, a grid of several cells.
  bool divided() const { return leafCount() > 1; }

  // Tree: objects whose leaves a division or reunion rewrote while another object changed (see
  // RegionTree::takeRelisted), and of those the ones a reunion widened. Other kinds: none.
  std::vector<int> takeRelisted() {
    std::vector<int> out;
    takeRelisted(out);
    return out;
  }
  void takeRelisted(std::vector<int>& out) {
    visit([&](auto& s) {
      if constexpr (RelistsObjects<std::decay_t<decltype(s)>>) s.takeRelisted(out);
      else out.clear();
    });
  }
  bool hasRelisted() const {
    return visit([](const auto& s) {
      if constexpr (RelistsObjects<std::decay_t<decltype(s)>>) return s.hasRelisted();
      else return false;
    });
  }
  std::vector<int> takeWidened() {
    std::vector<int> out;
    takeWidened(out);
    return out;
  }
  void takeWidened(std::vector<int>& out) {
    visit([&](auto& s) {
      if constexpr (RelistsObjects<std::decay_t<decltype(s)>>) s.takeWidened(out);
      else out.clear();
    });
  }
  bool hasWidened() const {
    return visit([](const auto& s) {
      if constexpr (RelistsObjects<std::decay_t<decltype(s)>>) return s.hasWidened();
      else return false;
    });
  }

  // decomposition_factor: auto (SpaceRule::autoFactor, a tree): the tuner choosing the factor in
  // force (rule().decompositionFactor); null otherwise.
  const FactorTuner* tuner() const { return tuning_ ? &tuner_ : nullptr; }

  const SpaceCounters& counters() const {
    return visit([&](const auto& s) -> const SpaceCounters& { return s.counters(); });
  }

  // The implementation itself, or null if the space is of another kind.
  const RegionTree<D>* tree() const { return std::get_if<RegionTree<D>>(&impl_); }
  const UniformGrid<D>* grid() const { return std::get_if<UniformGrid<D>>(&impl_); }

 private:
  using Impl = std::variant<BruteForce<D>, SingleList<D>, RegionTree<D>, UniformGrid<D>>;
  static Impl make(SpaceKind kind, const Box& bounds, const SpaceRule& rule);
  template <class F>
  decltype(auto) visit(F&& f) {
    return std::visit(f, impl_);
  }
  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit(f, impl_);
  }

  bool tune(int id, const Box& box, bool changed);
  bool decideIfFull();

  SpaceKind kind_;
  Box bounds_;
  SpaceRule rule_;
  Impl impl_;
  std::uint64_t revision_ = 0;
  // the implementation's capabilities, asked once
  bool reportsGains_ = visit([](const auto& s) { return ReportsGainedNeighbors<std::decay_t<decltype(s)>>; });
  bool followsSlowing_ = visit([](const auto& s) { return FollowsSlowingPaths<std::decay_t<decltype(s)>>; });
  // auto: the tuner and what it reads that the implementation does not keep
  bool tuning_ = false;
  mutable FactorTuner tuner_;  // counts the const queries' visits
  std::vector<Vec<D>> centre_;  // each object's box centre at its last insert or update
  int objects_ = 0;
};

extern template class Space<2>;
extern template class Space<3>;

}  // namespace st
