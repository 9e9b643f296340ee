#include "city_textures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>

namespace farfield::city {

namespace {

constexpr int kSide = 256;

// Integer hash noise in [0, 1): the same value for the same (x, y, salt) on every machine.
float noise(uint32_t x, uint32_t y, uint32_t salt) {
  uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ salt * 0xcb1ab31fu;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return float(h & 0xffffff) / float(0x1000000);
}

// Value noise smoothed over cells of `cell` texels, tiling over kSide.
float smooth_noise(int x, int y, int cell, uint32_t salt) {
  const int n = kSide / cell;
  const float fx = float(x) / cell, fy = float(y) / cell;
  const int x0 = int(fx), y0 = int(fy);
  const float tx = fx - x0, ty = fy - y0;
  auto at = [&](int i, int j) { return noise(uint32_t(i % n), uint32_t(j % n), salt); };
  return (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x0 + 1, y0)) +
         ty * ((1 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1));
}

void put(Texels& t, int x, int y, float r, float g, float b) {
  uint8_t* p = t.texel(x, y);
  p[0] = uint8_t(std::clamp(r, 0.0f, 1.0f) * 255.0f + 0.5f);
  p[1] = uint8_t(std::clamp(g, 0.0f, 1.0f) * 255.0f + 0.5f);
  p[2] = uint8_t(std::clamp(b, 0.0f, 1.0f) * 255.0f + 0.5f);
  p[3] = 255;
}

}  // namespace

Texels facade_texels() {
  Texels t(kSide, kSide);
  constexpr int course = 16, brick = 32, mortar = 2;  // 8 courses a repeat
  for (int y = 0; y < kSide; ++y) {
    const int row = y / course, offset = row % 2 ? brick / 2 : 0;
    for (int x = 0; x < kSide; ++x) {
      const int bx = (x + offset) % kSide;
      const bool joint = y % course < mortar || bx % brick < mortar;
      const float shade = joint ? 0.72f
                                : 0.86f + 0.1f * noise(uint32_t(bx / brick), uint32_t(row), 1) +
                                      0.06f * smooth_noise(x, y, 8, 2);
      put(t, x, y, shade, shade * 0.97f, shade * 0.94f);
    }
  }
  return t;
}

Texels paving_texels() {
  Texels t(kSide, kSide);
  constexpr int slab = 64, joint = 2;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const bool gap = x % slab < joint || y % slab < joint;
      const float shade = gap ? 0.7f
                              : 0.9f + 0.06f * noise(uint32_t(x / slab), uint32_t(y / slab), 3) +
                                    0.05f * smooth_noise(x, y, 4, 4);
      put(t, x, y, shade, shade, shade * 0.98f);
    }
  return t;
}

Texels asphalt_texels() {
  Texels t(kSide, kSide);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const float shade =
          0.8f + 0.12f * noise(uint32_t(x), uint32_t(y), 5) + 0.08f * smooth_noise(x, y, 16, 6);
      put(t, x, y, shade, shade, shade);
    }
  return t;
}

void project_texture_coordinates(Scene& scene, const Object& object, float tile) {
  for (uint32_t i = 0; i < object.vertex_count; ++i) {
    const Vertex& v = scene.vertices[object.first_vertex + i];
    const glm::vec3 n = unpack_normal(v.normal), p = v.position;
    glm::vec2 uv;
    if (std::abs(n.y) > 0.7071f) {
      uv = {p.x, p.z};
    } else {
      glm::vec3 along(-n.z, 0.0f, n.x);
      const float length = glm::length(along);
      along = length > 0.0f ? along / length : glm::vec3(1.0f, 0.0f, 0.0f);
      uv = {glm::dot(p, along), -p.y};  // down the wall: glTF's v grows downwards
    }
    scene.uvs[object.first_uv + i] = uv / tile;
  }
}

}  // namespace farfield::city
