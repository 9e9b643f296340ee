#include "farfield/techniques/clusters/frame_cost.hpp"

#include <algorithm>
#include <cmath>

namespace farfield {

void FrameCostModel::Sums::add(double keep, double t, double d, double y) {
  auto blend = [keep](double& sum, double value) { sum = keep * sum + value; };
  blend(weight, 1.0);
  blend(this->t, t);
  blend(this->d, d);
  blend(this->y, y);
  blend(tt, t * t);
  blend(td, t * d);
  blend(dd, d * d);
  blend(ty, t * y);
  blend(dy, d * y);
}

void FrameCostModel::observe(double triangles, double draws, double ms) {
  if (!(triangles > 0.0) || !(ms > 0.0) || !(draws >= 0.0)) return;
  recent_.add(kKeep, triangles, draws, ms);
  longer_.add(kKeepLonger, triangles, draws, ms);
  fit_ = solve(recent_, separated_);
  if (separated_) return;
  // The recent frames did not vary enough (a budget held at one cut, the coarsest one
  // perhaps): the parts the longer memory tells apart, the fixed part set so that the model
  // is exact at the recent frames' mean. Charging everything to the triangles instead would
  // price a frame of one screen-filling cluster at microseconds a triangle and never let the
  // walk refine it.
  bool longer_separated = false;
  const Fit longer = solve(longer_, longer_separated);
  if (!longer_separated) return;
  const double mt = recent_.t / recent_.weight, md = recent_.d / recent_.weight,
               my = recent_.y / recent_.weight;
  const double fixed = my - longer.per_triangle * mt - longer.per_draw * md;
  if (fixed < 0.0) return;
  fit_ = {fixed, longer.per_triangle, longer.per_draw};
  separated_ = true;
}

FrameCostModel::Fit FrameCostModel::solve(const Sums& s, bool& separated) {
  separated = false;
  Fit f;
  if (!(s.weight > 0.0)) return f;
  const double mt = s.t / s.weight, md = s.d / s.weight, my = s.y / s.weight;
  const double vtt = s.tt / s.weight - mt * mt, vdd = s.dd / s.weight - md * md,
               vtd = s.td / s.weight - mt * md, cty = s.ty / s.weight - mt * my,
               cdy = s.dy / s.weight - md * my;
  const bool triangles_vary = vtt > 0.01 * mt * mt, draws_vary = vdd > 0.01 * md * md;
  // Both parts where they vary apart from each other (correlation below 0.98).
  if (triangles_vary && draws_vary && vtd * vtd < 0.98 * 0.98 * vtt * vdd) {
    const double det = vtt * vdd - vtd * vtd;
    const double a = (cty * vdd - cdy * vtd) / det, b = (cdy * vtt - cty * vtd) / det;
    const double fixed = my - a * mt - b * md;
    if (a > 0.0 && b >= 0.0 && fixed >= 0.0) {
      separated = true;
      return {fixed, a, b};
    }
  }
  // Triangles alone: a slope where they vary, else (or with a fixed part below zero) the
  // whole time charged to them.
  if (triangles_vary && cty > 0.0) {
    const double slope = cty / vtt;
    if (my - slope * mt >= 0.0) {
      separated = true;
      return {my - slope * mt, slope, 0.0};
    }
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
  if (ms <= f.fixed) return ms / (recent_.y / recent_.t);
  return (ms - f.fixed) / f.per_triangle;
}

}  // namespace farfield
