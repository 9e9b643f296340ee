#include "farfield/techniques/clusters/billboards.hpp"

#include <cmath>
#include <glm/geometric.hpp>

namespace farfield {

namespace {

constexpr int kUpright[4] = {0, 1, 4, 5};  // +x, -x, +z, -z (TexturedBox::sides)
const glm::vec3 kUprightNormal[4] = {{1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}};

}  // namespace

int billboard_side(const TexturedBox& box, const glm::vec3& eye) {
  const glm::vec3 to = eye - box.bounds.center();
  const float across = std::sqrt(to.x * to.x + to.z * to.z);
  const int flat = to.y >= 0.0f ? 2 : 3;  // top, bottom
  if (std::abs(to.y) > across && box.sides[flat].w > 0) return flat;
  int best = -1;
  float best_dot = -INFINITY;
  for (int k = 0; k < 4; ++k) {
    const float d = glm::dot(kUprightNormal[k], to);
    if (box.sides[kUpright[k]].w > 0 && d > best_dot) {
      best = kUpright[k];
      best_dot = d;
    }
  }
  if (best < 0 && box.sides[flat].w > 0) return flat;
  if (best < 0 && box.sides[5 - flat].w > 0) return 5 - flat;  // 2 <-> 3
  return best;
}

void append_billboard(const TexturedBox& box, int texture_px, const glm::vec3& eye,
                      TexturedMesh& out) {
  const int side = billboard_side(box, eye);
  if (side < 0) return;
  const BoxSideFrame frame = box_side_frame(box.bounds, side);
  const glm::vec3 centre = box.bounds.center();
  glm::vec3 right = frame.right, up = frame.up;
  if (side != 2 && side != 3) {
    // Turned about the vertical to face the eye; right = -normal x up, as a side's frame.
    glm::vec3 normal(eye.x - centre.x, 0.0f, eye.z - centre.z);
    const float length = glm::length(normal);
    if (length > 1e-6f) {
      normal /= length;
      right = glm::cross(-normal, glm::vec3(0, 1, 0)) * glm::length(frame.right);
      up = glm::vec3(0, 1, 0) * glm::length(frame.up);
    }
  }
  const BoxSide& s = box.sides[side];
  const float texel = 1.0f / float(texture_px);
  const float u0 = float(s.x) * texel, v0 = float(s.y) * texel;
  const float u1 = float(s.x + s.w) * texel, v1 = float(s.y + s.h) * texel;
  append_quad(out, centre, right, up, {u0, v0}, {u1, v1});
}

}  // namespace farfield
