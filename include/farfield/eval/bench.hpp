// The benchmark runner (DESIGN.md, "The benchmark protocol"): plays a camera path without a
// window for each named technique, times every frame from the start of selection to the end
// of drawing (glFinish), measures image error against brute force, and writes DIR/bench.json,
// sample frames, their difference images against brute and a frame-time plot.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "farfield/core/camera_path.hpp"
#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/techniques/technique.hpp"

namespace farfield {

// `raw` is not a technique: it is the bound of the protocol, all the scene's triangles in one
// indexed draw with the same shading and no per-object work.
inline constexpr const char* kRawBound = "raw";

struct BenchOptions {
  std::string scene_file;               // for the report
  std::string store_file;               // a .ffpack from `farfield bake`; empty: load in memory
  std::vector<std::string> techniques;  // brute is always run (first) as the reference
  TechniqueSettings settings;           // --set NAME.KEY=VALUE
  int width = 1024, height = 768;
  float hfov_deg = 90.0f;
  std::string out_dir;
  uint32_t warmup_frames = 3;    // drawn before timing, untimed
  uint32_t reference_every = 10;  // compare with brute every N frames (and on sample frames)
  uint32_t sample_images = 3;    // frames saved as PNG per technique, spread over the path
  bool plot = true;              // frame_times.png through python3-matplotlib
  float birdseye_height = 0;     // > 0: also a bird's-eye picture of each sample frame
};

struct FrameRecord {
  double frame_ms = 0, cpu_ms = 0, gpu_ms = 0;
  uint64_t triangles = 0, draw_calls = 0;
  uint64_t proxy_triangles = 0;  // of the triangles, stand-ins (two per colour-cube face)
  bool compared = false;  // a brute reference exists for this frame
  double psnr_db = 0;     // infinite when identical
  uint64_t differing_pixels = 0;
};

struct TechniqueRecord {
  std::string name, description;
  std::vector<std::pair<std::string, double>> figures;  // Technique::figures()
  double load_s = 0;
  double bake_s = 0;         // the last `farfield bake` run into the pack (its meta NAME/bake_s)
  uint64_t store_bytes = 0;  // the technique's blobs in the pack (NAME/...)
  double peak_rss_mb = 0;
  std::vector<FrameRecord> frames;
};

struct BenchReport {
  std::string renderer;  // GL_RENDERER
  std::vector<TechniqueRecord> techniques;
};

Result<BenchReport> run_bench(const Scene& scene, const CameraPath& path,
                              const BenchOptions& options, Progress& progress);

// The summary table printed after a run: one line per technique.
std::string format_bench_summary(const BenchReport& report);

}  // namespace farfield
