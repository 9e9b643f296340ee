#include "farfield/core/frustum.hpp"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace farfield {

Frustum::Frustum(const View& view)
    : view_projection_(view.view_projection()), eye_(view.pose.position) {
  // Planes from the rows of the view-projection matrix (Gribb and Hartmann). The projection
  // maps depth to [0, 1] reversed with no far plane, so near is w - z >= 0.
  const glm::mat4 m = glm::transpose(view_projection_);  // m[i] is row i
  planes_[0] = m[3] + m[0];
  planes_[1] = m[3] - m[0];
  planes_[2] = m[3] + m[1];
  planes_[3] = m[3] - m[1];
  planes_[4] = m[3] - m[2];
  for (glm::vec4& p : planes_) p /= glm::length(glm::vec3(p));

  const glm::mat4 inverse = glm::inverse(view_projection_);
  const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int i = 0; i < 4; ++i) {
    glm::vec4 p = inverse * glm::vec4(corners[i][0], corners[i][1], 0.5f, 1.0f);
    corner_rays_[i] = glm::normalize(glm::vec3(p) / p.w - eye_);
  }
}

Visibility Frustum::classify(const Bounds3& box) const {
  Visibility result = Visibility::full;
  for (const glm::vec4& p : planes_) {
    const glm::vec3 n(p);
    // The corner farthest along the plane normal, and the nearest.
    const glm::vec3 far(n.x >= 0 ? box.max.x : box.min.x, n.y >= 0 ? box.max.y : box.min.y,
                        n.z >= 0 ? box.max.z : box.min.z);
    const glm::vec3 near(n.x >= 0 ? box.min.x : box.max.x, n.y >= 0 ? box.min.y : box.max.y,
                         n.z >= 0 ? box.min.z : box.max.z);
    if (glm::dot(n, far) + p.w < 0.0f) return Visibility::none;
    if (glm::dot(n, near) + p.w < 0.0f) result = Visibility::partial;
  }
  return result;
}

namespace {

// Slab test of the ray eye + t * dir, t > 0, against the box.
bool ray_hits_box(const glm::vec3& eye, const glm::vec3& dir, const Bounds3& box) {
  float t0 = 0.0f, t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(dir[a]) < 1e-12f) {
      if (eye[a] < box.min[a] || eye[a] > box.max[a]) return false;
      continue;
    }
    float near = (box.min[a] - eye[a]) / dir[a], far = (box.max[a] - eye[a]) / dir[a];
    if (near > far) std::swap(near, far);
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace

Visibility Frustum::classify_paper004(const Bounds3& box) const {
  // Step 1: how many of the eight corners are in front of the eye and on screen.
  int on_screen = 0;
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 corner(c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y,
                           c & 4 ? box.max.z : box.min.z);
    const glm::vec4 clip = view_projection_ * glm::vec4(corner, 1.0f);
    if (clip.w <= 0.0f) continue;  // behind the eye
    const float x = clip.x / clip.w, y = clip.y / clip.w;
    on_screen += (x >= -1.0f && x <= 1.0f && y >= -1.0f && y <= 1.0f);
  }
  if (on_screen == 8) return Visibility::full;
  if (on_screen > 0) return Visibility::partial;
  // Step 2: rays from the eye through the four screen corners.
  for (const glm::vec3& ray : corner_rays_) {
    if (ray_hits_box(eye_, ray, box)) return Visibility::partial;
  }
  return Visibility::none;
}

}  // namespace farfield
