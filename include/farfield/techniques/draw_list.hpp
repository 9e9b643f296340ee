// DrawList: what a technique selected for one frame, as plain data (DESIGN.md). The renderer
// draws `opaque` first, then `proxies`, then `transparent` with blending, each in the order
// given. Scene ranges are of the scene's index array; proxy ranges of the technique's
// ProxyMesh. Capacity is kept between frames: clear() does not free.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace farfield {

struct DrawRange {
  uint32_t first_index;  // into Scene::indices, a multiple of 3
  uint32_t index_count;  // a multiple of 3
  uint32_t material;     // into Scene::materials
};

// Stand-in geometry a technique draws instead of scene geometry (colour-cube faces, ...):
// unlit, its colour already shaded when baked; alpha < 1 is blended. Counter-clockwise
// front faces, back faces culled.
struct ProxyVertex {
  glm::vec3 position;  // metres
  uint32_t color;      // RGBA8 unorm, R in the low byte
};
static_assert(sizeof(ProxyVertex) == 16);

struct ProxyMesh {
  std::vector<ProxyVertex> vertices;
  std::vector<uint32_t> indices;  // triangles
};

struct DrawList {
  std::vector<DrawRange> opaque;
  std::vector<DrawRange> transparent;
  std::vector<DrawRange> proxies;  // of the technique's ProxyMesh; `material` unused

  void clear() {
    opaque.clear();
    transparent.clear();
    proxies.clear();
  }
  // Scene triangles and proxy triangles together.
  uint64_t triangle_count() const {
    uint64_t n = 0;
    for (const auto* ranges : {&opaque, &transparent, &proxies})
      for (const auto& r : *ranges) n += r.index_count / 3;
    return n;
  }
  uint64_t proxy_triangle_count() const {
    uint64_t n = 0;
    for (const auto& r : proxies) n += r.index_count / 3;
    return n;
  }
  // Draw commands the renderer issues (one per range).
  uint64_t draw_count() const { return opaque.size() + transparent.size() + proxies.size(); }
};

}  // namespace farfield
