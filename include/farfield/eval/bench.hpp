// The benchmark runner (DESIGN.md, "The benchmark protocol"): plays a camera path without a
// window for each named technique, times every frame from the start of selection to the end
// of drawing (glFinish), measures image error against brute force, and writes DIR/bench.json,
// sample frames, their difference images against brute and a frame-time plot.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "farfield/core/camera_path.hpp"
#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/eval/timing_noise.hpp"
#include "farfield/gpu/lighting.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

class ChunkedScene;

// `raw` is not a technique: it is the bound of the protocol, all the scene's triangles in one
// indexed draw with the same shading and no per-object work.
inline constexpr const char* kRawBound = "raw";

struct BenchOptions {
  std::string scene_file;               // for the report
  std::string store_file;               // a .ffpack from `farfield bake`; empty: load in memory
  std::vector<std::string> techniques;  // brute is run first as the reference (unless !brute)
  // false: brute force left out (--no-brute): nothing compared, no ratio to brute; for timing
  // techniques on their own where brute force is too slow to walk (a 100M-triangle scene).
  bool brute = true;
  TechniqueSettings settings;           // --set NAME.KEY=VALUE
  int width = 1024, height = 768;
  float hfov_deg = 90.0f;
  std::string out_dir;
  uint32_t warmup_frames = 3;     // drawn before timing, untimed
  uint32_t reference_every = 10;  // compare with brute every N frames (and on sample frames)
  // > 1: the compared frames are also compared with brute drawn at this many times the width
  // and height, each block of N x N pixels averaged (an antialiased reference, against which
  // brute's own aliasing counts as error too): FrameRecord::psnr_supersampled_db.
  int reference_supersample = 1;
  uint32_t sample_images = 3;     // frames saved as PNG per technique, spread over the path
  bool plot = true;               // frame_times.png through python3-matplotlib
  float birdseye_height = 0;      // > 0: also a bird's-eye picture of each sample frame
  double budget_ms = 0;           // the engine's frame-time budget for every technique; 0: none
  // The lights' heading and elevation, degrees (gpu/lighting.hpp), for every technique and
  // brute alike; baked images keep the light they were baked with.
  float light_heading_deg = gpu::kLightHeadingDeg, light_elevation_deg = gpu::kLightElevationDeg;
  // Time the techniques frame by frame (frame f of each, then f + 1), so that drift on a
  // shared machine falls on all alike; all are loaded at once and peak_rss_mb is the process's.
  bool interleave = false;
  // After each technique's run, the path again with selection one frame ahead on a second
  // thread (FrameLoop::run_pipelined); its figures beside the first run's.
  bool pipelined = false;
  // Before the techniques, the machine's own noise (timing_noise.hpp): a fixed workload of the
  // budget's length (30 ms without one) on every core, timed once per path frame.
  bool noise_floor = false;
  // > 0: the scene's geometry stays in its file (run_bench's `on_disk`) and the techniques
  // walk it through a cache of this many MB of GPU meshes (--cache-mb).
  uint64_t cache_mb = 0;
  // Upload every instance as geometry of its own instead of drawing it from its prototype's
  // (gpu::InstanceDrawing::expanded), for comparison (--expand-instances).
  bool expand_instances = false;
};

struct FrameRecord {
  double frame_ms = 0, cpu_ms = 0, gpu_ms = 0;
  uint64_t triangles = 0, draw_calls = 0;
  uint64_t proxy_triangles = 0;  // of the triangles, technique meshes (two per cube face)
  bool compared = false;         // a brute reference exists for this frame
  double psnr_db = 0;            // infinite when identical
  // Against brute supersampled (BenchOptions::reference_supersample > 1); brute's frames too.
  double psnr_supersampled_db = 0;
  uint64_t differing_pixels = 0;
  double pipelined_frame_ms = 0, pipelined_latency_ms = 0;  // BenchOptions::pipelined
  double predicted_ms = -1;  // the technique's own prediction of frame_ms; < 0: none
  double occlusion_ms = -1;  // of cpu_ms, occlusion culling; < 0: none
  double upload_ms = 0;      // of frame_ms, the renderer taking in the list's uploads
};

struct TechniqueRecord {
  std::string name, description;
  std::vector<std::pair<std::string, double>> figures;  // Technique::figures()
  double load_s = 0;
  bool from_bake = false;    // loaded from the pack's bake
  double bake_s = 0;         // the bake that made it (the pack's bake record)
  uint64_t store_bytes = 0;  // the technique's blobs in the pack (NAME/...)
  // Sequential runs: the peak resident memory while the technique loaded and ran, less what
  // was resident before it loaded (scene, renderer, the reference frames); interleaved
  // runs: the process's peak.
  double peak_rss_mb = 0;
  double resident_before_mb = 0;
  uint64_t gpu_resource_bytes = 0;  // its meshes and textures in the renderer
  uint64_t fallback_frames = 0;     // Technique::fallback_frames over the path
  std::vector<FrameRecord> frames;
};

struct BenchReport {
  std::string renderer;                  // GL_RENDERER
  uint64_t scene_texture_gpu_bytes = 0;  // the scene's texture arrays, mipmaps included
  uint64_t scene_geometry_gpu_bytes = 0;  // the scene's own vertex, index and uv buffers
  uint64_t instances_placed = 0;          // instances drawn from their prototypes' geometry
  uint64_t scene_triangles = 0;          // in memory or left on disk
  bool interleaved = false, pipelined = false;
  int width = 0, height = 0;
  double budget_ms = 0;  // BenchOptions::budget_ms
  std::optional<TimingNoise> noise_floor;  // BenchOptions::noise_floor
  std::vector<TechniqueRecord> techniques;
};

// `on_disk`: the scene's geometry left in its file (options.cache_mb > 0); `scene` is then its
// index, without geometry.
Result<BenchReport> run_bench(const Scene& scene, const CameraPath& path,
                              const BenchOptions& options, Progress& progress,
                              const ChunkedScene* on_disk = nullptr);

// The summary table printed after a run: one line per technique.
std::string format_bench_summary(const BenchReport& report);

}  // namespace farfield
