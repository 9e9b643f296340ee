#include "farfield/core/view_sphere.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace farfield {

namespace {

// Longitude in [0, 360) and latitude in [-90, 90] of the eye seen from the centre.
void angles_of(const glm::vec3& d, float& longitude, float& latitude) {
  const float length = glm::length(d);
  if (!(length > 0.0f)) {
    longitude = latitude = 0.0f;
    return;
  }
  longitude = glm::degrees(std::atan2(d.z, d.x));
  if (longitude < 0.0f) longitude += 360.0f;
  latitude = glm::degrees(std::asin(std::clamp(d.y / length, -1.0f, 1.0f)));
}

}  // namespace

ViewSphere ViewSphere::with_steps(const glm::vec3& centre, float radius, float d_theta_deg,
                                  float d_phi_deg) {
  ViewSphere s;
  s.centre = centre;
  s.radius = radius;
  s.longitudes = std::max(1, int(std::lround(360.0f / d_theta_deg)));
  s.latitudes = std::max(1, int(std::lround(180.0f / d_phi_deg)));
  return s;
}

float ViewSphere::longitude_deg(uint32_t id) const {
  return float(id % uint32_t(longitudes)) * d_theta_deg();
}

float ViewSphere::latitude_deg(uint32_t id) const {
  return -90.0f + float(id / uint32_t(longitudes) + 1) * d_phi_deg();
}

CameraPose pose_on_sphere(const glm::vec3& centre, float radius, float longitude_deg,
                          float latitude_deg) {
  const float theta = glm::radians(longitude_deg), phi = glm::radians(latitude_deg);
  CameraPose p;
  p.position = centre + radius * glm::vec3(std::cos(phi) * std::cos(theta), std::sin(phi),
                                           std::cos(phi) * std::sin(theta));
  // Looking back at the centre: the opposite longitude, the latitude below the horizon.
  p.yaw_deg = longitude_deg + 180.0f;
  if (p.yaw_deg >= 180.0f) p.yaw_deg -= 360.0f;
  p.pitch_deg = -latitude_deg;
  return p;
}

glm::vec3 ViewSphere::position(uint32_t id) const {
  return pose(id).position;
}

CameraPose ViewSphere::pose(uint32_t id) const {
  return pose_on_sphere(centre, radius, longitude_deg(id), latitude_deg(id));
}

bool ViewSphere::stands_for(const glm::vec3& eye) const {
  const float distance = glm::length(eye - centre);
  return distance >= 0.5f * radius && distance <= 2.0f * radius;
}

uint32_t ViewSphere::nearest(const CameraPose& eye) const {
  uint32_t best = 0;
  float best_weight = -1.0f;
  for (const Weighted& w : around(eye))
    if (w.weight > best_weight) {
      best_weight = w.weight;
      best = w.id;
    }
  return best;
}

std::array<ViewSphere::Weighted, 4> ViewSphere::around(const CameraPose& eye) const {
  float longitude, latitude;
  angles_of(eye.position - centre, longitude, latitude);
  // Row r stands at latitude -90 + (r + 1) d_phi.
  const float row = std::clamp((latitude + 90.0f) / d_phi_deg() - 1.0f, 0.0f,
                               float(latitudes - 1));
  const int r0 = std::min(int(std::floor(row)), latitudes - 1);
  const int r1 = std::min(r0 + 1, latitudes - 1);
  const float s = row - float(r0);
  // The columns of a row: by the eye's longitude, or in the pole's row (its viewpoints all
  // at the pole) by the longitude whose viewpoint looks as the eye's yaw does.
  auto columns = [&](int r, int& c0, int& c1, float& t) {
    float at = longitude;
    if (r == latitudes - 1) {
      at = std::fmod(eye.yaw_deg - 180.0f, 360.0f);
      if (at < 0.0f) at += 360.0f;
    }
    const float column = at / d_theta_deg();
    c0 = int(std::floor(column)) % longitudes;
    c1 = (c0 + 1) % longitudes;
    t = column - std::floor(column);
  };
  int a0, a1, b0, b1;
  float ta, tb;
  columns(r0, a0, a1, ta);
  columns(r1, b0, b1, tb);
  auto id = [&](int r, int c) { return uint32_t(r) * uint32_t(longitudes) + uint32_t(c); };
  return {Weighted{id(r0, a0), (1 - ta) * (1 - s)}, Weighted{id(r0, a1), ta * (1 - s)},
          Weighted{id(r1, b0), (1 - tb) * s}, Weighted{id(r1, b1), tb * s}};
}

}  // namespace farfield
