#include "farfield/techniques/clusters/frame_cost.hpp"

#include <algorithm>
#include <cmath>

namespace farfield {

void FrameCostModel::observe(double triangles, double draws, double ms) {
  if (!(triangles > 0.0) || !(ms > 0.0) || !(draws >= 0.0)) return;
  weight_ = kKeep * weight_ + 1.0;
  auto add = [](double& sum, double value) { sum = kKeep * sum + value; };
  add(t_, triangles);
  add(d_, draws);
  add(y_, ms);
  add(tt_, triangles * triangles);
  add(td_, triangles * draws);
  add(dd_, draws * draws);
  add(ty_, triangles * ms);
  add(dy_, draws * ms);
  fit_ = solve();
}

FrameCostModel::Fit FrameCostModel::solve() const {
  Fit f;
  if (!ready()) return f;
  const double mt = t_ / weight_, md = d_ / weight_, my = y_ / weight_;
  const double vtt = tt_ / weight_ - mt * mt, vdd = dd_ / weight_ - md * md,
               vtd = td_ / weight_ - mt * md, cty = ty_ / weight_ - mt * my,
               cdy = dy_ / weight_ - md * my;
  const bool triangles_vary = vtt > 0.01 * mt * mt, draws_vary = vdd > 0.01 * md * md;
  // Both parts where they vary apart from each other (correlation below 0.98).
  if (triangles_vary && draws_vary && vtd * vtd < 0.98 * 0.98 * vtt * vdd) {
    const double det = vtt * vdd - vtd * vtd;
    const double a = (cty * vdd - cdy * vtd) / det, b = (cdy * vtt - cty * vtd) / det;
    const double fixed = my - a * mt - b * md;
    if (a > 0.0 && b >= 0.0 && fixed >= 0.0) return {fixed, a, b};
  }
  // Triangles alone: a slope where they vary, else (or with a fixed part below zero) the
  // whole time charged to them.
  if (triangles_vary && cty > 0.0) {
    const double slope = cty / vtt;
    if (my - slope * mt >= 0.0) return {my - slope * mt, slope, 0.0};
  }
  return {0.0, my / mt, 0.0};
}

double FrameCostModel::predict_ms(double triangles, double draws) const {
  const Fit& f = fit_;
  return f.fixed + f.per_triangle * triangles + f.per_draw * draws;
}

double FrameCostModel::triangles_per_draw() const {
  const Fit& f = fit_;
  return f.per_triangle > 0.0 ? f.per_draw / f.per_triangle : 0.0;
}

double FrameCostModel::triangles_within(double ms) const {
  const Fit& f = fit_;
  if (!(f.per_triangle > 0.0)) return 0.0;
  // A fixed part at or over the budget would ask for nothing, and frames of nothing then
  // teach the model nothing (the "fixed" part is mostly the fill of the screen, which a frame
  // of one coarse cluster does not pay): the mean time per triangle of the frames measured
  // instead, which asks for what took that long.
  if (ms <= f.fixed) return ms / (y_ / t_);
  return (ms - f.fixed) / f.per_triangle;
}

}  // namespace farfield
