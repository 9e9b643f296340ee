// Viewcell analysis of Stratified Rendering (paper 000, Chapters 2 and 4): how long a viewcell
// may be so that the far field, pre-rendered from the viewcell's centre onto the sides of its
// bounding box, stays within an angular error bound alpha_max from every viewpoint in the cell.
//
// Pure math: no GL, no files, microseconds per call. Lengths are metres, angles degrees.
// Symbols are the paper's: alpha_max the angular error bound, v the viewcell length, b the
// bounding box length, l the model length (its largest horizontal extent). Bad input returns a
// Result whose message names the option as `farfield analyze viewcell` spells it.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "farfield/core/result.hpp"

namespace farfield::stratified {

// paper 000, Eq. 2.2: the largest viewcell length v for alpha_max, b and l. Needs
// 0 < alpha_max < 90 and 0 < b < l; fails when alpha_max is so large that even a viewcell as long
// as the box stays within it. Closed form (a quadratic in v, see the .cpp).
Result<double> viewcell_length(double alpha_max_deg, double box, double model);

// A viewcell length whose bound holds in 3D for every eye point in the viewcell and every far
// point at any distance: a far point and its texel are seen at most asin(D / (b/2)) apart, D the
// distance from the viewcell's centre to its corners (the eye displaced by D from the centre
// sees the ray through the texel within that angle). Eq. 2.2 takes the worst case in the plane
// of Fig. 2-4 (s = v/sqrt2, the texel straight ahead); an eye at a corner, looking past the
// side's middle, errs up to ~15% more (tests/stratified_test.cpp measures it). Viewcells are
// at most `height` tall (a navigable band thinner than v), which allows longer ones.
Result<double> strict_viewcell_length(double alpha_max_deg, double box, double height);

// Eq. 2.2 solved for each of the other three from the rest. Each needs 0 < v < b < l.
Result<double> alpha_for_viewcell(double viewcell, double box, double model);  // alpha_max, deg
Result<double> box_for_viewcell(double alpha_max_deg, double viewcell, double model);
Result<double> model_for_viewcell(double alpha_max_deg, double viewcell, double box);

// One shell of the multi-shell extension (paper 000, Chapter 4); index 0 is the innermost.
struct Shell {
  double box = 0.0;       // b_i
  double far = 0.0;       // l_i: the largest distance from a point in the viewcell to its far
                          // objects (Sec. 4.2.1); l for the outermost shell
  double viewcell = 0.0;  // v_i
};

// paper 000, Eq. 4.1 with l_i of Sec. 4.2.1: viewcell lengths for the given box lengths
// (strictly increasing, the outermost shorter than the model). The far field of shell i ends at
// shell i+1's box, so l_i = v_i + v_{i+1}/2 + b_{i+1}/2; the outermost shell's far field is the
// rest of the model (Eq. 2.2 with l). Solved from the outside in.
Result<std::vector<Shell>> shell_viewcells(double alpha_max_deg, std::span<const double> boxes,
                                           double model);

// Box series of paper 000, Sec. 4.2.1 from b_0 and a factor f > 1: linear b_{i+1} = f b_i,
// exponential b_{i+1} = b_i^f (metres, as the paper; b_0 > 1 m so that it grows). `count` shells
// exactly (failing if one would reach the model), or with count 0 every box shorter than the
// model, which is how the paper's Tables 4.1 and 4.2 count (their totals include a sixth,
// resp. fifth, shell that the tables do not list). At most max_shells.
enum class Spacing { linear, exponential };
inline constexpr int max_shells = 256;
Result<std::vector<double>> box_series(Spacing spacing, double b0, double factor, double model,
                                       int count = 0);

// Viewcells over a navigable region of extents x, y, z (metres, any order).
struct ViewcellCount {
  std::array<uint64_t, 3> cells{};  // per axis: ceil(extent / v), at least 1
  uint64_t grid = 0;                // their product: the paper's count (see below)
  double volume_ratio = 0.0;        // region volume / v^3, the literal form of Eq. 4.2
};
// The paper counts whole cells per axis, each axis rounded up: that reproduces its campus figure
// (158 x 158 x 2 = 49,928, "50,000", Sec. 2.4.3), every row and total of Tables 4.1 and 4.2, and
// its remark that the total doubles once v_0 < 10 m no longer covers the 10 m height in one cell.
// The volume ratio is what its city figure uses (10^10 / 6.22^3 = 4.15e7, "4.1 x 10^7", Sec.
// 2.4.4). An extent within 1e-9 (relative) of a whole number of cells is not rounded up.
Result<ViewcellCount> count_viewcells(double viewcell, const std::array<double, 3>& region);

// What the triangle density is counted per: the paper's polygons per cubic metre, or per square
// metre of ground for a 2.5D model no taller than the box (Sec. 3.1.2: cities usually are).
enum class DensityUnit { per_cubic_metre, per_square_metre };

struct Throughput {
  double triangles_per_second = 0.0;  // P_sec: the renderer's measured rate (farfield bench)
  double frame_ms = 0.0;              // the target frame time
  double density = 0.0;               // near triangles per unit volume or area
  DensityUnit unit = DensityUnit::per_cubic_metre;
  double hfov_deg = 90.0;  // the paper's 90 x 90 degree view; each in (0, 90]
  double vfov_deg = 90.0;
};

struct ThroughputBox {
  double triangles_per_frame = 0.0;  // p = P (Eq. 2.3)
  double visible_fraction = 0.0;     // share of the box's triangles in the view frustum
  double box = 0.0;                  // b
};

// paper 000, Sec. 2.4.2: the box whose near triangles in view fill one frame, p = P (Eq. 2.3).
// Assumes, as the paper does, that textured-pixel fill is not the bottleneck, that the far
// textures cost nothing next to the near triangles, that triangles are spread evenly and that
// the viewpoint is at the box centre. Then p = b^3 rho * fraction, with fraction = 1/6 for the
// paper's 90 x 90 degree frustum (one face's pyramid of six), tan(h/2) tan(v/2) / 6 in general;
// per area, p = b^2 rho * tan(h/2) / 4 (the wedge of the square inside the horizontal view).
Result<ThroughputBox> box_from_throughput(const Throughput& throughput);

}  // namespace farfield::stratified
