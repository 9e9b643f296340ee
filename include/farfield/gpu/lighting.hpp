// The lighting every renderer and baker of farfield shares (paper 000, Sec. 5.3): two
// directional lights opposite each other in heading, 14 degrees above the horizon, so that
// every vertical face is lit by one of them, plus ambient. The GL shader and the CPU bakers
// (colour cubes) use these same numbers, so a baked colour matches a drawn one.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

namespace farfield::gpu {

inline constexpr float kLightElevationDeg = 14.0f;
inline constexpr float kLightHeadingDeg = 30.0f;  // View's convention: 0 = +X, 90 = +Z; other +180
inline constexpr float kLightWeight = 0.55f;      // diffuse weight of each light
inline constexpr float kAmbient = 0.35f;
inline constexpr float kSkyColor[4] = {0.70f, 0.78f, 0.85f, 1.0f};  // light blue-grey, linear RGB

// Unit directions towards the two lights: the first at `heading_deg` (View's convention),
// the other opposite, both `elevation_deg` above the horizon.
inline std::array<glm::vec3, 2> light_directions(float heading_deg = kLightHeadingDeg,
                                                 float elevation_deg = kLightElevationDeg) {
  std::array<glm::vec3, 2> lights;
  for (int i = 0; i < 2; ++i) {
    const float heading = glm::radians(heading_deg + 180.0f * float(i));
    const float elevation = glm::radians(elevation_deg);
    lights[i] = {std::cos(elevation) * std::cos(heading), std::sin(elevation),
                 std::cos(elevation) * std::sin(heading)};
  }
  return lights;
}

// The renderer's colour for a front face with unit normal `n` and surface colour `c` (its
// vertex shader lights each vertex so, gpu/shaders.cpp: on a flat face, every pixel).
inline glm::vec3 shade(const glm::vec3& n, const glm::vec3& c) {
  static const std::array<glm::vec3, 2> lights = light_directions();
  const float light = kAmbient + kLightWeight * (std::max(glm::dot(n, lights[0]), 0.0f) +
                                                 std::max(glm::dot(n, lights[1]), 0.0f));
  return glm::min(c * light, glm::vec3(1.0f));
}

}  // namespace farfield::gpu
