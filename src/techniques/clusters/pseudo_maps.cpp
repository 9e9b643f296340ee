#include "farfield/techniques/clusters/pseudo_maps.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace farfield {

namespace {

// One halving along x (`along_x`) or y: each output texel the [1 2 1] weighted, alpha
// weighted, average of the input texels 2i - 1, 2i, 2i + 1 (clamped at the edges).
std::vector<uint32_t> halve(const std::vector<uint32_t>& in, int w, int h, bool along_x) {
  const int ow = along_x ? (w + 1) / 2 : w, oh = along_x ? h : (h + 1) / 2;
  std::vector<uint32_t> out(size_t(ow) * size_t(oh));
  for (int y = 0; y < oh; ++y)
    for (int x = 0; x < ow; ++x) {
      double rgb[3] = {0, 0, 0}, alpha = 0, weights = 0;
      for (int k = -1; k <= 1; ++k) {
        const int sx = along_x ? std::clamp(2 * x + k, 0, w - 1) : x;
        const int sy = along_x ? y : std::clamp(2 * y + k, 0, h - 1);
        const uint32_t t = in[size_t(sy) * size_t(w) + size_t(sx)];
        const double weight = k == 0 ? 2.0 : 1.0, a = double(t >> 24) / 255.0;
        for (int c = 0; c < 3; ++c) rgb[c] += weight * a * double((t >> (8 * c)) & 0xffu);
        alpha += weight * a;
        weights += weight;
      }
      uint32_t t = uint32_t(std::lround(255.0 * alpha / weights)) << 24;
      if (alpha > 0)
        for (int c = 0; c < 3; ++c)
          t |= uint32_t(std::clamp(std::lround(rgb[c] / alpha), 0l, 255l)) << (8 * c);
      out[size_t(y) * size_t(ow) + size_t(x)] = t;
    }
  return out;
}

}  // namespace

std::vector<uint32_t> shrink_image(std::vector<uint32_t> texels, int& w, int& h, int max_px) {
  while (w > max_px || h > max_px) {
    const bool along_x = w >= h;  // the longer side first, so that a texel stays square-ish
    texels = halve(texels, w, h, along_x);
    (along_x ? w : h) = (along_x ? w : h) / 2 + (along_x ? w : h) % 2;
  }
  return texels;
}

PseudoMaps pseudo_maps(const BoxSet& set, int max_px) {
  PseudoMaps maps;
  maps.max_px = std::clamp(max_px, 1, 255);
  for (const TexturedBox& box : set.boxes) {
    maps.first.push_back(uint32_t(maps.texels.size()));
    std::array<uint8_t, 12> sizes{};
    const std::vector<uint8_t>& page = set.pages[box.page];
    for (int side = 0; side < 6; ++side) {
      const BoxSide& s = box.sides[side];
      if (s.w == 0) continue;
      std::vector<uint32_t> image(size_t(s.w) * s.h);
      for (int y = 0; y < s.h; ++y)
        for (int x = 0; x < s.w; ++x) {
          const uint8_t* p = &page[(size_t(s.y + y) * size_t(set.page_px) + size_t(s.x + x)) * 4];
          image[size_t(y) * s.w + size_t(x)] =
              uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
        }
      int w = s.w, h = s.h;
      image = shrink_image(std::move(image), w, h, maps.max_px);
      sizes[2 * side] = uint8_t(w);
      sizes[2 * side + 1] = uint8_t(h);
      maps.texels.insert(maps.texels.end(), image.begin(), image.end());
    }
    maps.sizes.push_back(sizes);
  }
  return maps;
}

void append_pseudo_box(const BoxSet& set, const PseudoMaps& maps, uint32_t b, const glm::vec3& eye,
                       TexturedMesh& out) {
  const TexturedBox& box = set.boxes[b];
  const std::array<uint8_t, 12>& sizes = maps.sizes[b];
  uint32_t at = maps.first[b];
  for (int side = 0; side < 6; ++side) {
    const int w = sizes[2 * side], h = sizes[2 * side + 1];
    if (w == 0) continue;
    const uint32_t first = at;
    at += uint32_t(w * h);
    const auto [c, r, u] = box_side_frame(box.bounds, side);
    if (glm::dot(glm::cross(r, u), eye - c) <= 0.0f) continue;  // seen from behind
    // Texel (x, y) spans [x, x + 1] / w of the side's width from its left, [y, y + 1] / h
    // of its height from its top.
    const glm::vec3 top_left = c - r + u, step_x = 2.0f * r / float(w),
                    step_y = -2.0f * u / float(h);
    const glm::vec2 uv(0.5f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const uint32_t t = maps.texels[first + uint32_t(y * w + x)];
        if ((t >> 24) < 128) continue;  // covered less than half
        const uint32_t colour = t | 0xff000000u;
        const glm::vec3 centre = top_left + (float(x) + 0.5f) * step_x + (float(y) + 0.5f) * step_y;
        append_quad(out, centre, 0.5f * step_x, -0.5f * step_y, uv, uv, colour);
      }
  }
}

}  // namespace farfield
