#include "farfield/techniques/clusters/average_boxes.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <string>

#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

namespace {

constexpr const char* kAverages = "clusters/box_averages";

int8_t offset(double centre, double half) {
  return int8_t(std::lround(std::clamp(centre / half, -1.0, 1.0) * 127.0));
}

}  // namespace

// Paper 001, Sec. 5.1: "the average of the rgb colors of all non-black pixels and the average
// area [...] the number of all non-black pixels"; here texels weigh by their alpha, so that a
// silhouette's half-covered texels count half.
AverageBox average_box(const TexturedBox& box, std::span<const uint8_t> page, int page_px) {
  AverageBox out;
  for (int side = 0; side < 6; ++side) {
    const BoxSide& s = box.sides[side];
    if (s.w == 0) continue;
    double weight = 0, r = 0, g = 0, b = 0, x = 0, y = 0;
    for (int ty = 0; ty < s.h; ++ty)
      for (int tx = 0; tx < s.w; ++tx) {
        const uint8_t* t = &page[(size_t(s.y + ty) * size_t(page_px) + size_t(s.x + tx)) * 4];
        const double a = t[3];
        weight += a;
        r += a * t[0];
        g += a * t[1];
        b += a * t[2];
        x += a * (tx + 0.5);
        y += a * (ty + 0.5);
      }
    if (weight <= 0) continue;
    AverageSide& a = out.sides[side];
    a.r = uint8_t(std::lround(r / weight));
    a.g = uint8_t(std::lround(g / weight));
    a.b = uint8_t(std::lround(b / weight));
    a.coverage = uint8_t(std::clamp(std::lround(weight / (double(s.w) * s.h)), long(1), long(255)));
    // Image x runs along the side's right, image y down its up direction.
    a.u = offset(x / weight - 0.5 * s.w, 0.5 * s.w);
    a.v = offset(0.5 * s.h - y / weight, 0.5 * s.h);
  }
  return out;
}

std::vector<AverageBox> average_boxes(const BoxSet& set) {
  std::vector<AverageBox> out;
  out.reserve(set.boxes.size());
  for (const TexturedBox& box : set.boxes)
    out.push_back(average_box(box, set.pages[box.page], set.page_px));
  return out;
}

void append_average_box(const TexturedBox& box, const AverageBox& average, const glm::vec3& eye,
                        TexturedMesh& out) {
  for (int side = 0; side < 6; ++side) {
    const AverageSide& a = average.sides[side];
    if (a.coverage == 0) continue;
    const auto [c, r, u] = box_side_frame(box.bounds, side);
    if (glm::dot(glm::cross(r, u), eye - c) <= 0.0f) continue;  // seen from behind
    // A rectangle of the side's proportions and the covered area, about the covered part's
    // centre, kept within the side.
    const float scale = std::sqrt(float(a.coverage) / 255.0f);
    const float du = std::clamp(float(a.u) / 127.0f, scale - 1.0f, 1.0f - scale);
    const float dv = std::clamp(float(a.v) / 127.0f, scale - 1.0f, 1.0f - scale);
    const glm::vec3 centre = c + du * r + dv * u;
    const glm::vec3 rs = scale * r, us = scale * u;
    const uint32_t colour = uint32_t(a.r) | uint32_t(a.g) << 8 | uint32_t(a.b) << 16 | 0xff000000u;
    append_quad(out, centre, rs, us, glm::vec2(0.5f), glm::vec2(0.5f), colour);
  }
}

Result<void> save_average_boxes(std::span<const AverageBox> averages, Store& store) {
  return store.put(kAverages, std::as_bytes(averages));
}

Result<std::vector<AverageBox>> load_average_boxes(const Store& store, const BoxSet& set) {
  auto present = store.contains(kAverages);
  if (!present) return present.error();
  if (!*present) return std::vector<AverageBox>{};
  auto averages = read_array<AverageBox>(store, kAverages);
  if (!averages) return averages.error();
  if (averages->size() != set.boxes.size())
    return make_error(store.path(), ": blob '", kAverages, "' is not one average box per box (",
                      std::to_string(averages->size()), " for ", std::to_string(set.boxes.size()),
                      ")");
  return averages;
}

}  // namespace farfield
