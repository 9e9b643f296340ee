// DrawList: what a technique selected for one frame, as plain data (DESIGN.md). The renderer
// makes the `uploads` first, draws `opaque`, `proxies`, then `far_quads` behind everything
// drawn so far, `transparent` with blending, and `lines` over the top, each in the order
// given. Scene ranges are of the scene's index array; proxy ranges of the technique's
// ProxyMesh. Capacity is kept between frames: clear() does not free.
#pragma once

#include <array>
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

// Texture slots of the renderer, for TextureUpload and TexturedQuad.
inline constexpr uint32_t kTextureSlots = 256;

// Pixels for one of the renderer's texture slots (far-field images: paper 000's box sides).
// The pixels belong to the technique and must stay valid until Renderer::draw returns.
struct TextureUpload {
  uint32_t slot;          // < kTextureSlots
  int width, height;      // pixels
  int channels;           // 3 (RGB8) or 4 (RGBA8, alpha = coverage)
  const uint8_t* pixels;  // rows from the top
};

// A quadrilateral showing a slot's texture: corners at the image's top-left, top-right,
// bottom-right and bottom-left. Blended with the texture's alpha times `opacity`.
struct TexturedQuad {
  std::array<glm::vec3, 4> corners;
  uint32_t slot;
  float opacity = 1.0f;
};

// A line in the picture (bird's-eye annotations: frusta, viewcells), drawn over everything.
struct LineSegment {
  glm::vec3 from, to;
  uint32_t color;  // RGBA8, R in the low byte
};

struct DrawList {
  std::vector<DrawRange> opaque;
  std::vector<DrawRange> transparent;
  std::vector<DrawRange> proxies;  // of the technique's ProxyMesh; `material` unused
  std::vector<TextureUpload> uploads;
  // Far-field quads. Normally a backdrop, in order, filling only what no geometry covers, so
  // that all geometry lands in front of them (a near object that crosses the box is not cut).
  // With `quads_in_world` (bird's-eye views) they are drawn at their place, both sides.
  std::vector<TexturedQuad> far_quads;
  bool quads_in_world = false;
  std::vector<LineSegment> lines;

  void clear() {
    opaque.clear();
    transparent.clear();
    proxies.clear();
    uploads.clear();
    far_quads.clear();
    quads_in_world = false;
    lines.clear();
  }
  // Scene, proxy and far-quad triangles together (two per quad).
  uint64_t triangle_count() const {
    uint64_t n = 2 * far_quads.size();
    for (const auto* ranges : {&opaque, &transparent, &proxies})
      for (const auto& r : *ranges) n += r.index_count / 3;
    return n;
  }
  uint64_t proxy_triangle_count() const {
    uint64_t n = 0;
    for (const auto& r : proxies) n += r.index_count / 3;
    return n;
  }
  // Draw commands the renderer issues (one per range and quad).
  uint64_t draw_count() const {
    return opaque.size() + transparent.size() + proxies.size() + far_quads.size();
  }
};

}  // namespace farfield
