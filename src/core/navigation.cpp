#include "farfield/core/navigation.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/core/view_sphere.hpp"

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

Orbit Orbit::through(const CameraPose& pose, const glm::vec3& centre, float min_radius) {
  Orbit o;
  o.centre = centre;
  const glm::vec3 d = pose.position - centre;
  const float length = glm::length(d);
  o.radius = std::max(length, min_radius);
  if (length > 0.0f) {
    o.longitude_deg = glm::degrees(std::atan2(d.z, d.x));
    if (o.longitude_deg < 0.0f) o.longitude_deg += 360.0f;
    o.latitude_deg =
        std::clamp(glm::degrees(std::asin(std::clamp(d.y / length, -1.0f, 1.0f))), -89.0f, 89.0f);
  }
  return o;
}

CameraPose Orbit::pose() const { return pose_on_sphere(centre, radius, longitude_deg, latitude_deg); }

Orbit navigate(const Orbit& orbit, const NavigationInput& in, const NavigationSpeeds& speeds,
               float seconds) {
  Orbit next = orbit;
  const float boost = in.fast ? 5.0f : 1.0f;
  // Turning right moves the eye the way the walk turns it (increasing longitude), so the
  // model seems to turn left under it.
  next.longitude_deg =
      std::fmod(orbit.longitude_deg + in.turn * speeds.turn_deg_per_s * boost * seconds, 360.0f);
  if (next.longitude_deg < 0.0f) next.longitude_deg += 360.0f;
  next.latitude_deg = std::clamp(
      orbit.latitude_deg + in.look * speeds.look_deg_per_s * boost * seconds, -89.0f, 89.0f);
  // Forward halves the radius in two seconds (at x1), back doubles it: the same feel at any size.
  next.radius = orbit.radius * std::exp2(-0.5f * in.forward * boost * seconds);
  return next;
}

}  // namespace farfield
