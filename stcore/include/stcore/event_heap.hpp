#pragma once
// The simulator's event queue: an indexed min-heap of items 0..n-1 (balls), each with one key,
// ordered by (time, item) so that equal times leave in a fixed order.
//
// Sifting is latency-bound: a level's children must be read before the next level is known, and
// the heap outgrows L1 at 10^4 balls. So the times live in their own 64-byte-aligned array, apart
// from the items: a node's four children's times are 32 bytes that never straddle a cache line,
// and the items are read only for the child that moves and on equal times. Side by side at 2-D
// N = 10^4 this is 4-5 % faster than (time, item) entries in one array; arity 8 (one full line per
// level) was 2 % faster and 16 slower than the old layout.
#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

namespace st {

template <class T, std::size_t Align>
struct AlignedAllocator {
  using value_type = T;
  AlignedAllocator() = default;
  template <class U>
  AlignedAllocator(const AlignedAllocator<U, Align>&) {}
  template <class U>
  struct rebind {
    using other = AlignedAllocator<U, Align>;
  };
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t{Align})); }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t{Align}); }
  bool operator==(const AlignedAllocator&) const { return true; }
};

class EventHeap {
 public:
  static constexpr int kArity = 4;

  bool empty() const { return size_ == 0; }
  int size() const { return size_; }
  // The earliest item and its time (not empty()).
  int top() const { return item_[kPad]; }
  double topTime() const { return time_[kPad]; }
  bool contains(int item) const { return item < static_cast<int>(pos_.size()) && pos_[item] >= 0; }
  // An item's key (contains(item)).
  double timeOf(int item) const { return time_[kPad + pos_[item]]; }

  // Gives item the key t (inserting it if absent). t must not be NaN.
  void set(int item, double t) {
    t += 0.0;  // no -0.0: the times' bits must order as the times do (see siftDown)
    if (item >= static_cast<int>(pos_.size())) pos_.resize(static_cast<std::size_t>(item) + 1, -1);
    int pos = pos_[item];
    if (pos < 0) {
      pos = size_++;
      time_.resize(static_cast<std::size_t>(kPad + size_));
      item_.resize(static_cast<std::size_t>(kPad + size_));
      siftUp(pos, t, item);
      return;
    }
    // a key only moves one way: sift in that direction
    if (before(t, item, time_[kPad + pos], item)) siftUp(pos, t, item);
    else siftDown(pos, t, item);
  }

  void remove(int item) {
    if (!contains(item)) return;
    const int pos = pos_[item];
    pos_[item] = -1;
    --size_;
    const double lastT = time_[kPad + size_];
    const int last = item_[kPad + size_];
    time_.pop_back();
    item_.pop_back();
    if (last == item) return;
    // the last entry fills the hole: it may belong above or below it
    if (pos > 0 && before(lastT, last, time_[kPad + (pos - 1) / kArity], item_[kPad + (pos - 1) / kArity]))
      siftUp(pos, lastT, last);
    else
      siftDown(pos, lastT, last);
  }

 private:
  // Position p lives at index kPad + p, so the children of p, at kArity * p + 1 ..., start at a
  // multiple of kArity: one aligned line.
  static constexpr int kPad = kArity - 1;

  static bool before(double ta, int a, double tb, int b) { return ta < tb || (ta == tb && a < b); }

  void place(int pos, double t, int item) {
    time_[kPad + pos] = t;
    item_[kPad + pos] = item;
    pos_[item] = pos;
  }

  void siftUp(int pos, double t, int item) {
    while (pos > 0) {
      const int parent = (pos - 1) / kArity;
      const double pt = time_[kPad + parent];
      const int pi = item_[kPad + parent];
      if (!before(t, item, pt, pi)) break;
      place(pos, pt, pi);
      pos = parent;
    }
    place(pos, t, item);
  }

  void siftDown(int pos, double t, int item) {
    while (true) {
      const int first = kArity * pos + 1;
      if (first >= size_) break;
      const int count = std::min(kArity, size_ - first);
      const double* times = &time_[kPad + first];
      // the grandchildren's times are contiguous: fetch them while these are compared
      const double* grand = times + (kArity - 1) * first + 1;
      if (grand + kArity * kArity <= time_.data() + time_.size()) {
        // (the two ends; a third prefetch for the middle line measured no faster)
        __builtin_prefetch(grand);
        __builtin_prefetch(grand + kArity * kArity - 1);
      }
      // the least time by selects on the times' bits (times are >= +0.0, where the bits of a
      // double order as the double does): which child it is cannot be predicted, and a branch
      // per child costs a misprediction per level
      std::int64_t least = std::bit_cast<std::int64_t>(times[0]);
      int child = 0;
      bool tie = false;
      for (int c = 1; c < count; ++c) {
        const std::int64_t tc = std::bit_cast<std::int64_t>(times[c]);
        const bool less = tc < least;
        tie = (tie | (tc == least)) & !less;  // another child holds the least time
        const std::int64_t keep = static_cast<std::int64_t>(less) - 1;  // all ones when not less
        child = static_cast<int>((c & ~keep) | (child & keep));
        least = (tc & ~keep) | (least & keep);
      }
      if (tie) {  // equal least times (a colliding pair's two events): the lower item goes first
        for (int c = 0; c < count; ++c)
          if (std::bit_cast<std::int64_t>(times[c]) == least && item_[kPad + first + c] < item_[kPad + first + child])
            child = c;
      }
      child += first;
      const double ct = time_[kPad + child];
      const int ci = item_[kPad + child];
      if (!before(ct, ci, t, item)) break;
      place(pos, ct, ci);
      pos = child;
    }
    place(pos, t, item);
  }

  std::vector<double, AlignedAllocator<double, 64>> time_ = std::vector<double, AlignedAllocator<double, 64>>(kPad);
  std::vector<int> item_ = std::vector<int>(kPad);
  std::vector<int> pos_;  // per item: its position, or -1
  int size_ = 0;
};

}  // namespace st
