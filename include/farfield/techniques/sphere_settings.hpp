// The viewpoint sphere's settings, shared by the techniques of paper 003 (ibr and hybrid):
// longitude and latitude steps (Sec. 2.1) and the radius, and the sphere they give for a scene.
#pragma once

#include "farfield/core/view_sphere.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

inline constexpr SettingSpec kDThetaSetting{
    .key = "d_theta",
    .type = SettingType::number,
    .default_value = "5",
    .help = "longitude between viewpoints (rounded to divide 360)",
    .unit = "deg",
    .symbol = "Delta theta (003, Sec. 2.1)",
    .min = 0.5,
    .max = 180,
    .baked = true};
inline constexpr SettingSpec kDPhiSetting{
    .key = "d_phi",
    .type = SettingType::number,
    .default_value = "5",
    .help = "latitude between viewpoints (rounded to divide 180)",
    .unit = "deg",
    .symbol = "Delta phi (003, Sec. 2.1)",
    .min = 0.5,
    .max = 180,
    .baked = true};
inline constexpr SettingSpec kRadiusSetting{
    .key = "radius",
    .type = SettingType::number,
    .default_value = "",
    .help = "the viewpoints' distance from the scene's centre; default: path --kind orbit's "
            "(the scene's bounding sphere fills the height of a 90-degree 4:3 view)",
    .unit = "m",
    .min = 0,
    .min_open = true,
    .baked = true};

struct SphereSettings {
  float d_theta_deg = 5.0f, d_phi_deg = 5.0f;
  float radius_m = 0.0f;  // 0: the orbit path's distance

  static SphereSettings from(const SettingValues& v);
  double radius_for(const Scene& scene) const;
  // About the scene's centre, at radius_for(scene).
  ViewSphere sphere_for(const Scene& scene) const;
};

}  // namespace farfield
