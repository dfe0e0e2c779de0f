#pragma once
// The report's "no space": no regions at all, every object a candidate of every other (Jolt's
// BroadPhaseBruteForce behind the same interface as its quadtree). It keeps only which ids are
// present, in increasing order, so a caller walks the others in id order; boxes and margins are
// not looked at, and an object never has a region event. It doubles as the oracle the other
// implementations are tested against (tests/stcore/broadphase_test.cpp).
//
// Beside SingleList (the report's version I, one region that is kept as a list and reordered on
// every update), this is what a caller without a space did by hand: a loop over all objects.
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <vector>

#include <stcore/broadphase.hpp>

namespace st {

template <int D>
class BruteForce {
 public:
  using Box = Aabb<D>;

  // The bounds are only reported back (leafBounds); any box will do, an empty one too.
  explicit BruteForce(const Box& bounds) : bounds_(bounds) {}

  const Box& bounds() const { return bounds_; }

  void insert(int id, const Box& /*box*/, double /*margin*/ = 0.0) {
    if (id < 0) throw std::invalid_argument("space: negative object id");
    if (id >= static_cast<int>(present_.size())) present_.resize(id + 1, false);
    if (present_[id]) throw std::logic_error("space: object inserted twice");
    present_[id] = true;
    // ids arrive in increasing order as a rule: an append
    objects_.insert(std::lower_bound(objects_.begin(), objects_.end(), id), id);
  }
  // Nothing moves: every object neighbours every other whatever its box.
  void update(int id, const Box& /*box*/, double /*margin*/ = 0.0) {
    if (!contains(id)) throw std::logic_error("space: update of an object not in the space");
  }
  void remove(int id) {
    if (!contains(id)) return;
    present_[id] = false;
    objects_.erase(std::lower_bound(objects_.begin(), objects_.end(), id));
  }
  bool contains(int id) const { return id >= 0 && id < static_cast<int>(present_.size()) && present_[id]; }

  // every other object, in increasing id order
  template <class F>
  void forEachNeighbor(int id, F&& f) const {
    for (int other : objects_)
      if (other != id) f(other);
  }
  template <class F>
  void forEachInBox(const Box& /*box*/, F&& f) const {
    for (int other : objects_) f(other);
  }
  template <class F>
  void forEachPair(F&& f) const {
    for (std::size_t i = 0; i < objects_.size(); ++i)
      for (std::size_t j = i + 1; j < objects_.size(); ++j) f(objects_[i], objects_[j]);
  }
  double exitTime(int /*id*/, const BallPath<D>& /*path*/) const { return std::numeric_limits<double>::infinity(); }
  // no box is listed, so nothing needs room around it
  static double listingMargin(double /*radius*/, double /*fatFraction*/) { return 0.0; }

  // one notional leaf, the bounds, holding every object (for drawing, counting and checks)
  std::vector<int> leaves() const { return {0}; }
  Box leafBounds(int /*leaf*/) const { return bounds_; }
  ObjectList objectsIn(int /*leaf*/) const { return {objects_.data(), objects_.size(), 0}; }
  const std::vector<int>& leavesOf(int /*id*/) const { return root_; }
  int depthOf(int /*leaf*/) const { return 0; }
  int leafCount() const { return 1; }
  const SpaceCounters& counters() const { return counters_; }

 private:
  Box bounds_;
  std::vector<int> objects_;   // present ids, increasing
  std::vector<bool> present_;  // id -> listed
  std::vector<int> root_{0};
  SpaceCounters counters_;     // all zero: no regions
};

static_assert(Broadphase<BruteForce<2>, 2> && Broadphase<BruteForce<3>, 3>);

}  // namespace st
