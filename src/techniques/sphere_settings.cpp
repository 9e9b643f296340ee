#include "farfield/techniques/sphere_settings.hpp"

#include "farfield/scene/path_generator.hpp"

namespace farfield {

SphereSettings SphereSettings::from(const SettingValues& v) {
  SphereSettings s;
  s.d_theta_deg = float(v.number("d_theta"));
  s.d_phi_deg = float(v.number("d_phi"));
  s.radius_m = float(v.number_or("radius", 0.0));
  return s;
}

double SphereSettings::radius_for(const Scene& scene) const {
  return radius_m > 0 ? double(radius_m) : whole_view_distance(scene.bounds);
}

ViewSphere SphereSettings::sphere_for(const Scene& scene) const {
  return ViewSphere::with_steps(scene.bounds.center(), float(radius_for(scene)), d_theta_deg,
                                d_phi_deg);
}

}  // namespace farfield
