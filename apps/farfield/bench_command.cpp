// farfield bench SCENE --path path.json --technique brute,octree --out DIR
#include <algorithm>
#include <cstdio>

#include "commands.hpp"
#include "large_pages.hpp"
#include "farfield/scene/chunked_scene.hpp"
#include "farfield/core/camera_path.hpp"
#include "farfield/core/text.hpp"
#include "farfield/core/view.hpp"
#include "farfield/eval/bench.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield::cli {

void add_bench_command(CLI::App& root, std::vector<Command>& commands) {
  struct Settings {
    BenchOptions bench;
    std::string path;
    std::vector<std::string> techniques{"brute", "octree"};
    std::vector<std::string> settings;
    bool quiet = false, no_plot = false, no_brute = false;
    size_t frames = 0;
    std::vector<float> light;  // heading, elevation
  };
  auto s = std::make_shared<Settings>();
  const std::string technique_help =
      "Techniques to compare, comma-separated; brute always runs "
      "first as the reference. 'raw' adds the protocol's bound "
      "(every triangle in one draw). Known (their settings: farfield techniques):\n" +
      techniques_help(false);
  CLI::App* cmd = root.add_subcommand(
      "bench",
      "Play a camera path headless for each technique; write DIR/bench.json, sample "
      "frames, difference images against brute and a frame-time plot");
  cmd->add_option("scene", s->bench.scene_file, "A .ffscene file")->required();
  cmd->add_option("--store", s->bench.store_file,
                  "A .ffpack from 'farfield bake': techniques load their bake from it");
  cmd->add_option("--path", s->path, "Camera path (farfield path ... --out path.json)")->required();
  CLI::Option* technique_option = cmd->add_option("--technique,-t", s->techniques, technique_help)
                                      ->delimiter(',')
                                      ->capture_default_str();
  cmd->add_option("--set", s->settings,
                  "Technique setting TECHNIQUE.KEY=VALUE, repeatable (e.g. colorcube.depth=6)");
  cmd->add_option("--frames", s->frames, "Play only the path's first N frames (0: all)")
      ->check(CLI::Range(size_t(0), size_t(1) << 24))
      ->capture_default_str();
  cmd->add_option("--width", s->bench.width, "Image width, pixels")
      ->check(CLI::Range(kMinImageSide, kMaxImageSide))
      ->capture_default_str();
  cmd->add_option("--height", s->bench.height, "Image height, pixels")
      ->check(CLI::Range(kMinImageSide, kMaxImageSide))
      ->capture_default_str();
  cmd->add_option("--hfov", s->bench.hfov_deg, "Horizontal field of view, degrees")
      ->check(number_range(kMinHfovDeg, kMaxHfovDeg))
      ->capture_default_str();
  cmd->add_option("--warmup", s->bench.warmup_frames, "Untimed frames drawn first")
      ->check(CLI::Range(0u, 1000u))
      ->capture_default_str();
  cmd->add_option("--reference-every", s->bench.reference_every,
                  "Compare with brute every N frames (0: sample frames only)")
      ->capture_default_str();
  cmd->add_option("--reference-supersample", s->bench.reference_supersample,
                  "N > 1: also compare the compared frames with brute drawn at N times the width "
                  "and height, each N x N block averaged (an antialiased reference, against "
                  "which brute's own aliasing counts too): psnr_supersampled_db")
      ->check(CLI::Range(1, 4))
      ->capture_default_str();
  cmd->add_flag("--no-brute", s->no_brute,
                "Leave brute force out: nothing compared, no x_brute; for timing techniques on "
                "their own where brute force is too slow (sample frames still saved)");
  cmd->add_option("--samples", s->bench.sample_images, "Frames saved as PNG per technique")
      ->check(CLI::Range(0u, 1000u))
      ->capture_default_str();
  cmd->add_option("--birdseye", s->bench.birdseye_height,
                  "Also save a bird's-eye picture of each sample frame from this many metres "
                  "above the eye (frustum in red; stratified adds its viewcell and box)")
      ->check(number_range(0, 100000));
  cmd->add_option("--light", s->light,
                  "HEADING,ELEVATION: the two lights (opposite headings) turned and raised to "
                  "these degrees, for every technique alike (default 30,14); images baked "
                  "earlier keep their light")
      ->expected(2)
      ->delimiter(',');
  cmd->add_option("--budget-ms", s->bench.budget_ms,
                  "Frame-time budget for every technique, ms (0: none); techniques that hold a "
                  "frame time read it")
      ->check(number_range(0, 10000));
  cmd->add_flag("--interleave", s->bench.interleave,
                "Time the techniques frame by frame (frame f of each, then f+1), so that drift "
                "on a shared machine falls on all alike; peak_rss_mb is then the process's");
  cmd->add_flag("--pipelined", s->bench.pipelined,
                "Run each technique's path a second time with selection one frame ahead on a "
                "second thread; report its frame time and latency beside the first run's");
  cmd->add_flag("--noise-floor", s->bench.noise_floor,
                "Before the techniques, time a fixed workload of the budget's length (30 ms "
                "without one) on every core once per path frame, and report its share of "
                "rounds over 1.1x its median: the machine's own noise, under any technique's");
  cmd->add_flag("--expand-instances", s->bench.expand_instances,
                "Upload every instance (an object repeating another's model, docs/scene.md) as "
                "geometry of its own instead of drawing it from its prototype's, to compare");
  cmd->add_option("--cache-mb", s->bench.cache_mb,
                  "Leave the scene's geometry in its file and walk it through a cache of this "
                  "many MB of GPU meshes, read on demand on a background thread: scenes larger "
                  "than memory (techniques that stream: brute); 0: read the scene whole")
      ->check(CLI::Range(uint64_t(0), uint64_t(1) << 20));
  cmd->add_flag("--no-plot", s->no_plot, "Skip the frame-time plot (needs python3-matplotlib)");
  cmd->add_option("--out,-o", s->bench.out_dir, "Output folder")->required();
  cmd->add_flag("--quiet,-q", s->quiet, "Do not show progress");
  commands.push_back({cmd, [s, technique_option] {
                        use_large_pages();
                        // With --cache-mb the default is what streams.
                        if (s->bench.cache_mb > 0 && technique_option->count() == 0)
                          s->techniques = {"brute"};
                        s->bench.techniques = s->techniques;
                        for (const std::string& setting : s->settings)
                          if (auto ok = s->bench.settings.add(setting); !ok)
                            return usage_error(ok.error().message);
                        s->bench.plot = !s->no_plot;
                        s->bench.brute = !s->no_brute;
                        if (s->bench.reference_supersample > 1 && !s->bench.brute)
                          return usage_error(
                              "--reference-supersample needs brute's frames: not with --no-brute");
                        if (std::max(s->bench.width, s->bench.height) *
                                s->bench.reference_supersample >
                            kMaxImageSide)
                          return usage_error(formatted(
                              "--reference-supersample %d: %dx%d frames drawn at %dx%d, over "
                              "%d pixels a side",
                              s->bench.reference_supersample, s->bench.width, s->bench.height,
                              s->bench.width * s->bench.reference_supersample,
                              s->bench.height * s->bench.reference_supersample, kMaxImageSide));
                        if (s->light.size() == 2) {
                          s->bench.light_heading_deg = s->light[0];
                          s->bench.light_elevation_deg = s->light[1];
                        }
                        auto path = read_camera_path(s->path);
                        if (!path) return fail(path.error().message);
                        if (s->frames > path->frames.size())
                          return fail("--frames " + std::to_string(s->frames) + ": " + s->path +
                                      " has only " + counted(path->frames.size(), "frame"));
                        if (s->frames > 0) path->frames.resize(s->frames);
                        std::optional<ChunkedScene> on_disk;
                        std::optional<Scene> in_memory;
                        if (s->bench.cache_mb > 0) {
                          auto opened = ChunkedScene::open(s->bench.scene_file);
                          if (!opened) return fail(opened.error().message);
                          on_disk.emplace(std::move(*opened));
                        } else {
                          auto read = read_scene(s->bench.scene_file);
                          if (!read) return fail(read.error().message);
                          in_memory.emplace(std::move(*read));
                        }
                        Progress progress(s->quiet);
                        auto report =
                            run_bench(on_disk ? on_disk->index() : *in_memory, *path, s->bench,
                                      progress, on_disk ? &*on_disk : nullptr);
                        progress.finish();
                        if (!report) return fail(report.error().message);
                        std::fputs(format_bench_summary(*report).c_str(), stdout);
                        std::printf("report: %s/bench.json\n", s->bench.out_dir.c_str());
                        return 0;
                      }});
}

}  // namespace farfield::cli
