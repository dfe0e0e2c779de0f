#pragma once
// The simulator's event queue as an event calendar (Smallenburg's EDMD, EPJE 2022): time is cut
// into blocks of one width; the events of the current block are sorted, the later ones wait
// unsorted in one list per block. An update of an event in a later block costs O(1) instead of a
// sift through a heap of every ball.
//
// The current block: when it becomes current its list is copied into one array and sorted once
// (the run), which is then served front to back; an item leaving the run (re-keyed or removed)
// is only marked, and the front skips the marked ones. An item re-keyed into the current block
// (and every infinite time) goes to a small EventHeap beside the run, and the top is the earlier
// of the two fronts. Most updates re-key the top, so most leave the run at its front, in O(1)
// instead of a sift-down; and a block comes in with one sort instead of a heap insertion (and a
// vector resize) per item. Callgrind, 3-D N 4000 with lists, K 32: the queue 479 M -> 275 M
// instructions, the run 0.937x (bench/RESULTS.md).
//
// Same interface and the same order as EventHeap: items 0..n-1, one key each, ordered by
// (time, item). The order is exact because a block is floor((t - origin) / width), monotone in t:
// every sorted item (block <= current) comes before every item outside it, and ties (equal times)
// share a block and are ordered by the run's sort, the heap, and the (time, item) comparison of
// their two fronts.
//
// Blocks: `buckets` lists cover the next buckets - 1 blocks cyclically; items beyond them wait in
// an overflow list, re-filed each time the current block has gone round the buckets once (every
// overflow item then lies at or beyond the next re-filing). An empty calendar jumps to the earliest
// overflow block instead of walking empty lists.
//
// Width: with eventsPerBlock = 0 the calendar never leaves its one block (the plain heap). Otherwise
// it measures its updates per unit of time every 2 n updates (at least 1024) and, when the width
// for eventsPerBlock updates per block is off by more than 2x, re-files every item at that width,
// with about 4 n / eventsPerBlock lists (a horizon of about four times a ball's mean time between
// updates). Every input is a count or a key, so the calendar is deterministic, and no re-filing
// changes the order.
//
// The lists are intrusive (next/prev item indices per item, a head per list), as EDMD's: no
// allocation per list and O(1) removal.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <stcore/event_heap.hpp>

namespace st {

class EventCalendar {
 public:
  explicit EventCalendar(double eventsPerBlock = 0.0) : eventsPerBlock_(eventsPerBlock) {}

  bool empty() const { return size_ == 0; }
  int size() const { return size_; }
  // The earliest item and its time (not empty()).
  int top() const { return runFirst() ? run_[runAt_].second : heap_.top(); }
  double topTime() const { return runFirst() ? run_[runAt_].first : heap_.topTime(); }
  bool contains(int item) const { return item < static_cast<int>(where_.size()) && where_[item] != kAbsent; }
  // The items sorted now (the current block's and the infinite), and the current block's width.
  int sortedSize() const { return heap_.size() + runLive_; }
  double blockWidth() const { return invWidth_ > 0.0 ? 1.0 / invWidth_ : std::numeric_limits<double>::infinity(); }

  // Gives item the key t (inserting it if absent). t must not be NaN.
  void set(int item, double t) {
    t += 0.0;  // as EventHeap: no -0.0
    if (item >= static_cast<int>(where_.size())) grow(item + 1);
    const int at = where_[item];
    if (at == kAbsent) ++size_;
    if (invWidth_ == 0.0) {  // one block: the heap alone
      where_[item] = kHeap;
      heap_.set(item, t);
    } else {
      file(item, t, at);
      settle();
    }
    if (eventsPerBlock_ > 0.0 && ++updates_ >= tuneEvery()) tune();
  }

  void remove(int item) {
    if (!contains(item)) return;
    const int at = where_[item];
    if (at == kHeap) heap_.remove(item);
    else if (at == kRun) leaveRun(item);
    else unlink(item, at);
    where_[item] = kAbsent;
    --size_;
    settle();
  }

 private:
  static constexpr int kAbsent = -1;
  static constexpr int kHeap = -2;
  static constexpr int kRun = -3;
  // blocks at or past this are "far": overflow (finite times only; infinite ones are sorted)
  static constexpr std::int64_t kFar = std::int64_t{1} << 62;

  std::int64_t blockOf(double t) const {
    const double x = (t - origin_) * invWidth_;  // monotone in t
    if (!(x < static_cast<double>(kFar))) return kFar;
    return x <= 0.0 ? 0 : static_cast<std::int64_t>(x);  // floor, x >= 0
  }
  int overflowList() const { return static_cast<int>(head_.size()) - 1; }

  void grow(int n) {
    where_.resize(static_cast<std::size_t>(n), kAbsent);
    time_.resize(static_cast<std::size_t>(n), 0.0);
    next_.resize(static_cast<std::size_t>(n), -1);
    prev_.resize(static_cast<std::size_t>(n), -1);
  }

  // Puts item (now at `at`) where time t belongs.
  void file(int item, double t, int at) {
    const std::int64_t b = blockOf(t);
    if (b <= cur_ || t == std::numeric_limits<double>::infinity()) {
      if (at == kRun) leaveRun(item);
      else if (at >= 0) unlink(item, at);
      where_[item] = kHeap;
      heap_.set(item, t);
      return;
    }
    if (at == kHeap) heap_.remove(item);
    else if (at == kRun) leaveRun(item);
    else if (at >= 0) unlink(item, at);
    time_[item] = t;
    link(item, b < cur_ + buckets_ ? static_cast<int>(b & (buckets_ - 1)) : overflowList());
  }

  void link(int item, int list) {
    const int h = head_[static_cast<std::size_t>(list)];
    next_[item] = h;
    prev_[item] = -1;
    if (h >= 0) prev_[h] = item;
    head_[static_cast<std::size_t>(list)] = item;
    where_[item] = list;
    ++waiting_;
    if (list == overflowList()) ++overflowN_;
  }

  void unlink(int item, int list) {
    const int n = next_[item], p = prev_[item];
    if (p >= 0) next_[p] = n;
    else head_[static_cast<std::size_t>(list)] = n;
    if (n >= 0) prev_[n] = p;
    --waiting_;
    if (list == overflowList()) --overflowN_;
  }

  // The run's front is live (or the run is done); whether it, not the heap's top, is the earliest.
  bool runFirst() const {
    if (runLive_ == 0) return false;  // (then runAt_ is the run's end)
    if (heap_.empty()) return true;
    const double t = run_[runAt_].first, ht = heap_.topTime();
    return t < ht || (t == ht && run_[runAt_].second < heap_.top());
  }

  // Marks item as gone from the run; past the front when it was the front.
  void leaveRun(int item) {
    where_[item] = kAbsent;
    --runLive_;
    if (run_[runAt_].second != item) return;
    ++runAt_;
    while (runAt_ < static_cast<int>(run_.size()) && where_[run_[runAt_].second] != kRun) ++runAt_;
  }

  // Keeps the earliest item sorted: while only infinite times (or none) are sorted and items wait
  // in lists, makes the next block current.
  void settle() {
    while (waiting_ > 0 && runLive_ == 0 &&
           (heap_.empty() || heap_.topTime() == std::numeric_limits<double>::infinity())) {
      if (waiting_ == overflowN_) {
        // only the overflow waits: jump to its earliest block and re-file it from there
        std::int64_t least = kFar;
        for (int i = head_[static_cast<std::size_t>(overflowList())]; i >= 0; i = next_[i])
          least = std::min(least, blockOf(time_[i]));
        cur_ = least;
        refileOverflow();
        continue;
      }
      ++cur_;
      if (cur_ >= nextRefile_) refileOverflow();
      const int list = static_cast<int>(cur_ & (buckets_ - 1));
      int i = head_[static_cast<std::size_t>(list)];
      head_[static_cast<std::size_t>(list)] = -1;
      // the block's list becomes the run, sorted once by (time, item) (no -0.0, no NaN: the
      // pairs' order is the heap's)
      run_.clear();
      runAt_ = 0;
      for (; i >= 0; i = next_[i]) {
        where_[i] = kRun;
        run_.push_back({time_[i], i});
      }
      runLive_ = static_cast<int>(run_.size());
      waiting_ -= runLive_;
      std::sort(run_.begin(), run_.end());
    }
  }

  // Re-files the overflow from the current block; what stays lies at or past nextRefile_.
  void refileOverflow() {
    nextRefile_ = cur_ + buckets_;
    const int list = overflowList();
    int i = head_[static_cast<std::size_t>(list)];
    head_[static_cast<std::size_t>(list)] = -1;
    waiting_ -= overflowN_;
    overflowN_ = 0;
    while (i >= 0) {
      const int n = next_[i];
      where_[i] = kAbsent;
      file(i, time_[i], kAbsent);
      i = n;
    }
  }

  std::uint64_t tuneEvery() const { return std::max<std::uint64_t>(1024, 2 * static_cast<std::uint64_t>(size_)); }

  // Measures updates per unit of time; re-files everything when the width is off by over 2x.
  [[gnu::noinline]] void tune() {
    const double now = size_ == 0 ? tunedAt_ : topTime();
    const double span = now - tunedAt_;
    const double rate = static_cast<double>(updates_) / span;
    updates_ = 0;
    tunedAt_ = now;
    if (!(span > 0.0) || !std::isfinite(now) || !(rate > 0.0) || !std::isfinite(rate)) return;
    const double inv = rate / eventsPerBlock_;  // 1 / the wanted width
    if (invWidth_ > 0.0 && inv < 2.0 * invWidth_ && inv > 0.5 * invWidth_) return;
    rebuild(now, inv);
  }

  [[gnu::noinline]] void rebuild(double origin, double invWidth) {
    std::vector<std::pair<int, double>> all;
    all.reserve(static_cast<std::size_t>(size_));
    for (int i = 0; i < static_cast<int>(where_.size()); ++i) {
      if (where_[i] == kAbsent) continue;
      all.push_back({i, where_[i] == kHeap ? heap_.timeOf(i) : time_[i]});  // time_: lists and run
      where_[i] = kAbsent;
    }
    heap_ = EventHeap{};
    run_.clear();
    runAt_ = 0;
    runLive_ = 0;
    std::int64_t lists = 16;
    const double wanted = 4.0 * size_ / eventsPerBlock_;
    while (static_cast<double>(lists) < wanted && lists < (std::int64_t{1} << 24)) lists *= 2;
    buckets_ = lists;
    head_.assign(static_cast<std::size_t>(buckets_ + 1), -1);
    origin_ = origin;
    invWidth_ = invWidth;
    cur_ = 0;
    nextRefile_ = buckets_;
    waiting_ = 0;
    overflowN_ = 0;
    for (const auto& [i, t] : all) file(i, t, kAbsent);
    settle();
  }

  double eventsPerBlock_;
  EventHeap heap_;
  std::vector<int> where_;    // per item: kAbsent, kHeap, kRun or its list
  std::vector<double> time_;  // per item in a list or the run: its key
  // the current block sorted once: (time, item), served from runAt_ (live there, or the end);
  // entries whose item left (where_ != kRun) are skipped
  std::vector<std::pair<double, int>> run_;
  int runAt_ = 0;
  int runLive_ = 0;
  std::vector<int> next_, prev_;
  std::vector<int> head_ = std::vector<int>(2, -1);  // per list its first item; the last: overflow
  std::int64_t buckets_ = 1;
  std::int64_t cur_ = 0;  // the current block: sorted in the heap are blocks <= cur_
  std::int64_t nextRefile_ = 1;
  int waiting_ = 0;    // items in lists
  int overflowN_ = 0;  // of them in the overflow
  int size_ = 0;
  double origin_ = 0.0;
  double invWidth_ = 0.0;  // 0: one block, a plain heap
  std::uint64_t updates_ = 0;
  double tunedAt_ = 0.0;
};

}  // namespace st
