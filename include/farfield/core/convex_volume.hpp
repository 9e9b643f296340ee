// A convex volume bounded by planes (inside where dot(n, p) + d >= 0): the view frustum
// narrowed by the portals it looks through (spatial/portal_walk.hpp). Fixed capacity, so
// that narrowing allocates nothing; a plane beyond it is dropped, which only enlarges the
// volume (a conservative test stays conservative).
#pragma once

#include <array>
#include <cstdint>
#include <glm/vec4.hpp>
#include <span>

#include "farfield/core/bounds.hpp"
#include "farfield/core/frustum.hpp"
#include "farfield/core/view.hpp"

namespace farfield {

class ConvexVolume {
 public:
  static constexpr uint32_t kMaxPlanes = 40;

  // The view's frustum: its left, right, bottom, top and near planes.
  static ConvexVolume of_view(const View& view);

  void add(const glm::vec4& plane) {
    if (count_ < kMaxPlanes) planes_[count_++] = plane;
  }
  std::span<const glm::vec4> planes() const { return {planes_.data(), count_}; }
  // none: the box lies wholly outside one plane; full: wholly inside all (conservative).
  Visibility classify(const Bounds3& box) const;

 private:
  std::array<glm::vec4, kMaxPlanes> planes_;
  uint32_t count_ = 0;
};

}  // namespace farfield
