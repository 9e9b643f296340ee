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

// At `longitude_deg`, `latitude_deg` on the sphere about `centre`, looking at the centre.
// path --kind orbit and the viewpoints both place their cameras with it, so that an orbit
// frame at a viewpoint's angles is that viewpoint, float for float (hybrid's frames there are
// then brute's, pixel for pixel).
CameraPose pose_on_sphere(const glm::vec3& centre, float radius, float longitude_deg,
                          float latitude_deg);

struct ViewSphere {
  glm::vec3 centre{0.0f};
  float radius = 1.0f;
  int longitudes = 72;  // 360 / d_theta
  int latitudes = 36;   // 180 / d_phi

  // Steps of d_theta_deg and d_phi_deg, rounded so that they divide 360 and 180.
  static ViewSphere with_steps(const glm::vec3& centre, float radius, float d_theta_deg,
                               float d_phi_deg);
  uint32_t count() const { return uint32_t(longitudes) * uint32_t(latitudes); }
  // Whether what the viewpoints saw stands for what the eye sees: the eye between half and
  // twice the radius from the centre (ibr and hybrid draw the scene's geometry elsewhere).
  bool stands_for(const glm::vec3& eye) const;
  float d_theta_deg() const { return 360.0f / float(longitudes); }
  float d_phi_deg() const { return 180.0f / float(latitudes); }
  // Viewpoint `id` = row * longitudes + column.
  float longitude_deg(uint32_t id) const;
  float latitude_deg(uint32_t id) const;
  glm::vec3 position(uint32_t id) const;
  CameraPose pose(uint32_t id) const;  // at position(id), looking at the centre

  // The viewpoint whose direction from the centre is nearest the eye's (by longitude and
  // latitude, as the paper's walk steps between them). The north pole's viewpoints stand in
  // one place, turned by their longitude: there the one turned as the eye's yaw is.
  uint32_t nearest(const CameraPose& eye) const;
  // The four viewpoints around the eye's direction with bilinear weights in longitude and
  // latitude (summing to 1; the eye on a viewpoint gives it weight 1). Above the last row
  // or below the first, the row's two; in the pole's row, the two nearest the eye's yaw.
  struct Weighted {
    uint32_t id;
    float weight;
  };
  std::array<Weighted, 4> around(const CameraPose& eye) const;
};

}  // namespace farfield
