// What a frame costs, learnt from the frames measured so far (paper 001, Sec. 5.2 measures
// each representation's cost offline; this is the run-time half): frame time = a fixed part +
// a part per triangle, fitted by exponentially weighted least squares over the last frames'
// (triangles, milliseconds), so that the model follows the machine and the path. Where the
// frames measured do not vary enough in triangles to tell the two parts apart, the whole time
// is charged to the triangles (no fixed part): exact at the count measured, and the changes a
// budget makes to the count then tell the parts apart.
#pragma once

namespace farfield {

class FrameCostModel {
 public:
  void observe(double triangles, double ms);
  bool ready() const { return weight_ > 0.0; }
  double fixed_ms() const;
  double ms_per_triangle() const;
  double predict_ms(double triangles) const { return fixed_ms() + ms_per_triangle() * triangles; }
  // The most triangles predicted to fit in `ms` (0 when the fixed part alone exceeds it).
  double triangles_within(double ms) const;

 private:
  static constexpr double kKeep = 0.9;  // each frame's weight against the previous ones'
  double weight_ = 0, x_ = 0, y_ = 0, xx_ = 0, xy_ = 0;  // weighted sums
};

}  // namespace farfield
