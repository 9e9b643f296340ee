// Viewpoints on a sphere around a model (paper 003, Sec. 2.1): the camera stands on the sphere
// every d_theta degrees of longitude and d_phi of latitude, looking at its centre; 360 / d_theta
// x 180 / d_phi viewpoints (2,592 at the paper's 5 degrees). Longitude is measured from +X
// towards +Z (View's yaw), latitude up from the horizontal plane; the rows of latitude run from
// -90 + d_phi to +90 (the north pole is a row of its own, the south pole none: a model is seen
// from above more than from below), so that `path --kind orbit`, at 25 degrees above the
// horizon, passes through a row at every step of 5.
#pragma once

#include <array>
#include <cstdint>

#include <glm/vec3.hpp>

#include "farfield/core/view.hpp"

namespace farfield {

struct ViewSphere {
  glm::vec3 centre{0.0f};
  float radius = 1.0f;
  int longitudes = 72;  // 360 / d_theta
  int latitudes = 36;   // 180 / d_phi

  // Steps of d_theta_deg and d_phi_deg, rounded so that they divide 360 and 180.
  static ViewSphere with_steps(const glm::vec3& centre, float radius, float d_theta_deg,
                               float d_phi_deg);
  uint32_t count() const { return uint32_t(longitudes) * uint32_t(latitudes); }
  float d_theta_deg() const { return 360.0f / float(longitudes); }
  float d_phi_deg() const { return 180.0f / float(latitudes); }
  // Viewpoint `id` = row * longitudes + column.
  float longitude_deg(uint32_t id) const;
  float latitude_deg(uint32_t id) const;
  glm::vec3 position(uint32_t id) const;
  CameraPose pose(uint32_t id) const;  // at position(id), looking at the centre

  // The viewpoint whose direction from the centre is nearest the eye's (by longitude and
  // latitude, as the paper's walk steps between them).
  uint32_t nearest(const glm::vec3& eye) const;
  // The four viewpoints around the eye's direction with bilinear weights in longitude and
  // latitude (summing to 1; the eye on a viewpoint gives it weight 1). Above the last row
  // or below the first, the row's two.
  struct Weighted {
    uint32_t id;
    float weight;
  };
  std::array<Weighted, 4> around(const glm::vec3& eye) const;
};

}  // namespace farfield
