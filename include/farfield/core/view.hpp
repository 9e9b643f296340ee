// Camera pose and view: where the eye is, where it looks, and the image it makes.
//
// Conventions: metres, +Y up. Heading `yaw_deg` turns in the XZ plane: 0 looks along +X,
// 90 along +Z. `pitch_deg` is up from the horizon (positive looks up), within (-90, 90).
// Projection: symmetric perspective from the horizontal field of view and the aspect ratio,
// depth mapped to [0, 1] reversed (near plane at 1, infinity at 0) for float depth buffers.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "farfield/core/bounds.hpp"

namespace farfield {

struct CameraPose {
  glm::vec3 position{0.0f};
  float yaw_deg = 0.0f;
  float pitch_deg = 0.0f;

  glm::vec3 forward() const;  // unit
  glm::vec3 right() const;    // unit, horizontal
  glm::vec3 up() const;       // unit
};

struct View {
  CameraPose pose;
  int width = 1024;        // pixels
  int height = 768;        // pixels
  float hfov_deg = 90.0f;  // horizontal field of view
  float near_m = 0.1f;     // near plane; there is no far plane (near_plane_for: per scene)

  float aspect() const { return float(width) / float(height); }
  float vfov_deg() const;
  glm::mat4 view_matrix() const;
  glm::mat4 projection_matrix() const;  // reversed-Z, infinite far plane
  glm::mat4 view_projection() const { return projection_matrix() * view_matrix(); }
};

// The limits every command takes for an image and its field of view (bench and view alike).
inline constexpr int kMinImageSide = 16, kMaxImageSide = 16384;
inline constexpr float kMinHfovDeg = 1.0f, kMaxHfovDeg = 179.0f;

// The near plane for a scene of these bounds: 0.1 m for anything 10 m or more across
// (cities, buildings), 1/100 of the size for smaller models, which 0.1 m would cut.
float near_plane_for(const Bounds3& scene_bounds);

}  // namespace farfield
