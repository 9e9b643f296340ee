// A max-heap of distinct 64-bit keys with four children a node: half the levels of a binary
// heap, each pair of children compared without a branch (std::pop_heap's sifting, a
// mispredicted compare a level, took a third of the clusters' budget pass). With distinct keys
// it pops in the same order as any max-heap: largest first.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace farfield {

inline void four_ary_heap_push(std::vector<uint64_t>& heap, uint64_t key) {
  size_t i = heap.size();
  heap.push_back(key);
  while (i > 0) {
    const size_t parent = (i - 1) / 4;
    if (heap[parent] > key) break;
    heap[i] = heap[parent];
    i = parent;
  }
  heap[i] = key;
}

// The largest key, removed; the heap must not be empty.
inline uint64_t four_ary_heap_pop(std::vector<uint64_t>& heap) {
  const uint64_t top = heap.front(), last = heap.back();
  heap.pop_back();
  const size_t n = heap.size();
  if (n == 0) return top;
  size_t i = 0;
  for (;;) {
    const size_t first = 4 * i + 1;
    if (first >= n) break;
    size_t best = first;
    if (first + 3 < n) {
      const size_t a = first + size_t(heap[first + 1] > heap[first]);
      const size_t b = first + 2 + size_t(heap[first + 3] > heap[first + 2]);
      best = heap[b] > heap[a] ? b : a;
    } else {
      for (size_t c = first + 1; c < n; ++c) best = heap[c] > heap[best] ? c : best;
    }
    if (heap[best] < last) break;
    heap[i] = heap[best];
    i = best;
  }
  heap[i] = last;
  return top;
}

}  // namespace farfield
