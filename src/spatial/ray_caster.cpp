#include "farfield/spatial/ray_caster.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

namespace farfield {

namespace {

// The entry distance of the ray into the box (slab test), or none within [0, max_distance].
std::optional<float> enters(const Bounds3& b, const glm::vec3& origin, const glm::vec3& inverse,
                            float max_distance) {
  float near = 0.0f, far = max_distance;
  for (int a = 0; a < 3; ++a) {
    float t0 = (b.min[a] - origin[a]) * inverse[a], t1 = (b.max[a] - origin[a]) * inverse[a];
    if (std::isnan(t0) || std::isnan(t1)) {  // parallel to the slab and on its plane
      if (origin[a] < b.min[a] || origin[a] > b.max[a]) return std::nullopt;
      continue;
    }
    if (t0 > t1) std::swap(t0, t1);
    near = std::max(near, t0);
    far = std::min(far, t1);
    if (near > far) return std::nullopt;
  }
  return near;
}

// Moller-Trumbore, both faces.
std::optional<float> hits_triangle(const glm::vec3& origin, const glm::vec3& direction,
                                   const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 e1 = b - a, e2 = c - a, p = glm::cross(direction, e2);
  const float det = glm::dot(e1, p);
  if (std::abs(det) < 1e-12f) return std::nullopt;
  const float inv = 1.0f / det;
  const glm::vec3 s = origin - a;
  const float u = glm::dot(s, p) * inv;
  if (u < 0.0f || u > 1.0f) return std::nullopt;
  const glm::vec3 q = glm::cross(s, e1);
  const float v = glm::dot(direction, q) * inv;
  if (v < 0.0f || u + v > 1.0f) return std::nullopt;
  const float t = glm::dot(e2, q) * inv;
  if (t < 0.0f) return std::nullopt;
  return t;
}

}  // namespace

RayCaster::RayCaster(const Scene& scene) : scene_(scene) {
  std::vector<Bounds3> bounds(scene.objects.size());
  for (size_t i = 0; i < bounds.size(); ++i) bounds[i] = scene.objects[i].bounds;
  tree_ = build_octree(bounds, {});
  tested_in_.assign(scene.objects.size(), 0);
}

std::optional<RayHit> RayCaster::cast(const glm::vec3& origin, const glm::vec3& direction,
                                      float max_distance, Faces faces) const {
  if (tree_.nodes.empty()) return std::nullopt;
  const glm::vec3 inverse = 1.0f / direction;
  std::optional<RayHit> best;
  float limit = max_distance;
  std::vector<uint32_t> stack{0};
  if (++cast_ == 0) {  // wrapped: every mark is stale
    std::fill(tested_in_.begin(), tested_in_.end(), 0);
    cast_ = 1;
  }
  while (!stack.empty()) {
    const OctreeNode& node = tree_.nodes[stack.back()];
    stack.pop_back();
    if (!enters(node.bounds, origin, inverse, limit)) continue;
    if (!node.leaf()) {
      for (uint32_t c = 0; c < node.child_count; ++c) stack.push_back(node.first_child + c);
      continue;
    }
    for (uint32_t i = node.items_begin; i < node.items_end; ++i) {
      const uint32_t o = tree_.items[i];
      if (tested_in_[o] == cast_) continue;
      tested_in_[o] = cast_;
      const Object& object = scene_.objects[o];
      if (!enters(object.bounds, origin, inverse, limit)) continue;
      const Material& material = scene_.materials[object.material];
      const bool culled = faces == Faces::as_drawn && !material.double_sided &&
                          !material.transparent() && material.alpha_mode != AlphaMode::mask;
      for (uint32_t k = object.first_index; k < object.first_index + object.index_count; k += 3) {
        const glm::vec3& a = scene_.vertices[scene_.indices[k]].position;
        const glm::vec3& b = scene_.vertices[scene_.indices[k + 1]].position;
        const glm::vec3& c = scene_.vertices[scene_.indices[k + 2]].position;
        if (culled && glm::dot(glm::cross(b - a, c - a), direction) >= 0.0f) continue;
        const auto t = hits_triangle(origin, direction, a, b, c);
        if (t && *t <= limit) {
          limit = *t;
          best = RayHit{*t, o, k / 3};
        }
      }
    }
  }
  return best;
}

}  // namespace farfield
