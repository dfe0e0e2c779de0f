// EventHeap against a brute-force reference (a std::set of (time, item)): after every random
// insert, re-key (earlier and later) and removal, top() is the least (time, item) and every item's
// presence agrees. Times are drawn from a small set so that equal times, which order by item, are
// common, as they are for a colliding pair's two events.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>
#include <utility>

#include <stcore/event_heap.hpp>

namespace st {
namespace {

TEST(EventHeap, MatchesOrderedSetUnderRandomOperations) {
  for (int items : {1, 2, 5, 17, 64, 1000}) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(items));
    EventHeap heap;
    std::set<std::pair<double, int>> reference;
    std::map<int, double> key;
    std::uniform_int_distribution<int> pick(0, items - 1);
    std::uniform_int_distribution<int> coarse(0, 20);
    std::uniform_real_distribution<double> fine(0.0, 100.0);
    for (int step = 0; step < 20000; ++step) {
      const int item = pick(rng);
      if (rng() % 5 == 0) {
        heap.remove(item);
        if (key.count(item)) reference.erase({key[item], item});
        key.erase(item);
      } else {
        // half the times from 21 values (ties), half continuous; zero included
        const double t = rng() % 2 ? static_cast<double>(coarse(rng)) : fine(rng);
        heap.set(item, t);
        if (key.count(item)) reference.erase({key[item], item});
        key[item] = t;
        reference.insert({t, item});
      }
      ASSERT_EQ(heap.size(), static_cast<int>(reference.size()));
      ASSERT_EQ(heap.empty(), reference.empty());
      if (!reference.empty()) {
        ASSERT_EQ(heap.top(), reference.begin()->second) << "items " << items << " step " << step;
        ASSERT_EQ(heap.topTime(), reference.begin()->first);
      }
      ASSERT_EQ(heap.contains(item), key.count(item) == 1);
    }
    // draining in order gives the reference's order
    while (!reference.empty()) {
      ASSERT_EQ(heap.top(), reference.begin()->second);
      heap.remove(heap.top());
      reference.erase(reference.begin());
    }
    EXPECT_TRUE(heap.empty());
  }
}

TEST(EventHeap, NegativeZeroOrdersAsZero) {
  EventHeap heap;
  heap.set(3, 0.0);
  heap.set(1, -0.0);
  heap.set(2, 1.0);
  EXPECT_EQ(heap.top(), 1);  // equal times: lower item first
  heap.remove(1);
  EXPECT_EQ(heap.top(), 3);
}

}  // namespace
}  // namespace st
