// Axis-aligned bounding box in scene units (metres). An empty box has min > max.
#pragma once

#include <glm/vec3.hpp>
#include <glm/common.hpp>
#include <cmath>
#include <limits>

namespace farfield {

struct Bounds3 {
  glm::vec3 min{std::numeric_limits<float>::max()};
  glm::vec3 max{std::numeric_limits<float>::lowest()};

  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void expand(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void expand(const Bounds3& b) {
    if (b.empty()) return;
    min = glm::min(min, b.min);
    max = glm::max(max, b.max);
  }
  glm::vec3 size() const { return empty() ? glm::vec3(0.0f) : max - min; }
  glm::vec3 center() const { return (min + max) * 0.5f; }
  bool contains(const glm::vec3& p) const {
    return p.x >= min.x && p.y >= min.y && p.z >= min.z && p.x <= max.x && p.y <= max.y &&
           p.z <= max.z;
  }
};

// Whether two closed boxes meet (share at least a point); never for an empty box.
inline bool meet(const Bounds3& a, const Bounds3& b) {
  return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
         a.min.z <= b.max.z && b.min.z <= a.max.z;
}

// The distance from a point to the nearest point of a box (0 inside).
inline float distance_to(const Bounds3& box, const glm::vec3& point) {
  const glm::vec3 d = glm::max(glm::max(box.min - point, point - box.max), glm::vec3(0.0f));
  return std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
}

}  // namespace farfield
