// DrawList: what a technique selected for one frame, as plain data (DESIGN.md). The renderer
// draws `opaque` first, then `transparent` with blending, each in the order given. Ranges are
// of the scene's index array. Capacity is kept between frames: clear() does not free.
#pragma once

#include <cstdint>
#include <vector>

namespace farfield {

struct DrawRange {
  uint32_t first_index;  // into Scene::indices, a multiple of 3
  uint32_t index_count;  // a multiple of 3
  uint32_t material;     // into Scene::materials
};

struct DrawList {
  std::vector<DrawRange> opaque;
  std::vector<DrawRange> transparent;

  void clear() {
    opaque.clear();
    transparent.clear();
  }
  uint64_t triangle_count() const {
    uint64_t n = 0;
    for (const auto& r : opaque) n += r.index_count / 3;
    for (const auto& r : transparent) n += r.index_count / 3;
    return n;
  }
  // Draw commands the renderer issues (one per range).
  uint64_t draw_count() const { return opaque.size() + transparent.size(); }
};

}  // namespace farfield
