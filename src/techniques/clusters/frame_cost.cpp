#include "farfield/techniques/clusters/frame_cost.hpp"

#include <algorithm>

namespace farfield {

void FrameCostModel::observe(double triangles, double ms) {
  if (!(triangles > 0.0) || !(ms > 0.0)) return;
  weight_ = kKeep * weight_ + 1.0;
  x_ = kKeep * x_ + triangles;
  y_ = kKeep * y_ + ms;
  xx_ = kKeep * xx_ + triangles * triangles;
  xy_ = kKeep * xy_ + triangles * ms;
}

double FrameCostModel::ms_per_triangle() const {
  if (!ready()) return 0.0;
  const double mx = x_ / weight_, my = y_ / weight_;
  const double variance = xx_ / weight_ - mx * mx, covariance = xy_ / weight_ - mx * my;
  // Triangle counts within 10% of each other cannot separate a fixed part from the rest.
  if (variance > 0.01 * mx * mx && covariance > 0.0) {
    const double slope = covariance / variance;
    if (my - slope * mx >= 0.0) return slope;  // a fixed part below zero: fit through zero
  }
  return my / mx;
}

double FrameCostModel::fixed_ms() const {
  if (!ready()) return 0.0;
  return std::max(0.0, (y_ - ms_per_triangle() * x_) / weight_);
}

double FrameCostModel::triangles_within(double ms) const {
  const double per = ms_per_triangle();
  if (!(per > 0.0)) return 0.0;
  return std::max(0.0, (ms - fixed_ms()) / per);
}

}  // namespace farfield
