// What a frame costs, learnt from the frames measured so far (paper 001, Sec. 5.2 measures
// each representation's cost offline; this is the run-time half): frame time = a fixed part +
// a part per triangle + a part per draw, fitted by exponentially weighted least squares over
// the last frames' (triangles, draws, milliseconds), so that the model follows the machine
// and the path. On llvmpipe a draw costs as much as a few hundred triangles, so a budget
// counted in triangles alone buys too many small draws. Where the frames measured do not
// vary enough to tell the parts apart (triangles and draws within 10%, or moving together),
// the draws are left out, and where triangles do not vary either the whole time is charged
// to the triangles (no fixed part): exact at the count measured, and the changes a budget
// makes to the counts then tell the parts apart.
#pragma once

#include <cstdint>

namespace farfield {

class FrameCostModel {
 public:
  void observe(double triangles, double draws, double ms);
  bool ready() const { return weight_ > 0.0; }
  double fixed_ms() const { return fit_.fixed; }
  double ms_per_triangle() const { return fit_.per_triangle; }
  double ms_per_draw() const { return fit_.per_draw; }
  double predict_ms(double triangles, double draws) const;
  // The most triangles predicted to fit in `ms` when each draw is counted as
  // triangles_per_draw() triangles; where the fixed part alone exceeds `ms`, what fits at the
  // mean time per triangle of the frames measured.
  double triangles_within(double ms) const;
  double triangles_per_draw() const;
  // What share of triangles_within() frame `frame` should ask for. A budget that holds its
  // frames steady would leave the model nothing to tell its fixed part from its part per
  // triangle (it would charge everything to the triangles and buy too few): every third
  // frame asks for a quarter fewer, below the budget, never above.
  static double probe_share(uint64_t frame) { return frame % 3 == 0 ? 0.75 : 1.0; }

 private:
  struct Fit {
    double fixed = 0, per_triangle = 0, per_draw = 0;
  };
  Fit solve() const;                    // from the sums
  Fit fit_;                             // solve() after the last observe()
  static constexpr double kKeep = 0.9;  // each frame's weight against the previous ones'
  // Weighted sums of t (triangles), d (draws), y (ms) and their products.
  double weight_ = 0, t_ = 0, d_ = 0, y_ = 0, tt_ = 0, td_ = 0, dd_ = 0, ty_ = 0, dy_ = 0;
};

}  // namespace farfield
