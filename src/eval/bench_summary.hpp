// Statistics of one technique's frames, against brute where it has frames of the same path.
#pragma once

#include "farfield/eval/bench.hpp"

namespace farfield {

struct BenchSummary {
  double median_ms = 0, p95_ms = 0, p99_ms = 0, max_ms = 0, mean_ms = 0;
  double mean_triangles = 0, mean_draw_calls = 0;
  uint32_t compared_frames = 0, identical_frames = 0;
  // PSNR over the compared frames, an identical frame counted at `psnr_ceiling_db`: the PSNR
  // of one channel of one pixel off by one, above that of any frame that differs.
  double psnr_db_mean = 0, psnr_db_min = 0;
  double psnr_db_mean_differing = 0;  // over the frames that differ; 0 when none does
  // The PSNR of the mean squared error over all compared frames (an identical frame's is 0),
  // so that techniques that differ on different frames compare; 0 when none differs.
  double psnr_db_pooled = 0;
  double psnr_ceiling_db = 0;
  // Over the compared frames against brute supersampled (BenchOptions::reference_supersample),
  // brute's own frames included, an identical frame at the ceiling; 0 without one.
  uint32_t supersampled_frames = 0;
  double psnr_supersampled_db_mean = 0;
  double pipelined_median_ms = 0, pipelined_p99_ms = 0, pipelined_latency_median_ms = 0;
  // Against brute, frame by frame (0 for brute itself).
  double median_ratio_to_brute = 0;          // median(this) / median(brute)
  double triangle_ratio_to_brute = 0;        // mean triangles / brute's
  double frames_slower_than_brute_1_1x = 0;  // fraction with frame_ms > 1.1 x brute's
  // Under a budget (0: none): the fraction of frames over 1.1 x it, and p99 / budget.
  double frames_over_budget_1_1x = 0, p99_to_budget = 0;
  // Frames whose technique predicted their time, and the median of |predicted - measured| /
  // measured over them.
  uint32_t predicted_frames = 0;
  double predicted_median_rel_error = 0;
  // Frames that culled by occlusion, and the median CPU time it took them.
  uint32_t occlusion_frames = 0;
  double occlusion_ms_median = 0;
};

BenchSummary summarize(const TechniqueRecord& technique, const TechniqueRecord* brute, int width,
                       int height, double budget_ms = 0);

}  // namespace farfield
