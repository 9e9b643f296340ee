#include "farfield/core/navigation.hpp"

#include <algorithm>
#include <cmath>

#include <glm/trigonometric.hpp>

namespace farfield {

CameraPose navigate(const CameraPose& pose, const NavigationInput& in,
                    const NavigationSpeeds& speeds, float seconds) {
  CameraPose next = pose;
  const float boost = in.fast ? 5.0f : 1.0f;
  // Turning right turns clockwise seen from above: with +Y up and yaw 0 along +X, that is
  // towards +Z, which is increasing yaw.
  next.yaw_deg = std::fmod(pose.yaw_deg + in.turn * speeds.turn_deg_per_s * seconds, 360.0f);
  if (next.yaw_deg < 0) next.yaw_deg += 360.0f;
  next.pitch_deg =
      std::clamp(pose.pitch_deg + in.look * speeds.look_deg_per_s * seconds, -89.0f, 89.0f);
  const float yaw = glm::radians(next.yaw_deg);
  const glm::vec3 heading(std::cos(yaw), 0.0f, std::sin(yaw));
  next.position += heading * (in.forward * speeds.move_m_per_s * boost * seconds);
  next.position.y += in.climb * speeds.climb_m_per_s * boost * seconds;
  return next;
}

}  // namespace farfield
