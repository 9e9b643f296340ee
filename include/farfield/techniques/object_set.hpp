// A set of object numbers that turns into a DrawList in scene order: objects are drawn in
// the order brute force draws them, so a technique that selects a subset produces the same
// pixels wherever it keeps everything visible, and neighbouring objects with the same
// material merge into one draw range. A bit per object: inserting is O(1), repeats are free.
#pragma once

#include <cstdint>
#include <vector>

#include "farfield/scene/scene.hpp"
#include "farfield/gpu/draw_list.hpp"

namespace farfield {

class ObjectSet {
 public:
  explicit ObjectSet(const Scene& scene);
  void clear();
  void insert(uint32_t object) { words_[object >> 6] |= uint64_t(1) << (object & 63); }
  bool contains(uint32_t object) const { return (words_[object >> 6] >> (object & 63)) & 1; }
  void insert_all();
  // Every object whose bounds meet `box` (touching counts: Region::near's objects).
  void insert_meeting(const Bounds3& box);
  // Appends the set's objects to `out` in scene order, merging contiguous ranges.
  void emit(DrawList& out) const;

 private:
  const Scene& scene_;
  std::vector<uint64_t> words_;
};

}  // namespace farfield
