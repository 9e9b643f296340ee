// Walking through a scene (paper 000, Sec. 5.1: the walkthrough keeps the eye at a height
// above the ground and out of the buildings): a proposed move is stopped short of a surface
// ahead, and the eye is set at eye height above the ground below it. Where there is no ground
// below (above the roofs, outside the scene), the move is kept as it is: flying.
#pragma once

#include "farfield/core/view.hpp"
#include "farfield/spatial/ray_caster.hpp"

namespace farfield {

struct WalkOptions {
  float eye_height = 1.7f;   // metres above the ground
  float step_height = 0.5f;  // ground this much above the feet is stepped onto (curbs, stairs)
  float clearance = 0.3f;    // a move stops this far from a surface ahead
};

// Options for a scene's size: 1.7 m eyes in anything 17 m or larger, a tenth of the size
// below that, the rest in proportion.
WalkOptions walk_options_for(const Bounds3& scene_bounds);

// The pose after walking from `from` towards `to` (heading and pitch of `to`).
CameraPose walk(const RayCaster& caster, const CameraPose& from, const CameraPose& to,
                const WalkOptions& options);

}  // namespace farfield
