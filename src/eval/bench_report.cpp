#include "bench_report.hpp"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "bench_summary.hpp"

namespace farfield {

namespace {

using nlohmann::json;

// Infinite PSNR (identical images) has no JSON number: it is written as null.
json decibels(double db) { return std::isfinite(db) ? json(db) : json(nullptr); }

const TechniqueRecord* find_brute(const BenchReport& report) {
  for (const auto& t : report.techniques)
    if (t.name == "brute") return &t;
  return nullptr;
}

}  // namespace

std::string bench_json(const BenchReport& report, const BenchOptions& options,
                       const Scene& scene, const CameraPath& path) {
  json root;
  root["scene"] = {{"file", options.scene_file},
                   {"triangles", scene.triangle_count()},
                   {"objects", scene.objects.size()}};
  root["path"] = {{"kind", path.kind}, {"frames", path.frames.size()}};
  root["width"] = options.width;
  root["height"] = options.height;
  root["hfov_deg"] = options.hfov_deg;
  root["renderer"] = report.renderer;
  root["warmup_frames"] = options.warmup_frames;
  root["techniques"] = json::array();
  const TechniqueRecord* brute = find_brute(report);
  for (const TechniqueRecord& t : report.techniques) {
    json frames = json::array();
    for (const FrameRecord& f : t.frames) {
      json frame = {{"frame_ms", f.frame_ms},   {"cpu_ms", f.cpu_ms},
                    {"gpu_ms", f.gpu_ms},       {"triangles", f.triangles},
                    {"draw_calls", f.draw_calls}, {"proxy_triangles", f.proxy_triangles}};
      if (f.compared) {
        frame["psnr_db"] = decibels(f.psnr_db);
        frame["identical"] = f.differing_pixels == 0;
        frame["differing_pixels"] = f.differing_pixels;
      }
      frames.push_back(std::move(frame));
    }
    const BenchSummary s = summarize(t, brute);
    json summary = {{"median_ms", s.median_ms},
                    {"p95_ms", s.p95_ms},
                    {"p99_ms", s.p99_ms},
                    {"max_ms", s.max_ms},
                    {"mean_ms", s.mean_ms},
                    {"mean_triangles", s.mean_triangles},
                    {"mean_draw_calls", s.mean_draw_calls},
                    {"psnr_db_mean", decibels(s.psnr_db_mean)},
                    {"psnr_db_min", decibels(s.psnr_db_min)},
                    {"compared_frames", s.compared_frames},
                    {"identical_frames", s.identical_frames},
                    {"peak_rss_mb", t.peak_rss_mb},
                    {"bake_s", t.bake_s},
                    {"load_s", t.load_s},
                    {"store_bytes", t.store_bytes}};
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
  char line[256];
  std::snprintf(line, sizeof(line), "renderer: %s\n%-13s %9s %9s %9s %8s %12s %8s %10s %12s\n",
                report.renderer.c_str(), "technique", "median_ms", "p99_ms", "max_ms", "x_brute",
                "triangles", "draws", "psnr_db", "identical");
  out += line;
  for (const TechniqueRecord& t : report.techniques) {
    const BenchSummary s = summarize(t, brute);
    char psnr[32] = "-";
    if (s.compared_frames > s.identical_frames) std::snprintf(psnr, sizeof(psnr), "%.2f", s.psnr_db_mean);
    char ratio[32] = "-";
    if (&t != brute && brute) std::snprintf(ratio, sizeof(ratio), "%.3f", s.median_ratio_to_brute);
    std::snprintf(line, sizeof(line), "%-13s %9.2f %9.2f %9.2f %8s %12.0f %8.1f %10s %7u/%-4u\n",
                  t.name.c_str(), s.median_ms, s.p99_ms, s.max_ms, ratio, s.mean_triangles,
                  s.mean_draw_calls, psnr, s.identical_frames, s.compared_frames);
    out += line;
  }
  return out;
}

}  // namespace farfield
