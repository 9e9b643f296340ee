#include "farfield/techniques/stratified/viewcell_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace farfield::stratified {

namespace {

constexpr double kSqrt2 = std::numbers::sqrt2;
constexpr double kDegree = std::numbers::pi / 180.0;

std::string num(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

bool positive(double v) {
  return std::isfinite(v) && v > 0.0;
}

Result<void> check_alpha(double alpha_deg) {
  if (!(std::isfinite(alpha_deg) && alpha_deg > 0.0 && alpha_deg < 90.0))
    return make_error("--alpha-deg must be in (0, 90) degrees (got ", num(alpha_deg), ")");
  return {};
}

Result<void> check_length(double v, const char* option) {
  if (!positive(v))
    return make_error(option, " must be a positive length in metres (got ", num(v), ")");
  return {};
}

// Checks 0 < v < b < l for the inverse solves: the viewcell inside its box, the box inside
// the model (paper 000, Sec. 2.1 and Fig. 2-4).
Result<void> check_nested(double viewcell, double box, double model) {
  if (auto ok = check_length(viewcell, "--viewcell"); !ok) return ok;
  if (auto ok = check_length(box, "--box"); !ok) return ok;
  if (auto ok = check_length(model, "--model"); !ok) return ok;
  if (viewcell >= box)
    return make_error("--viewcell ", num(viewcell), " m must be shorter than --box ", num(box),
                      " m");
  if (box >= model)
    return make_error("--box ", num(box), " m must be shorter than --model ", num(model), " m");
  return {};
}

// paper 000, Eq. 2.1 at the worst viewpoint of Fig. 2-4: s = v / sqrt(2), t = (b - v) / 2 and
// the far point at t + t' = `far` from the viewpoint's foot. Returns alpha in degrees.
double parallax_error_deg(double v, double b, double far) {
  return 90.0 - (std::atan(v / (far * kSqrt2)) + std::atan((b - v) / (v * kSqrt2))) / kDegree;
}

// The smallest v in (0, b) with parallax_error_deg(v, b, p - q v) == alpha_deg: q = 1, p = l is
// Eq. 2.2 (t + t' = l - v); q = 0, p = l_i - v_i is Eq. 4.1 for an inner shell, whose far
// distance does not depend on v_i. Taking tan of both sides of Eq. 2.1 with the addition theorem
// (both arctangents lie in (0, 90), their sum is 90 - alpha) and clearing denominators leaves
//   (2 + 2q - k (1 - 2q)) v^2 - (2 (b q + p) + k (2p - b)) v + 2 b p = 0,  k = sqrt(2) cot alpha.
// The error grows from 0 at v = 0 and, when the box is long against the far distance, falls
// again before v = b, so two roots can lie in (0, b): the smaller is the first v whose error
// reaches alpha, the viewcell that keeps every smaller one within the bound. Returns 0 when no
// viewcell inside the box reaches alpha.
double solve_viewcell(double alpha_deg, double b, double p, double q) {
  const double k = kSqrt2 / std::tan(alpha_deg * kDegree);
  const double a2 = 2.0 + 2.0 * q - k * (1.0 - 2.0 * q);
  const double a1 = -(2.0 * (b * q + p) + k * (2.0 * p - b));
  const double a0 = 2.0 * b * p;
  double roots[2] = {0.0, 0.0};
  int n = 0;
  if (a2 == 0.0) {
    if (a1 != 0.0) roots[n++] = -a0 / a1;
  } else if (const double disc = a1 * a1 - 4.0 * a2 * a0; disc >= 0.0) {
    // The cancellation-free pair: q/a2 and a0/q (Numerical Recipes, Sec. 5.6).
    const double h = -0.5 * (a1 + std::copysign(std::sqrt(disc), a1));
    roots[n++] = h / a2;
    if (h != 0.0) roots[n++] = a0 / h;
  }
  double best = 0.0;
  for (int i = 0; i < n; ++i) {
    const double v = roots[i];
    if (!(v > 0.0 && v < b)) continue;
    // Clearing denominators admits no other roots in (0, b); the check guards rounding.
    if (std::abs(parallax_error_deg(v, b, p - q * v) - alpha_deg) > 1e-6 * (1.0 + alpha_deg))
      continue;
    if (best == 0.0 || v < best) best = v;
  }
  return best;
}

}  // namespace

Result<double> viewcell_length(double alpha_max_deg, double box, double model) {
  if (auto ok = check_alpha(alpha_max_deg); !ok) return ok.error();
  if (auto ok = check_length(box, "--box"); !ok) return ok.error();
  if (auto ok = check_length(model, "--model"); !ok) return ok.error();
  if (box >= model)
    return make_error("--box ", num(box), " m must be shorter than --model ", num(model), " m");
  // paper 000, Eq. 2.2
  const double v = solve_viewcell(alpha_max_deg, box, model, 1.0);
  if (v == 0.0)
    return make_error("--alpha-deg ", num(alpha_max_deg), " is too large for --box ", num(box),
                      " m and --model ", num(model),
                      " m: even a viewcell as long as the box errs by only ",
                      num(90.0 - std::atan(box / ((model - box) * kSqrt2)) / kDegree), " deg");
  return v;
}

Result<double> strict_viewcell_length(double alpha_max_deg, double box, double height) {
  if (auto ok = check_alpha(alpha_max_deg); !ok) return ok.error();
  if (auto ok = check_length(box, "--box"); !ok) return ok.error();
  if (!(height > 0.0)) return make_error("the navigable height must be > 0 m");
  const double reach = 0.5 * box * std::sin(alpha_max_deg * kDegree);  // the largest D
  const double cube = 2.0 * reach / std::sqrt(3.0);                      // D = v sqrt3 / 2
  if (height >= cube) return cube;
  // One layer of cells `height` tall: D^2 = 2 (v/2)^2 + (height/2)^2.
  return std::sqrt(2.0 * (reach * reach - 0.25 * height * height));
}

Result<double> alpha_for_viewcell(double viewcell, double box, double model) {
  if (auto ok = check_nested(viewcell, box, model); !ok) return ok.error();
  // paper 000, Eq. 2.2 as it stands: b < l keeps the two arctangents' sum below 90 degrees.
  return parallax_error_deg(viewcell, box, model - viewcell);
}

Result<double> box_for_viewcell(double alpha_max_deg, double viewcell, double model) {
  if (auto ok = check_alpha(alpha_max_deg); !ok) return ok.error();
  if (auto ok = check_length(viewcell, "--viewcell"); !ok) return ok.error();
  if (auto ok = check_length(model, "--model"); !ok) return ok.error();
  if (viewcell >= model)
    return make_error("--viewcell ", num(viewcell), " m must be shorter than --model ", num(model),
                      " m");
  // paper 000, Eq. 2.2 solved for its second arctangent, atan((b - v) / (v sqrt 2)) = angle. A
  // longer box puts the far points farther out and lowers the error, so this b is the shortest
  // box that keeps the error within alpha_max.
  const double far_angle = std::atan(viewcell / ((model - viewcell) * kSqrt2)) / kDegree;
  const double angle = 90.0 - alpha_max_deg - far_angle;
  if (angle <= 0.0)
    return make_error("--alpha-deg ", num(alpha_max_deg), " is too large for --viewcell ",
                      num(viewcell), " m and --model ", num(model),
                      " m: any box errs by less (a box as short as the viewcell by ",
                      num(90.0 - far_angle), " deg)");
  const double box = viewcell + viewcell * kSqrt2 * std::tan(angle * kDegree);
  if (box >= model)
    return make_error("--alpha-deg ", num(alpha_max_deg), " with --viewcell ", num(viewcell),
                      " m needs a box of ", num(box), " m, not shorter than --model ", num(model),
                      " m");
  return box;
}

Result<double> model_for_viewcell(double alpha_max_deg, double viewcell, double box) {
  if (auto ok = check_alpha(alpha_max_deg); !ok) return ok.error();
  if (auto ok = check_length(viewcell, "--viewcell"); !ok) return ok.error();
  if (auto ok = check_length(box, "--box"); !ok) return ok.error();
  if (viewcell >= box)
    return make_error("--viewcell ", num(viewcell), " m must be shorter than --box ", num(box),
                      " m");
  // paper 000, Eq. 2.2 solved for its first arctangent, atan(v / ((l - v) sqrt 2)) = angle. The
  // error grows with the model, so this l is the longest model within alpha_max.
  const double near_angle = std::atan((box - viewcell) / (viewcell * kSqrt2)) / kDegree;
  const double angle = 90.0 - alpha_max_deg - near_angle;
  if (angle <= 0.0)
    return make_error("--alpha-deg ", num(alpha_max_deg),
                      " holds for a model of any length with --viewcell ", num(viewcell),
                      " m and --box ", num(box), " m: the error only tends to ",
                      num(90.0 - near_angle), " deg as the model grows");
  const double model = viewcell + viewcell / (kSqrt2 * std::tan(angle * kDegree));
  if (model <= box)
    return make_error("--alpha-deg ", num(alpha_max_deg), " is too small for --viewcell ",
                      num(viewcell), " m and --box ", num(box), " m: only a model of ", num(model),
                      " m, not longer than the box, stays within it");
  return model;
}

Result<std::vector<Shell>> shell_viewcells(double alpha_max_deg, std::span<const double> boxes,
                                           double model) {
  if (auto ok = check_alpha(alpha_max_deg); !ok) return ok.error();
  if (auto ok = check_length(model, "--model"); !ok) return ok.error();
  if (boxes.empty()) return make_error("--shells needs at least one box length");
  for (size_t i = 0; i < boxes.size(); ++i) {
    if (!positive(boxes[i]))
      return make_error("--shells: box ", std::to_string(i),
                        " must be a positive length in metres (got ", num(boxes[i]), ")");
    if (i > 0 && boxes[i] <= boxes[i - 1])
      return make_error("--shells: box lengths must grow from the innermost out (",
                        num(boxes[i - 1]), " then ", num(boxes[i]), ")");
  }
  if (boxes.back() >= model)
    return make_error("--shells: the outermost box, ", num(boxes.back()),
                      " m, must be shorter than --model ", num(model), " m");

  std::vector<Shell> shells(boxes.size());
  for (size_t i = boxes.size(); i-- > 0;) {
    Shell& shell = shells[i];
    shell.box = boxes[i];
    const bool outermost = i + 1 == boxes.size();
    // paper 000, Eq. 4.1 with Sec. 4.2.1: l_i - v_i = v_{i+1}/2 + b_{i+1}/2 inside, l - v_i
    // for the outermost shell.
    const double p = outermost ? model : (shells[i + 1].viewcell + shells[i + 1].box) / 2.0;
    shell.viewcell = solve_viewcell(alpha_max_deg, shell.box, p, outermost ? 1.0 : 0.0);
    if (shell.viewcell == 0.0)
      return make_error("--alpha-deg ", num(alpha_max_deg), " is too large for shell ",
                        std::to_string(i), " (box ", num(shell.box),
                        " m): even a viewcell as long as the box stays within it");
    shell.far = outermost ? model : shell.viewcell + p;
  }
  return shells;
}

Result<std::vector<double>> box_series(Spacing spacing, double b0, double factor, double model,
                                       int count) {
  if (auto ok = check_length(b0, "--b0"); !ok) return ok.error();
  if (auto ok = check_length(model, "--model"); !ok) return ok.error();
  if (!(std::isfinite(factor) && factor > 1.0))
    return make_error("--factor must be a number over 1 so that the boxes grow (got ", num(factor),
                      ")");
  if (spacing == Spacing::exponential && b0 <= 1.0)
    return make_error(
        "--b0 must be over 1 m for exponential spacing: b0^factor would not grow (got ", num(b0),
        ")");
  if (count < 0 || count > max_shells)
    return make_error("--count must be in [1, ", std::to_string(max_shells), "] (got ",
                      std::to_string(count), ")");
  if (b0 >= model)
    return make_error("--b0 ", num(b0), " m must be shorter than --model ", num(model), " m");
  std::vector<double> boxes{b0};
  while (count == 0 || static_cast<int>(boxes.size()) < count) {
    // paper 000, Sec. 4.2.1: b_{i+1} = f b_i (linear) or b_i^f (exponential).
    const double next =
        spacing == Spacing::linear ? factor * boxes.back() : std::pow(boxes.back(), factor);
    if (next >= model) {
      if (count == 0) break;
      return make_error("--count ", std::to_string(count), ": box ", std::to_string(boxes.size()),
                        " would be ", num(next), " m, not shorter than --model ", num(model), " m");
    }
    if (static_cast<int>(boxes.size()) == max_shells)
      return make_error("--factor ", num(factor), " grows the boxes so slowly that more than ",
                        std::to_string(max_shells), " shells fit in --model ", num(model), " m");
    boxes.push_back(next);
  }
  return boxes;
}

Result<ViewcellCount> count_viewcells(double viewcell, const std::array<double, 3>& region) {
  if (auto ok = check_length(viewcell, "--viewcell"); !ok) return ok.error();
  ViewcellCount count;
  double volume = 1.0;
  double grid = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    if (!positive(region[axis]))
      return make_error("--region: extent ", std::to_string(axis),
                        " must be a positive length in metres (got ", num(region[axis]), ")");
    // Whole cells, rounded up (see the header); the slack keeps 1000 / 10.000000001 at 100.
    const double cells = std::max(1.0, std::ceil(region[axis] / viewcell * (1.0 - 1e-9)));
    grid *= cells;
    if (grid > 9e18)
      return make_error("--region ", num(region[0]), ",", num(region[1]), ",", num(region[2]),
                        " holds more than 9e18 viewcells of ", num(viewcell), " m");
    count.cells[axis] = static_cast<uint64_t>(cells);
    volume *= region[axis];
  }
  count.grid = count.cells[0] * count.cells[1] * count.cells[2];
  count.volume_ratio = volume / (viewcell * viewcell * viewcell);  // paper 000, Eq. 4.2
  return count;
}

Result<ThroughputBox> box_from_throughput(const Throughput& t) {
  if (!positive(t.triangles_per_second))
    return make_error("--triangles-per-second must be a positive number (got ",
                      num(t.triangles_per_second), ")");
  if (!positive(t.frame_ms))
    return make_error("--frame-ms must be a positive number of milliseconds (got ", num(t.frame_ms),
                      ")");
  if (!positive(t.density))
    return make_error("--triangle-density must be a positive number of triangles per ",
                      t.unit == DensityUnit::per_cubic_metre ? "m^3" : "m^2", " (got ",
                      num(t.density), ")");
  // A frustum wider than 90 degrees leaves the box through its side faces; the fractions below
  // hold up to 90 degrees, which covers the paper's view and our bench protocol (90 x 73.7).
  if (!(std::isfinite(t.hfov_deg) && t.hfov_deg > 0.0 && t.hfov_deg <= 90.0))
    return make_error("--hfov-deg must be in (0, 90] degrees (got ", num(t.hfov_deg), ")");
  if (!(std::isfinite(t.vfov_deg) && t.vfov_deg > 0.0 && t.vfov_deg <= 90.0))
    return make_error("--vfov-deg must be in (0, 90] degrees (got ", num(t.vfov_deg), ")");

  ThroughputBox out;
  // paper 000, Eq. 2.3: p = P, the triangles the renderer draws in one frame.
  out.triangles_per_frame = t.triangles_per_second * t.frame_ms / 1000.0;
  const double tx = std::tan(t.hfov_deg / 2.0 * kDegree);
  const double ty = std::tan(t.vfov_deg / 2.0 * kDegree);
  if (t.unit == DensityUnit::per_cubic_metre) {
    // From the centre the box splits into six pyramids, one per face (the paper's 1/6 at 90 x 90);
    // a narrower frustum takes tx * ty of its face's pyramid. p = b^3 rho fraction (Sec. 2.4.2).
    out.visible_fraction = tx * ty / 6.0;
    out.box = std::cbrt(out.triangles_per_frame / (t.density * out.visible_fraction));
  } else {
    // 2.5D: the box spans the model's height, so only the horizontal view culls: the wedge of
    // half-angle h/2 covers tx / 4 of the square.
    out.visible_fraction = tx / 4.0;
    out.box = std::sqrt(out.triangles_per_frame / (t.density * out.visible_fraction));
  }
  return out;
}

}  // namespace farfield::stratified
