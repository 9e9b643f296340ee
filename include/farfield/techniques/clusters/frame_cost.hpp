// What a frame costs, learnt from the frames measured so far (paper 001, Sec. 5.2 measures
// each representation's cost offline; this is the run-time half): frame time = a fixed part +
// a part per triangle + a part per draw + a part per pixel covered, fitted by exponentially
// weighted least squares over the last frames' (triangles, draws, pixels, milliseconds), so
// that the model follows the machine and the path. On llvmpipe a draw costs as much as a few
// hundred triangles, so a budget counted in triangles alone buys too many small draws, and
// filling the screen is a large share of a frame that a view turning from the sky to the
// city changes. The pixels are an estimate made before drawing (projected_pixels: the
// chosen representations' bounds on screen, overlaps counted as often as they overlap).
// The parts are fitted together where the frames vary enough to tell them apart; where they
// do not (counts within 10%, or moving together), the parts that cannot be told apart are
// left out (pixels first, then draws); where triangles do not vary either, the parts a
// longer memory of frames tells apart (the fixed part set to match the recent frames), and
// failing that the whole time is charged to the triangles (no fixed part): exact at the count
// measured, and the changes a budget makes to the counts then tell the parts apart.
#pragma once

#include <cstdint>

#include <glm/mat4x4.hpp>

#include "farfield/core/bounds.hpp"

namespace farfield {

// What a frame draws, as the cost model counts it.
struct FrameWork {
  double triangles = 0, draws = 0, pixels = 0;
};

class FrameCostModel {
 public:
  // `pixels`: false, the previous release's model of triangles and draws alone (the pixels
  // observed are ignored).
  explicit FrameCostModel(bool pixels = true) : use_pixels_(pixels) {}
  void observe(const FrameWork& work, double ms);
  bool ready() const { return recent_.weight > 0.0; }
  // The parts were told apart (by the recent frames or the longer memory); false: the frames
  // measured held one count, and the whole time is charged to the triangles.
  bool separated() const { return separated_; }
  double fixed_ms() const { return fit_.fixed; }
  double ms_per_triangle() const { return fit_.per[0]; }
  double ms_per_draw() const { return fit_.per[1]; }
  double ms_per_pixel() const { return fit_.per[2]; }
  double predict_ms(const FrameWork& work) const;
  // The most triangles predicted to fit in `ms` with `pixels` covered, each draw counted as
  // triangles_per_draw() triangles; where the fixed part and the pixels' alone exceed `ms`,
  // what fits at the mean time per triangle of the frames measured.
  double triangles_within(double ms, double pixels = 0.0) const;
  double triangles_per_draw() const;

 private:
  static constexpr int kParts = 3;  // triangles, draws, pixels
  struct Fit {
    double fixed = 0;
    double per[kParts] = {0, 0, 0};
  };
  // Exponentially weighted sums of the counts x, the time y and their products.
  struct Sums {
    double weight = 0, y = 0;
    double x[kParts] = {}, xx[kParts][kParts] = {}, xy[kParts] = {};
    void add(double keep, const double* counts, double ms);
  };
  // The least squares of `sums`; `separated`: the parts could be told apart.
  Fit solve(const Sums& sums, bool& separated) const;
  // Each frame's weight against the previous ones': the recent frames (about ten), and a
  // longer memory (about a hundred) for when the recent ones do not vary.
  static constexpr double kKeep = 0.9, kKeepLonger = 0.99;
  // The most triangles a draw may cost as much as; a fit above it leaves the draws out (a
  // draw costs hundreds of triangles on llvmpipe, thousands on a GPU).
  static constexpr double kMaxTrianglesPerDraw = 16384.0;
  bool use_pixels_;
  Sums recent_, longer_;
  Fit fit_;  // after the last observe()
  bool separated_ = false;
};

// The pixels `box` covers at most in a view of `width` x `height` pixels seen through
// `view_projection`: its corners' bounding rectangle on screen, clipped to the view; the
// whole view where it reaches behind the eye's near plane.
double projected_pixels(const Bounds3& box, const glm::mat4& view_projection, int width,
                        int height);

}  // namespace farfield
