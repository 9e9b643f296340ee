#include "farfield/techniques/clusters/frame_cost.hpp"

#include <algorithm>
#include <cmath>

#include <glm/vec4.hpp>

namespace farfield {

namespace {

// Solves the n x n system a x = b in place (n <= 3, partial pivoting); returns the
// determinant (0: singular, x unset).
double solve_linear(int n, double a[3][3], double b[3], double x[3]) {
  double det = 1.0;
  for (int c = 0; c < n; ++c) {
    int pivot = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
    if (a[pivot][c] == 0.0) return 0.0;
    if (pivot != c) {
      std::swap(a[pivot], a[c]);
      std::swap(b[pivot], b[c]);
      det = -det;
    }
    det *= a[c][c];
    for (int r = c + 1; r < n; ++r) {
      const double f = a[r][c] / a[c][c];
      for (int k = c; k < n; ++k) a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  for (int r = n; r-- > 0;) {
    double s = b[r];
    for (int k = r + 1; k < n; ++k) s -= a[r][k] * x[k];
    x[r] = s / a[r][r];
  }
  return det;
}

}  // namespace

void FrameCostModel::Sums::add(double keep, const double* counts, double ms) {
  weight = keep * weight + 1.0;
  y = keep * y + ms;
  for (int i = 0; i < kParts; ++i) {
    x[i] = keep * x[i] + counts[i];
    xy[i] = keep * xy[i] + counts[i] * ms;
    for (int j = 0; j < kParts; ++j) xx[i][j] = keep * xx[i][j] + counts[i] * counts[j];
  }
}

void FrameCostModel::observe(const FrameWork& work, double ms) {
  if (!(work.triangles > 0.0) || !(ms > 0.0) || !(work.draws >= 0.0) || !(work.pixels >= 0.0))
    return;
  const double counts[kParts] = {work.triangles, work.draws, use_pixels_ ? work.pixels : 0.0};
  recent_.add(kKeep, counts, ms);
  longer_.add(kKeepLonger, counts, ms);
  fit_ = solve(recent_, separated_);
  if (separated_) return;
  // The recent frames did not vary enough (a budget held at one cut, the coarsest one
  // perhaps): the parts the longer memory tells apart, the fixed part set so that the model
  // is exact at the recent frames' mean. Charging everything to the triangles instead would
  // price a frame of one screen-filling cluster at microseconds a triangle and never let the
  // walk refine it.
  bool longer_separated = false;
  Fit longer = solve(longer_, longer_separated);
  if (!longer_separated) return;
  double fixed = recent_.y / recent_.weight;
  for (int i = 0; i < kParts; ++i) fixed -= longer.per[i] * recent_.x[i] / recent_.weight;
  if (fixed < 0.0) return;
  longer.fixed = fixed;
  fit_ = longer;
  separated_ = true;
}

FrameCostModel::Fit FrameCostModel::solve(const Sums& s, bool& separated) const {
  separated = false;
  Fit f;
  if (!(s.weight > 0.0)) return f;
  double mean[kParts], cov[kParts][kParts], cov_y[kParts];
  const double my = s.y / s.weight;
  for (int i = 0; i < kParts; ++i) mean[i] = s.x[i] / s.weight;
  for (int i = 0; i < kParts; ++i) {
    cov_y[i] = s.xy[i] / s.weight - mean[i] * my;
    for (int j = 0; j < kParts; ++j) cov[i][j] = s.xx[i][j] / s.weight - mean[i] * mean[j];
  }
  auto varies = [&](int i) { return cov[i][i] > 0.01 * mean[i] * mean[i]; };
  // The parts fitted together, most first: a part is left out where it does not vary (its
  // counts within 10% of their mean), where the parts move together (the correlations'
  // determinant below that of two parts correlated at 0.98) or where its fit is negative.
  static constexpr int kSubsets[4][kParts + 1] = {{3, 0, 1, 2}, {2, 0, 1}, {2, 0, 2}, {1, 0}};
  for (const auto& subset : kSubsets) {
    const int n = subset[0];
    const int* parts = subset + 1;
    bool usable = true;
    for (int k = 0; k < n; ++k) usable = usable && varies(parts[k]);
    if (!usable) continue;
    double corr[3][3], a[3][3], b[3], x[3], unused[3] = {0, 0, 0}, none[3] = {0, 0, 0};
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) {
        a[r][c] = cov[parts[r]][parts[c]];
        corr[r][c] = a[r][c] / std::sqrt(cov[parts[r]][parts[r]] * cov[parts[c]][parts[c]]);
      }
    if (n > 1 && solve_linear(n, corr, none, unused) < 1.0 - 0.98 * 0.98) continue;
    for (int r = 0; r < n; ++r) b[r] = cov_y[parts[r]];
    if (solve_linear(n, a, b, x) == 0.0) continue;
    Fit fit;
    fit.fixed = my;
    bool positive = x[0] > 0.0;
    for (int k = 0; k < n; ++k) {
      positive = positive && x[k] >= 0.0;
      fit.per[parts[k]] = x[k];
      fit.fixed -= x[k] * mean[parts[k]];
    }
    // A draw priced as more than kMaxTrianglesPerDraw triangles has taken another cost that
    // moves with the draws for its own: on the 256-tree field's fly the few draws of the near
    // trees' levels (2 to 12 a frame) came out at 0.8 and 1.2 ms each, 26,000 and 43,000
    // triangles' worth, where a draw on llvmpipe costs hundreds; frames of many triangles in
    // few draws were then priced at half their time.
    const bool plausible = fit.per[1] <= kMaxTrianglesPerDraw * fit.per[0];
    if (positive && plausible && fit.fixed >= 0.0) {
      separated = true;
      return fit;
    }
  }
  f.per[0] = my / mean[0];  // the whole time charged to the triangles
  return f;
}

double FrameCostModel::predict_ms(const FrameWork& work) const {
  const Fit& f = fit_;
  return f.fixed + f.per[0] * work.triangles + f.per[1] * work.draws + f.per[2] * work.pixels;
}

double FrameCostModel::triangles_per_draw() const {
  const Fit& f = fit_;
  return f.per[0] > 0.0 ? f.per[1] / f.per[0] : 0.0;
}

double FrameCostModel::triangles_within(double ms, double pixels) const {
  const Fit& f = fit_;
  if (!(f.per[0] > 0.0)) return 0.0;
  // A fixed part at or over the budget would ask for nothing, and frames of nothing then
  // teach the model nothing (the "fixed" part is mostly the fill of the screen, which a frame
  // of one coarse cluster does not pay): the mean time per triangle of the frames measured
  // instead, which asks for what took that long.
  const double left = ms - f.fixed - f.per[2] * pixels;
  if (left <= 0.0) return ms / (recent_.y / recent_.x[0]);
  return left / f.per[0];
}

double projected_pixels(const Bounds3& box, const glm::mat4& view_projection, int width,
                        int height) {
  const double whole = double(width) * double(height);
  if (box.empty()) return 0.0;
  float lo_x = INFINITY, lo_y = INFINITY, hi_x = -INFINITY, hi_y = -INFINITY;
  for (int k = 0; k < 8; ++k) {
    const glm::vec4 clip =
        view_projection * glm::vec4((k & 1) ? box.max.x : box.min.x,
                                    (k & 2) ? box.max.y : box.min.y,
                                    (k & 4) ? box.max.z : box.min.z, 1.0f);
    if (!(clip.w > 1e-6f)) return whole;  // behind the eye: it may cover anything
    const float x = clip.x / clip.w, y = clip.y / clip.w;
    lo_x = std::min(lo_x, x);
    hi_x = std::max(hi_x, x);
    lo_y = std::min(lo_y, y);
    hi_y = std::max(hi_y, y);
  }
  const double dx = std::max(0.0f, std::min(hi_x, 1.0f) - std::max(lo_x, -1.0f));
  const double dy = std::max(0.0f, std::min(hi_y, 1.0f) - std::max(lo_y, -1.0f));
  return dx * dy * 0.25 * whole;
}

}  // namespace farfield
