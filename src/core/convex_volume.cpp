#include "farfield/core/convex_volume.hpp"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace farfield {

ConvexVolume ConvexVolume::of_view(const View& view) {
  // Rows of the view-projection matrix (Gribb and Hartmann), as Frustum: reversed depth, no
  // far plane, near is w - z >= 0.
  const glm::mat4 m = glm::transpose(view.view_projection());
  ConvexVolume v;
  for (const glm::vec4& p : {m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[3] - m[2]})
    v.add(p / glm::length(glm::vec3(p)));
  return v;
}

Visibility ConvexVolume::classify(const Bounds3& box) const {
  Visibility result = Visibility::full;
  for (uint32_t i = 0; i < count_; ++i) {
    const glm::vec4& p = planes_[i];
    const glm::vec3 far(p.x >= 0 ? box.max.x : box.min.x, p.y >= 0 ? box.max.y : box.min.y,
                        p.z >= 0 ? box.max.z : box.min.z);
    const glm::vec3 near(p.x >= 0 ? box.min.x : box.max.x, p.y >= 0 ? box.min.y : box.max.y,
                         p.z >= 0 ? box.min.z : box.max.z);
    if (glm::dot(glm::vec3(p), far) + p.w < 0.0f) return Visibility::none;
    if (glm::dot(glm::vec3(p), near) + p.w < 0.0f) result = Visibility::partial;
  }
  return result;
}

}  // namespace farfield
