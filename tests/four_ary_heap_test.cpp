#include "farfield/core/four_ary_heap.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <iterator>
#include <random>
#include <set>
#include <vector>

namespace farfield {
namespace {

// Pushes and pops interleaved at random against an ordered set: every pop the largest key
// held, at every size (a node's last children partly present included).
TEST(FourAryHeap, PopsTheLargestKeyAtEverySize) {
  std::mt19937_64 random(7);
  std::vector<uint64_t> heap;
  std::set<uint64_t> held;
  uint64_t pops = 0;
  for (int step = 0; step < 20000; ++step) {
    const bool push = held.empty() || (random() % 100) < (step < 10000 ? 60u : 40u);
    if (push) {
      uint64_t key = random() % 5000;  // few distinct values: near keys meet often
      key = key << 32 | uint64_t(step);  // distinct, as the selection's (key, item) pairs
      four_ary_heap_push(heap, key);
      held.insert(key);
    } else {
      const uint64_t expected = *held.rbegin();
      held.erase(std::prev(held.end()));
      ASSERT_EQ(four_ary_heap_pop(heap), expected) << "pop " << pops;
      ++pops;
    }
    ASSERT_EQ(heap.size(), held.size());
    if (!heap.empty()) {
      ASSERT_EQ(heap.front(), *held.rbegin());
    }
  }
  EXPECT_GT(pops, 5000u);
  while (!held.empty()) {  // drained to empty
    ASSERT_EQ(four_ary_heap_pop(heap), *held.rbegin());
    held.erase(std::prev(held.end()));
  }
  EXPECT_TRUE(heap.empty());
}

TEST(FourAryHeap, OneKeyIsPushedAndPoppedBack) {
  std::vector<uint64_t> heap;
  four_ary_heap_push(heap, 42);
  EXPECT_EQ(four_ary_heap_pop(heap), 42u);
  EXPECT_TRUE(heap.empty());
}

}  // namespace
}  // namespace farfield
