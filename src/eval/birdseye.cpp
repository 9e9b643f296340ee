#include "farfield/eval/birdseye.hpp"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace farfield {

namespace {
constexpr float kPitchDeg = -55.0f;
constexpr uint32_t kRed = 0xff0000ffu;  // RGBA8, R in the low byte
}  // namespace

View birdseye_view(const View& eye, float height) {
  View v = eye;
  const glm::vec3 heading{std::cos(glm::radians(eye.pose.yaw_deg)), 0.0f,
                          std::sin(glm::radians(eye.pose.yaw_deg))};
  // Back far enough that the eye sits a little below the picture's centre.
  const float back = height / std::tan(glm::radians(-kPitchDeg)) * 0.8f;
  v.pose.position = eye.pose.position + glm::vec3(0.0f, height, 0.0f) - heading * back;
  v.pose.pitch_deg = kPitchDeg;
  v.near_m = 1.0f;
  return v;
}

void add_frustum_lines(const View& eye, float length, DrawList& list) {
  const glm::vec3 o = eye.pose.position, f = eye.pose.forward(), r = eye.pose.right(),
                  u = eye.pose.up();
  const float x = std::tan(glm::radians(eye.hfov_deg) * 0.5f);
  const float y = std::tan(glm::radians(eye.vfov_deg()) * 0.5f);
  glm::vec3 corners[4];
  const float sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
  for (int i = 0; i < 4; ++i) {
    const glm::vec3 d = glm::normalize(f + r * (sx[i] * x) + u * (sy[i] * y));
    corners[i] = o + d * length;
    list.lines.push_back({o, corners[i], kRed});
  }
  for (int i = 0; i < 4; ++i) list.lines.push_back({corners[i], corners[(i + 1) % 4], kRed});
}

}  // namespace farfield
