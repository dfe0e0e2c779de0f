// EventCalendar against two independent orders: a std::set of (time, item) and the EventHeap it
// replaces. Random operations as the simulator makes them (the earliest item re-keyed later, any
// item re-keyed or removed, equal times, infinite and far times, -0.0), at block widths from a
// fraction of an update per block to hundreds, so that blocks, lists, the overflow, jumps over
// empty blocks and re-filings at a new width all happen: after every operation the calendar's top
// and time are the set's least and the heap's top, and draining gives the set's order.
#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <random>
#include <set>
#include <utility>

#include <stcore/event_calendar.hpp>
#include <stcore/event_heap.hpp>

namespace st {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void expectSame(const EventCalendar& cal, const EventHeap& heap, const std::set<std::pair<double, int>>& ref) {
  ASSERT_EQ(cal.size(), static_cast<int>(ref.size()));
  ASSERT_EQ(cal.empty(), ref.empty());
  ASSERT_EQ(heap.size(), cal.size());
  if (ref.empty()) return;
  ASSERT_EQ(cal.top(), ref.begin()->second);
  ASSERT_EQ(cal.topTime(), ref.begin()->first);
  ASSERT_EQ(cal.top(), heap.top());
}

TEST(EventCalendar, MatchesOrderedSetAndHeapUnderSimulatorLikeOperations) {
  for (double perBlock : {0.0, 0.25, 1.0, 4.0, 32.0, 300.0}) {
    for (int items : {1, 3, 17, 200, 3000}) {
      SCOPED_TRACE(testing::Message() << "per block " << perBlock << " items " << items);
      std::mt19937_64 rng(static_cast<std::uint64_t>(items * 7919 + static_cast<int>(perBlock * 4)));
      EventCalendar cal(perBlock);
      EventHeap heap;
      std::set<std::pair<double, int>> ref;
      std::map<int, double> key;
      auto put = [&](int item, double t) {
        cal.set(item, t);
        heap.set(item, t);
        if (key.count(item)) ref.erase({key[item], item});
        key[item] = t + 0.0;
        ref.insert({t + 0.0, item});
      };
      auto drop = [&](int item) {
        cal.remove(item);
        heap.remove(item);
        if (key.count(item)) ref.erase({key[item], item});
        key.erase(item);
      };
      std::uniform_int_distribution<int> pick(0, items - 1);
      std::exponential_distribution<double> delay(1.0);
      for (int i = 0; i < items; ++i) put(i, delay(rng));
      for (int step = 0; step < 40000; ++step) {
        const double now = ref.empty() ? 0.0 : ref.begin()->first;
        const double base = now < kInf ? now : 0.0;
        const int r = static_cast<int>(rng() % 100);
        if (r < 50 && !ref.empty()) {
          // the earliest item's event happens: its next one is later (sometimes at the same time)
          const int item = ref.begin()->second;
          put(item, rng() % 8 == 0 ? base : base + delay(rng) * items * 0.01);
        } else if (r < 75) {
          // another item is re-predicted: earlier or later, often a tie with a quantised time
          const double t = rng() % 2 ? base + static_cast<double>(rng() % 4) * 0.125 : base + delay(rng) * items * 0.01;
          put(pick(rng), t);
        } else if (r < 82) {
          put(pick(rng), kInf);  // at rest: no event
        } else if (r < 85) {
          put(pick(rng), base + 1e6 * delay(rng));  // far beyond any horizon (the overflow)
        } else if (r < 86) {
          put(pick(rng), -0.0);  // before now, and negative zero
        } else if (r < 92) {
          drop(pick(rng));
        } else {
          put(pick(rng), base + delay(rng) * 10.0);
        }
        expectSame(cal, heap, ref);
        if (HasFatalFailure()) return;
      }
      while (!ref.empty()) {
        ASSERT_EQ(cal.top(), ref.begin()->second);
        ASSERT_EQ(cal.topTime(), ref.begin()->first);
        drop(cal.top());
      }
      EXPECT_TRUE(cal.empty());
    }
  }
}

// With a width tuned to a few updates per block most items wait unsorted: the heap holds few.
TEST(EventCalendar, SortsOnlyTheCurrentBlock) {
  EventCalendar cal(4.0);
  std::mt19937_64 rng(5);
  std::exponential_distribution<double> delay(1.0);
  const int n = 4000;
  for (int i = 0; i < n; ++i) cal.set(i, delay(rng));
  int largest = 0;
  for (int step = 0; step < 200000; ++step) {
    const double now = cal.topTime();
    cal.set(cal.top(), now + delay(rng));
    if (step > 50000) largest = std::max(largest, cal.sortedSize());
  }
  EXPECT_LT(cal.blockWidth(), kInf);
  EXPECT_LT(largest, 200);
  EXPECT_EQ(cal.size(), n);
}

}  // namespace
}  // namespace st
