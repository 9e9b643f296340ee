// The view frustum as planes, and the visibility of a box against it: none, partial or full
// (paper 004, Sec. 2.1). Two tests:
//   classify():         the five planes of the (infinite) frustum against the box's nearest
//                       and farthest corners. Conservative: a box it calls `none` is outside,
//                       one it calls `full` is inside.
//   classify_paper004(): the paper's test: project the eight corners; all on screen is full,
//                       some is partial; none sends four rays through the screen corners at
//                       the box. Kept to compare with; it misses a box that crosses the view
//                       with every corner off screen and no screen corner on it (a long beam
//                       across the middle of the view), so it is not conservative.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "farfield/core/bounds.hpp"
#include "farfield/core/view.hpp"

namespace farfield {

enum class Visibility { none, partial, full };

class Frustum {
 public:
  explicit Frustum(const View& view);

  Visibility classify(const Bounds3& box) const;
  Visibility classify_paper004(const Bounds3& box) const;

 private:
  glm::vec4 planes_[5];  // left, right, bottom, top, near; inside where dot(p, (x,1)) >= 0
  glm::mat4 view_projection_;
  glm::vec3 eye_;
  glm::vec3 corner_rays_[4];  // through the screen corners, world space
};

}  // namespace farfield
