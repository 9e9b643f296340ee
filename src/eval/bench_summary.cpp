#include "bench_summary.hpp"

#include <algorithm>
#include <cmath>

namespace farfield {

namespace {

// Nearest-rank percentile of sorted values.
double percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  const size_t rank = static_cast<size_t>(std::ceil(p / 100.0 * double(sorted.size())));
  return sorted[std::clamp<size_t>(rank, 1, sorted.size()) - 1];
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  if (v.empty()) return 0.0;
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

BenchSummary summarize(const TechniqueRecord& t, const TechniqueRecord* brute, int width,
                       int height, double budget_ms) {
  BenchSummary s;
  // MSE of one channel of one pixel off by one: 1 / (3 w h).
  s.psnr_ceiling_db = 10.0 * std::log10(255.0 * 255.0 * 3.0 * double(width) * double(height));
  const size_t n = t.frames.size();
  if (n == 0) return s;
  std::vector<double> ms, pipelined, latency, prediction_error, occlusion;
  uint32_t over_budget = 0;
  double psnr_sum = 0, mse_sum = 0;
  uint32_t psnr_count = 0;
  s.psnr_db_min = s.psnr_ceiling_db;
  for (const FrameRecord& f : t.frames) {
    ms.push_back(f.frame_ms);
    over_budget += budget_ms > 0 && f.frame_ms > 1.1 * budget_ms;
    if (f.predicted_ms >= 0 && f.frame_ms > 0)
      prediction_error.push_back(std::abs(f.predicted_ms - f.frame_ms) / f.frame_ms);
    if (f.occlusion_ms >= 0) occlusion.push_back(f.occlusion_ms);
    if (f.pipelined_frame_ms > 0) {
      pipelined.push_back(f.pipelined_frame_ms);
      latency.push_back(f.pipelined_latency_ms);
    }
    s.mean_ms += f.frame_ms / double(n);
    s.mean_triangles += double(f.triangles) / double(n);
    s.mean_draw_calls += double(f.draw_calls) / double(n);
    if (!f.compared) continue;
    s.compared_frames++;
    if (f.psnr_supersampled_db > 0) {
      s.supersampled_frames++;
      s.psnr_supersampled_db_mean +=
          std::isfinite(f.psnr_supersampled_db) ? f.psnr_supersampled_db : s.psnr_ceiling_db;
    }
    if (f.differing_pixels == 0) {
      s.identical_frames++;
      continue;
    }
    psnr_sum += f.psnr_db;
    mse_sum += 255.0 * 255.0 / std::pow(10.0, f.psnr_db / 10.0);
    psnr_count++;
    s.psnr_db_min = std::min(s.psnr_db_min, f.psnr_db);
  }
  s.psnr_db_mean_differing = psnr_count ? psnr_sum / psnr_count : 0.0;
  s.psnr_db_pooled =
      mse_sum > 0 ? 10.0 * std::log10(255.0 * 255.0 * s.compared_frames / mse_sum) : 0.0;
  s.psnr_db_mean = s.compared_frames
                       ? (psnr_sum + s.identical_frames * s.psnr_ceiling_db) / s.compared_frames
                       : 0.0;
  if (s.compared_frames == 0) s.psnr_db_min = 0.0;
  if (s.supersampled_frames) s.psnr_supersampled_db_mean /= s.supersampled_frames;
  std::sort(pipelined.begin(), pipelined.end());
  s.pipelined_median_ms = median(pipelined);
  s.pipelined_p99_ms = percentile(pipelined, 99);
  s.pipelined_latency_median_ms = median(latency);
  std::sort(ms.begin(), ms.end());
  s.median_ms = median(ms);
  s.p95_ms = percentile(ms, 95);
  s.p99_ms = percentile(ms, 99);
  s.max_ms = ms.back();
  if (budget_ms > 0) {
    s.frames_over_budget_1_1x = double(over_budget) / double(n);
    s.p99_to_budget = s.p99_ms / budget_ms;
  }
  s.predicted_frames = uint32_t(prediction_error.size());
  s.predicted_median_rel_error = median(prediction_error);
  s.occlusion_frames = uint32_t(occlusion.size());
  s.occlusion_ms_median = median(occlusion);
  if (brute && brute != &t && brute->frames.size() == n) {
    BenchSummary b = summarize(*brute, nullptr, width, height);
    s.median_ratio_to_brute = b.median_ms > 0 ? s.median_ms / b.median_ms : 0;
    s.triangle_ratio_to_brute = b.mean_triangles > 0 ? s.mean_triangles / b.mean_triangles : 0;
    uint32_t slower = 0;
    for (size_t i = 0; i < n; ++i) slower += t.frames[i].frame_ms > 1.1 * brute->frames[i].frame_ms;
    s.frames_slower_than_brute_1_1x = double(slower) / double(n);
  }
  return s;
}

}  // namespace farfield
