#pragma once
// The broadphase: which objects may touch. One interface, four implementations, each in its own
// header (in the way Jolt puts a quadtree and a brute-force broadphase behind one BroadPhase):
//   BruteForce<D>   brute_force.hpp   no regions: every object a candidate of every other (the
//                                     report's "no space", SpaceKind::None; the test oracle)
//   SingleList<D>   single_list.hpp   one region listing every object: the report's version I
//   RegionTree<D>   region_tree.hpp   the report's space (§2.6): regions that subdivide past a
//                                     decomposition factor and reunite below it; a quadtree in
//                                     2-D, an octree in 3-D (version II)
//   UniformGrid<D>  uniform_grid.hpp  fixed uniform cells, never divided
// Space<D> (space.hpp) holds the one a caller picks at run time, so a caller never branches on
// the kind; a caller that knows its kind may use the type itself.
//
// Every implementation, for objects named by the caller's dense ids (0, 1, 2, ...) and given
// as boxes (grown by an optional margin), answers:
//   insert(id, box, margin), update(id, box, margin), remove(id), contains(id)
//   forEachNeighbor(id, f)    f(other) once for every other object sharing a leaf with id
//   forEachInBox(box, f)      f(object) once for every object listed in a leaf the box touches
//   forEachPair(f)            f(a, b) once for every pair sharing a leaf (a < b)
//   exitTime(id, path)        the next region event of a ball moving from its listed box
//   listingMargin(r, fat)     the margin a ball of radius r is listed with (fat: the caller's
//                             fraction of r for implementations that keep fat boxes)
//   leaves(), leafBounds(leaf), objectsIn(leaf), leavesOf(id), depthOf(leaf), leafCount()
// An object is listed in every leaf its box (closed) touches; the box is clamped to the bounds.
//
// Optional capabilities are refinements of that interface (the concepts at the end of this file);
// Space<D> answers them for every implementation, with the documented default where one lacks it.
#include <array>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
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
  // Tree only, decomposition_factor: auto. The space picks the factor itself as it runs and keeps
  // picking it as the scene changes (factor_tuner.hpp: what it measures, how it decides);
  // decompositionFactor is then the factor in force (Space::rule()).
  bool autoFactor = false;
  // auto: the cost of one region event (an object entering or leaving a leaf) in candidate pair
  // checks; the pool's event-driven simulator measured 8 (bench/pool_break, bench/RESULTS.md).
  double autoRegionCost = 100.0;
  // auto: the factor in force until the first window closes. 16: a scene of a few objects starts
  // as one leaf, a large one as a moderate tree. A caller that keeps neighbour lists and tests them
  // every round (Space::noteRound: the arm's monitor) starts fine, at 2: moving coarser reunites
  // leaves, which allocates nothing, while moving finer divides the tree inside the caller's
  // rounds (0.4-0.8 ms for each halving of the factor among the arm's 1 000 obstacles).
  int autoStart = 16;
};

struct SpaceCounters {
  std::uint64_t subdivisions = 0;
  std::uint64_t reunions = 0;
  std::uint64_t transfers = 0;  // membership changes of an object (the report's TransferObject)
};

// A ball's path from its last update: centre p, velocity v, a constant acceleration a (zero, or
// a deceleration along -v until the ball stops), for `horizon` seconds (the stop; infinity).
template <int D>
struct BallPath {
  Vec<D> p;
  Vec<D> v;
  double radius = 0.0;
  Vec<D> a = Vec<D>::Zero();
  double horizon = std::numeric_limits<double>::infinity();
};

// First time in [0, horizon] at which x0 + v t + a t^2 / 2 reaches `wall`, for a coordinate
// heading toward it (a opposes v or is zero: it slows and may stop short); infinity if it never
// does, 0 if it is already there or past.
// (inline: a region event computes several per ball)
inline double reachTime(double x0, double v, double a, double wall, double horizon) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (v == 0.0) return kInf;
  // along the direction of motion: distance d >= 0 to go at speed s, slowing at rate b >= 0
  const double d = v > 0.0 ? wall - x0 : x0 - wall;
  if (!(d > 0.0)) return 0.0;
  const double s = std::abs(v);
  const double b = std::abs(a);
  double t;
  if (b == 0.0) {
    t = d / s;
  } else {
    // s t - b t^2 / 2 = d: the smaller root, in the form without cancellation
    const double disc = s * s - 2.0 * b * d;
    if (disc < 0.0) return kInf;  // stops short of the wall
    t = 2.0 * d / (s + std::sqrt(disc));
  }
  return t <= horizon ? t : kInf;
}

// The objects listed in one leaf: a view, valid until the space changes. A grid stores each entry
// as (object << D) | corner bits (UniformGrid); the view yields the objects.
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

namespace detail {
template <int D>
inline Aabb<D> clampBox(const Aabb<D>& b, const Aabb<D>& bounds) {
  return {b.min.cwiseMax(bounds.min).cwiseMin(bounds.max), b.max.cwiseMin(bounds.max).cwiseMax(bounds.min)};
}
template <int D>
inline Aabb<D> grownBox(const Aabb<D>& b, double margin) {
  return {b.min.array() - margin, b.max.array() + margin};
}
// f(a, b) once for every pair a < b sharing a leaf, from forEachNeighbor (which already reports
// an object listed in several shared leaves once): the pair visit of the tree and the grid.
template <class B, class F>
void pairsFromNeighbors(const B& bp, int idEnd, F&& f) {
  for (int a = 0; a < idEnd; ++a)
    if (bp.contains(a))
      bp.forEachNeighbor(a, [&](int b) {
        if (a < b) f(a, b);
      });
}
}  // namespace detail

// What every implementation offers (checked where each is defined).
template <class B, int D>
concept Broadphase = requires(B b, const B cb, int id, const Aabb<D>& box, double margin, const BallPath<D>& path) {
  b.insert(id, box, margin);
  b.update(id, box, margin);
  b.remove(id);
  { cb.contains(id) } -> std::same_as<bool>;
  cb.forEachNeighbor(id, [](int) {});
  cb.forEachInBox(box, [](int) {});
  cb.forEachPair([](int, int) {});
  { cb.exitTime(id, path) } -> std::same_as<double>;
  { cb.leaves() } -> std::same_as<std::vector<int>>;
  { cb.leafBounds(id) } -> std::same_as<Aabb<D>>;
  { cb.objectsIn(id) } -> std::same_as<ObjectList>;
  { cb.leavesOf(id) } -> std::same_as<const std::vector<int>&>;
  { cb.leafCount() } -> std::same_as<int>;
  { cb.counters() } -> std::same_as<const SpaceCounters&>;
  { B::listingMargin(margin, margin) } -> std::same_as<double>;
};

// Refinements (Space<D> gives the default in brackets to an implementation without one):
// gathers a ball's neighbours into an array without a branch per entry [-1: walk them instead]
template <class B>
concept GathersNeighbors = requires(const B cb, int id, int* out) {
  { cb.gatherNeighbors(id, out, id) } -> std::same_as<int>;
};
// writes the objects forEachInBox visits to an array, in its order [-1: visit them]
template <class B, int D>
concept GathersInBox = requires(const B cb, const Aabb<D>& box, int* out) {
  { cb.gatherInBox(box, out, 0) } -> std::same_as<int>;
};
// names the objects an update may have brought as neighbours [every neighbour]
template <class B>
concept ReportsGainedNeighbors = requires(const B cb, int id) { cb.forEachNeighborGained(id, [](int) {}); };
// keys what forEachInBox visits by a block of cells [{-1, -1}: no key]
template <class B, int D>
concept KeysVisitsByBlock = requires(const B cb, const Aabb<D>& box) {
  { cb.cellBlock(box) } -> std::same_as<std::array<int, 2>>;
};
// re-lists other objects when an update divides or reunites regions [never]
template <class B>
concept RelistsObjects = requires(B b, std::vector<int>& out) {
  b.takeRelisted(out);
  b.takeWidened(out);
  { b.hasRelisted() } -> std::same_as<bool>;
  { b.hasWidened() } -> std::same_as<bool>;
};
// exitTime follows a slowing path (BallPath::a) exactly [the path's acceleration is not used]
template <class B>
concept FollowsSlowingPaths = B::kFollowsSlowingPaths;

}  // namespace st
