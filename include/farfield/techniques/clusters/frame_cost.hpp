// What a frame costs, learnt from the frames measured so far (paper 001, Sec. 5.2 measures
// each representation's cost offline; this is the run-time half): frame time = a fixed part +
// a part per triangle + a part per draw, fitted by exponentially weighted least squares over
// the last frames' (triangles, draws, milliseconds), so that the model follows the machine
// and the path. On llvmpipe a draw costs as much as a few hundred triangles, so a budget
// counted in triangles alone buys too many small draws. Where the frames measured do not
// vary enough to tell the parts apart (triangles and draws within 10%, or moving together),
// the draws are left out; where triangles do not vary either, the parts a longer memory of
// frames tells apart (the fixed part set to match the recent frames), and failing that the
// whole time is charged to the triangles (no fixed part): exact at the count measured, and
// the changes a budget makes to the counts then tell the parts apart.
#pragma once

#include <cstdint>

namespace farfield {

class FrameCostModel {
 public:
  void observe(double triangles, double draws, double ms);
  bool ready() const { return recent_.weight > 0.0; }
  // The parts were told apart (by the recent frames or the longer memory); false: the frames
  // measured held one count, and the whole time is charged to the triangles.
  bool separated() const { return separated_; }
  double fixed_ms() const { return fit_.fixed; }
  double ms_per_triangle() const { return fit_.per_triangle; }
  double ms_per_draw() const { return fit_.per_draw; }
  double predict_ms(double triangles, double draws) const;
  // The most triangles predicted to fit in `ms` when each draw is counted as
  // triangles_per_draw() triangles; where the fixed part alone exceeds `ms`, what fits at the
  // mean time per triangle of the frames measured.
  double triangles_within(double ms) const;
  double triangles_per_draw() const;

 private:
  struct Fit {
    double fixed = 0, per_triangle = 0, per_draw = 0;
  };
  // Exponentially weighted sums of t (triangles), d (draws), y (ms) and their products.
  struct Sums {
    double weight = 0, t = 0, d = 0, y = 0, tt = 0, td = 0, dd = 0, ty = 0, dy = 0;
    void add(double keep, double t, double d, double y);
  };
  // The least squares of `sums`; `separated`: the parts could be told apart.
  static Fit solve(const Sums& sums, bool& separated);
  // Each frame's weight against the previous ones': the recent frames (about ten), and a
  // longer memory (about a hundred) for when the recent ones do not vary.
  static constexpr double kKeep = 0.9, kKeepLonger = 0.99;
  Sums recent_, longer_;
  Fit fit_;  // after the last observe()
  bool separated_ = false;
};

}  // namespace farfield
