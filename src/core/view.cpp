#include "farfield/core/view.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

namespace farfield {

glm::vec3 CameraPose::forward() const {
  const float yaw = glm::radians(yaw_deg), pitch = glm::radians(pitch_deg);
  return {std::cos(pitch) * std::cos(yaw), std::sin(pitch), std::cos(pitch) * std::sin(yaw)};
}

glm::vec3 CameraPose::right() const {
  const float yaw = glm::radians(yaw_deg);
  return {-std::sin(yaw), 0.0f, std::cos(yaw)};
}

glm::vec3 CameraPose::up() const {
  return glm::cross(right(), forward());
}

float View::vfov_deg() const {
  const float half = std::atan(std::tan(glm::radians(hfov_deg) * 0.5f) / aspect());
  return glm::degrees(2.0f * half);
}

glm::mat4 View::view_matrix() const {
  return glm::lookAt(pose.position, pose.position + pose.forward(), pose.up());
}

glm::mat4 View::projection_matrix() const {
  // Reversed-Z infinite perspective: clip z = near, clip w = -z_eye, so depth = near / -z_eye.
  const float sx = 1.0f / std::tan(glm::radians(hfov_deg) * 0.5f);
  const float sy = sx * aspect();
  glm::mat4 p(0.0f);
  p[0][0] = sx;
  p[1][1] = sy;
  p[2][3] = -1.0f;
  p[3][2] = near_m;
  return p;
}

float near_plane_for(const Bounds3& b) {
  const glm::vec3 size = b.size();
  const float extent = std::max({size.x, size.y, size.z});
  return std::clamp(0.01f * extent, 1e-5f, 0.1f);
}

}  // namespace farfield
