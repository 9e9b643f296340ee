#include "bench_report.hpp"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "bench_summary.hpp"

namespace farfield {

namespace {

using nlohmann::json;

const TechniqueRecord* find_brute(const BenchReport& report) {
  for (const auto& t : report.techniques)
    if (t.name == "brute") return &t;
  return nullptr;
}

}  // namespace

std::string bench_json(const BenchReport& report, const BenchOptions& options, const Scene& scene,
                       const CameraPath& path) {
  json root;
  uint64_t texels = 0;
  for (const Texture& t : scene.textures) texels += uint64_t(t.width) * t.height;
  root["scene"] = {{"file", options.scene_file},
                   {"triangles", report.scene_triangles},
                   {"objects", scene.objects.size()},
                   {"textures", scene.textures.size()},
                   {"texels", texels},
                   {"texture_bytes", scene.texture_bytes()},
                   {"texture_gpu_bytes", report.scene_texture_gpu_bytes},
                   {"geometry_gpu_bytes", report.scene_geometry_gpu_bytes},
                   {"instances_placed", report.instances_placed}};
  root["path"] = {{"kind", path.kind}, {"frames", path.frames.size()}};
  root["width"] = options.width;
  root["height"] = options.height;
  root["hfov_deg"] = options.hfov_deg;
  root["renderer"] = report.renderer;
  root["warmup_frames"] = options.warmup_frames;
  root["budget_ms"] = options.budget_ms;
  root["cache_mb"] = options.cache_mb;
  root["light_deg"] = {options.light_heading_deg, options.light_elevation_deg};
  root["interleaved"] = report.interleaved;
  root["brute"] = options.brute;
  root["pipelined"] = report.pipelined;
  if (const auto& n = report.noise_floor)
    root["noise_floor"] = {{"work_ms", n->work_ms},           {"rounds", n->rounds},
                           {"threads", n->threads},           {"median_ms", n->median_ms},
                           {"p99_to_median", n->p99_to_median}, {"over_1_1x", n->over_1_1x}};
  root["techniques"] = json::array();
  const TechniqueRecord* brute = find_brute(report);
  for (const TechniqueRecord& t : report.techniques) {
    const BenchSummary s = summarize(t, brute, options.width, options.height, options.budget_ms);
    json frames = json::array();
    for (const FrameRecord& f : t.frames) {
      json frame = {{"frame_ms", f.frame_ms},     {"cpu_ms", f.cpu_ms},
                    {"gpu_ms", f.gpu_ms},         {"triangles", f.triangles},
                    {"draw_calls", f.draw_calls}, {"proxy_triangles", f.proxy_triangles}};
      if (f.compared) {
        // An identical frame's PSNR is infinite, which JSON cannot hold: the ceiling instead.
        frame["psnr_db"] = std::isfinite(f.psnr_db) ? f.psnr_db : s.psnr_ceiling_db;
        frame["identical"] = f.differing_pixels == 0;
        frame["differing_pixels"] = f.differing_pixels;
        if (f.psnr_supersampled_db > 0)
          frame["psnr_supersampled_db"] =
              std::isfinite(f.psnr_supersampled_db) ? f.psnr_supersampled_db : s.psnr_ceiling_db;
      }
      if (f.predicted_ms >= 0) frame["predicted_ms"] = f.predicted_ms;
      if (f.occlusion_ms >= 0) frame["occlusion_ms"] = f.occlusion_ms;
      if (f.upload_ms > 0) frame["upload_ms"] = f.upload_ms;
      if (report.pipelined) {
        frame["pipelined_frame_ms"] = f.pipelined_frame_ms;
        frame["pipelined_latency_ms"] = f.pipelined_latency_ms;
      }
      frames.push_back(std::move(frame));
    }
    json summary = {{"median_ms", s.median_ms},
                    {"p95_ms", s.p95_ms},
                    {"p99_ms", s.p99_ms},
                    {"max_ms", s.max_ms},
                    {"mean_ms", s.mean_ms},
                    {"mean_triangles", s.mean_triangles},
                    {"mean_draw_calls", s.mean_draw_calls},
                    {"psnr_ceiling_db", s.psnr_ceiling_db},
                    {"compared_frames", s.compared_frames},
                    {"identical_frames", s.identical_frames},
                    {"peak_rss_mb", t.peak_rss_mb},
                    {"resident_before_mb", t.resident_before_mb},
                    {"gpu_resource_bytes", t.gpu_resource_bytes},
                    {"fallback_frames", t.fallback_frames},
                    {"from_bake", t.from_bake},
                    {"bake_s", t.bake_s},
                    {"load_s", t.load_s},
                    {"store_bytes", t.store_bytes}};
    if (s.compared_frames > 0) {  // none with --no-brute
      summary["psnr_db_mean"] = s.psnr_db_mean;
      summary["psnr_db_min"] = s.psnr_db_min;
    }
    if (s.supersampled_frames > 0) {
      summary["reference_supersample"] = options.reference_supersample;
      summary["psnr_supersampled_db_mean"] = s.psnr_supersampled_db_mean;
    }
    if (s.compared_frames > s.identical_frames) {
      summary["psnr_db_mean_differing"] = s.psnr_db_mean_differing;
      summary["psnr_db_pooled"] = s.psnr_db_pooled;
    }
    if (options.budget_ms > 0) {
      summary["frames_over_budget_1_1x"] = s.frames_over_budget_1_1x;
      summary["p99_to_budget"] = s.p99_to_budget;
    }
    if (s.occlusion_frames > 0) summary["occlusion_ms_median"] = s.occlusion_ms_median;
    if (s.predicted_frames > 0) {
      summary["predicted_frames"] = s.predicted_frames;
      summary["predicted_median_rel_error"] = s.predicted_median_rel_error;
    }
    if (report.pipelined && t.name != kRawBound)
      summary["pipelined"] = {{"median_ms", s.pipelined_median_ms},
                              {"p99_ms", s.pipelined_p99_ms},
                              {"latency_median_ms", s.pipelined_latency_median_ms}};
    // Triangles drawn from the technique's proxy mesh (colorcube: cube faces, two triangles
    // each, and the leaves' own triangles).
    uint64_t proxy_triangles = 0;
    for (const FrameRecord& f : t.frames) proxy_triangles += f.proxy_triangles;
    if (proxy_triangles > 0)
      summary["mean_proxy_triangles"] = double(proxy_triangles) / double(t.frames.size());
    if (&t != brute && brute) {
      summary["median_ratio_to_brute"] = s.median_ratio_to_brute;
      summary["triangle_ratio_to_brute"] = s.triangle_ratio_to_brute;
      summary["frames_slower_than_brute_1_1x"] = s.frames_slower_than_brute_1_1x;
    }
    json figures = json::object();
    for (const auto& [key, value] : t.figures) figures[key] = value;
    root["techniques"].push_back({{"name", t.name},
                                  {"description", t.description},
                                  {"figures", std::move(figures)},
                                  {"frames", std::move(frames)},
                                  {"summary", std::move(summary)}});
  }
  return root.dump(1) + "\n";
}

std::string format_bench_summary(const BenchReport& report) {
  const TechniqueRecord* brute = find_brute(report);
  std::string out;
  char line[320];
  std::snprintf(line, sizeof(line), "renderer: %s%s\n%-13s %9s %9s %9s %8s %12s %8s %10s %12s %9s",
                report.renderer.c_str(), report.interleaved ? " (techniques interleaved)" : "",
                "technique", "median_ms", "p99_ms", "max_ms", "x_brute", "mean_tris", "mean_draws",
                "psnr_db", "identical", "fallback");
  out += line;
  if (report.pipelined) {
    std::snprintf(line, sizeof(line), " %12s %12s", "pipelined_ms", "latency_ms");
    out += line;
  }
  if (report.budget_ms > 0) {
    std::snprintf(line, sizeof(line), " %10s %11s", "over_1.1x", "p99/budget");
    out += line;
  }
  out += " pred_err\n";
  bool fell_back = false;
  std::string supersampled;  // each technique's PSNR against brute supersampled, if measured
  for (const TechniqueRecord& t : report.techniques) {
    const BenchSummary s = summarize(t, brute, report.width, report.height, report.budget_ms);
    if (s.supersampled_frames > 0) {
      std::snprintf(line, sizeof(line), "%s %s %.2f", supersampled.empty() ? "" : ",",
                    t.name.c_str(), s.psnr_supersampled_db_mean);
      supersampled += line;
    }
    char psnr[32] = "-";
    if (s.compared_frames > s.identical_frames)
      std::snprintf(psnr, sizeof(psnr), "%.2f", s.psnr_db_mean_differing);
    char ratio[32] = "-";
    if (&t != brute && brute) std::snprintf(ratio, sizeof(ratio), "%.3f", s.median_ratio_to_brute);
    char fallback[32];
    const bool most = 2 * t.fallback_frames > t.frames.size();
    fell_back |= most;
    std::snprintf(fallback, sizeof(fallback), "%llu%s", (unsigned long long)t.fallback_frames,
                  most ? " (most)" : "");
    char identical[32] = "reference";
    if (&t != brute)
      std::snprintf(identical, sizeof(identical), "%u/%u", s.identical_frames, s.compared_frames);
    std::snprintf(line, sizeof(line), "%-13s %9.2f %9.2f %9.2f %8s %12.0f %10.1f %10s %12s %9s",
                  t.name.c_str(), s.median_ms, s.p99_ms, s.max_ms, ratio, s.mean_triangles,
                  s.mean_draw_calls, psnr, identical, fallback);
    out += line;
    if (report.pipelined && s.pipelined_median_ms > 0) {
      std::snprintf(line, sizeof(line), " %12.2f %12.2f", s.pipelined_median_ms,
                    s.pipelined_latency_median_ms);
      out += line;
    }
    if (report.budget_ms > 0) {
      std::snprintf(line, sizeof(line), " %9.1f%% %11.2f", 100.0 * s.frames_over_budget_1_1x,
                    s.p99_to_budget);
      out += line;
    }
    if (s.predicted_frames > 0) {
      std::snprintf(line, sizeof(line), " %7.1f%%", 100.0 * s.predicted_median_rel_error);
      out += line;
    } else {
      out += "        -";
    }
    out += "\n";
  }
  out +=
      "psnr_db: mean over the compared frames that differ from brute's; identical: compared "
      "frames equal to brute's, pixel for pixel; fallback: frames a technique drew as plain "
      "geometry (outside its bake; docs/bench.md); over_1.1x: frames over 1.1 x the budget; "
      "pred_err: median |predicted - measured| / measured frame time, where the technique "
      "predicts it\n";
  if (!supersampled.empty())
    out += "psnr_db against brute supersampled (mean over the compared frames, brute's own "
           "aliasing counted):" +
           supersampled + "\n";
  if (const auto& n = report.noise_floor) {
    std::snprintf(line, sizeof(line),
                  "noise floor: a fixed %.1f ms workload on %u threads, %u rounds: median %.2f "
                  "ms, %.1f%% over 1.1x it, p99 %.2fx (the machine's own, under any technique's)\n",
                  n->work_ms, n->threads, n->rounds, n->median_ms, 100.0 * n->over_1_1x,
                  n->p99_to_median);
    out += line;
  }
  if (fell_back)
    out +=
        "(most): the technique fell back on most frames, so its figures are mostly plain "
        "geometry's, not the technique's\n";
  return out;
}

}  // namespace farfield
