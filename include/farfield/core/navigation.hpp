// Walkthrough navigation (paper 000, Sec. 5.1): move forward and back, turn left and right,
// ascend and descend, look up and down. Pure state update, so the viewer's controls are
// tested without a window.
#pragma once

#include <glm/vec3.hpp>

#include "farfield/core/view.hpp"

namespace farfield {

struct NavigationInput {
  float forward = 0;  // -1 back .. +1 forward
  float turn = 0;     // -1 left .. +1 right
  float climb = 0;    // -1 descend .. +1 ascend
  float look = 0;     // -1 down .. +1 up
  bool fast = false;  // x5 speed
};

struct NavigationSpeeds {
  float move_m_per_s = 15.0f;
  float turn_deg_per_s = 60.0f;
  float climb_m_per_s = 8.0f;
  float look_deg_per_s = 45.0f;
};

// Moves along the horizontal heading (walking does not change height when looking down),
// keeps pitch within +-89 degrees and yaw within [0, 360).
CameraPose navigate(const CameraPose& pose, const NavigationInput& input,
                    const NavigationSpeeds& speeds, float seconds);

// Orbit navigation (paper 003: a model seen from outside): the eye on a sphere about a centre,
// looking at it, placed by pose_on_sphere as the viewpoints of ibr and hybrid and the frames of
// `path --kind orbit` are. Turning moves along the longitude, looking along the latitude
// (within +-89 degrees), forward and back change the radius (by a factor per second).
struct Orbit {
  glm::vec3 centre{0.0f};
  float radius = 1.0f;
  float longitude_deg = 0.0f;  // [0, 360), from +X towards +Z (View's yaw)
  float latitude_deg = 0.0f;   // up from the horizontal plane

  // The orbit through the pose's eye about `centre` (radius at least `min_radius`).
  static Orbit through(const CameraPose& pose, const glm::vec3& centre, float min_radius);
  CameraPose pose() const;
};

Orbit navigate(const Orbit& orbit, const NavigationInput& input, const NavigationSpeeds& speeds,
               float seconds);

}  // namespace farfield
