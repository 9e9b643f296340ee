#include "farfield/spatial/walking.hpp"

#include <algorithm>

#include <glm/geometric.hpp>

namespace farfield {

WalkOptions walk_options_for(const Bounds3& b) {
  const glm::vec3 size = b.size();
  const float scale = std::clamp(0.1f * std::max({size.x, size.y, size.z}) / 1.7f, 1e-3f, 1.0f);
  WalkOptions o;
  o.eye_height *= scale;
  o.step_height *= scale;
  o.clearance *= scale;
  return o;
}

CameraPose walk(const RayCaster& caster, const CameraPose& from, const CameraPose& to,
                const WalkOptions& o) {
  CameraPose out = to;
  // Collision: along the move at knee height (above steps), stop short of what is ahead.
  const glm::vec3 knee(0.0f, o.step_height - o.eye_height, 0.0f);
  glm::vec3 move = to.position - from.position;
  move.y = 0.0f;
  const float length = glm::length(move);
  glm::vec3 at = from.position;
  if (length > 0.0f) {
    const glm::vec3 direction = move / length;
    const auto wall = caster.cast(from.position + knee, direction, length + o.clearance);
    const float allowed = wall ? std::max(0.0f, wall->distance - o.clearance) : length;
    at += direction * std::min(length, allowed);
  }
  at.y = to.position.y;
  // Ground following: the highest surface below the knee, within reach of the fall.
  const auto ground = caster.cast(at + knee, glm::vec3(0.0f, -1.0f, 0.0f), 4.0f * o.eye_height);
  if (ground) at.y = at.y + knee.y - ground->distance + o.eye_height;
  out.position = at;
  return out;
}

}  // namespace farfield
