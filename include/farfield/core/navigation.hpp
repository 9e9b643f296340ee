// Walkthrough navigation (paper 000, Sec. 5.1): move forward and back, turn left and right,
// ascend and descend, look up and down. Pure state update, so the viewer's controls are
// tested without a window.
#pragma once

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

}  // namespace farfield
