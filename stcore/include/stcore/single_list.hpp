#pragma once
// The report's version I (§2.6): one region, never divided, listing every object. Every object
// neighbours every other; membership never changes, so a ball has no region events.
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <vector>

#include <stcore/broadphase.hpp>

namespace st {

template <int D>
class SingleList {
 public:
  using Box = Aabb<D>;

  explicit SingleList(const Box& bounds) : bounds_(bounds) {
    if (!((bounds.max.array() > bounds.min.array()).all()))
      throw std::invalid_argument("space bounds must have positive extent");
  }

  const Box& bounds() const { return bounds_; }

  void insert(int id, const Box& /*box*/, double /*margin*/ = 0.0) {
    if (id < 0) throw std::invalid_argument("space: negative object id");
    if (id >= static_cast<int>(slot_.size())) slot_.resize(id + 1, -1);
    if (slot_[id] >= 0) throw std::logic_error("space: object inserted twice");
    slot_[id] = static_cast<int>(objects_.size());
    objects_.push_back(id);
  }
  // The box does not matter; the object swaps places with the last of the list.
  void update(int id, const Box& /*box*/, double /*margin*/ = 0.0) {
    if (!contains(id)) throw std::logic_error("space: update of an object not in the space");
    swapWithLast(id);
  }
  void remove(int id) {
    if (!contains(id)) return;
    swapWithLast(id);
    objects_.pop_back();
    slot_[id] = -1;
  }
  bool contains(int id) const { return id >= 0 && id < static_cast<int>(slot_.size()) && slot_[id] >= 0; }

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
      for (std::size_t j = i + 1; j < objects_.size(); ++j)
        f(std::min(objects_[i], objects_[j]), std::max(objects_[i], objects_[j]));
  }
  double exitTime(int /*id*/, const BallPath<D>& /*path*/) const { return std::numeric_limits<double>::infinity(); }
  static double listingMargin(double /*radius*/, double /*fatFraction*/) { return 0.0; }

  std::vector<int> leaves() const { return {0}; }
  Box leafBounds(int /*leaf*/) const { return bounds_; }
  ObjectList objectsIn(int /*leaf*/) const { return {objects_.data(), objects_.size(), 0}; }
  const std::vector<int>& leavesOf(int /*id*/) const { return root_; }
  int depthOf(int /*leaf*/) const { return 0; }
  int leafCount() const { return 1; }
  const SpaceCounters& counters() const { return counters_; }

 private:
  void swapWithLast(int id) {
    const int s = slot_[id];
    const int last = objects_.back();
    std::swap(objects_[s], objects_.back());
    slot_[last] = s;
    slot_[id] = static_cast<int>(objects_.size()) - 1;
  }

  Box bounds_;
  std::vector<int> objects_;
  std::vector<int> slot_;     // id -> index in objects_, -1 if absent
  std::vector<int> root_{0};
  SpaceCounters counters_;    // all zero: one region never divides nor transfers
};

static_assert(Broadphase<SingleList<2>, 2> && Broadphase<SingleList<3>, 3>);

}  // namespace st
