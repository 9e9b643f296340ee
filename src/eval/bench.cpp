#include "farfield/eval/bench.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>

#include <epoxy/gl.h>

#include "bench_report.hpp"
#include "farfield/core/atomic_file.hpp"
#include "farfield/eval/image_metrics.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/technique.hpp"
#include "farfield/eval/birdseye.hpp"
#include "frame_plot.hpp"

namespace farfield {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

double peak_rss_mb() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

Result<void> check_options(const BenchOptions& o, const CameraPath& path) {
  if (o.width < 16 || o.height < 16 || o.width > 16384 || o.height > 16384)
    return make_error("--width and --height must be within 16..16384 (got ",
                      std::to_string(o.width), "x", std::to_string(o.height), ")");
  if (!(o.hfov_deg > 1.0f && o.hfov_deg < 179.0f))
    return make_error("--hfov must be within (1, 179) degrees (got ", std::to_string(o.hfov_deg), ")");
  if (path.frames.empty()) return make_error("the camera path has no frames");
  if (o.techniques.empty()) return make_error("--technique names no technique");
  for (const std::string& name : o.techniques) {
    if (name == kRawBound) continue;
    if (auto t = make_technique(name, o.settings); !t) return t.error();
  }
  return {};
}

// Frames saved as PNG: spread evenly over the path, first and last included.
std::vector<uint32_t> sample_frames(uint32_t frames, uint32_t count) {
  std::vector<uint32_t> samples;
  for (uint32_t i = 0; i < count && frames > 0; ++i) {
    const uint32_t f = count == 1 ? 0 : uint32_t(uint64_t(i) * (frames - 1) / (count - 1));
    if (samples.empty() || samples.back() != f) samples.push_back(f);
  }
  return samples;
}

std::string frame_file(const std::string& dir, const std::string& technique, uint32_t frame,
                       const char* suffix) {
  char name[64];
  std::snprintf(name, sizeof(name), "_frame%04u%s.png", frame, suffix);
  return (std::filesystem::path(dir) / (technique + name)).string();
}

}  // namespace

Result<BenchReport> run_bench(const Scene& scene, const CameraPath& path,
                              const BenchOptions& options, Progress& progress) {
  if (auto ok = check_options(options, path); !ok) return ok.error();
  std::error_code ec;
  std::filesystem::create_directories(options.out_dir, ec);
  if (ec) return make_error(options.out_dir, ": cannot create the output folder: ", ec.message());

  std::optional<Store> store;
  if (!options.store_file.empty()) {
    auto opened = Store::open(options.store_file, Store::Mode::kRead);
    if (!opened) return opened.error();
    store.emplace(std::move(*opened));
  }
  auto context = gpu::create_headless_context();
  if (!context) return context.error();
  auto renderer = gpu::Renderer::create(scene);
  if (!renderer) return renderer.error();
  (*renderer)->set_offscreen(options.width, options.height);

  // Brute first: its frames are the reference of every other technique.
  std::vector<std::string> names{"brute"};
  for (const std::string& n : options.techniques)
    if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);

  const uint32_t frames = static_cast<uint32_t>(path.frames.size());
  const std::vector<uint32_t> samples = sample_frames(frames, options.sample_images);
  auto compared = [&](uint32_t f) {
    return (options.reference_every && f % options.reference_every == 0) ||
           std::binary_search(samples.begin(), samples.end(), f);
  };
  std::map<uint32_t, Image> reference;  // brute's frames that others are compared with

  BenchReport report;
  report.renderer = (*context)->renderer_name();
  DrawList list;
  for (const std::string& name : names) {
    TechniqueRecord record;
    record.name = name;
    std::unique_ptr<Technique> technique;
    if (name != kRawBound) {
      auto made = make_technique(name, options.settings);
      if (!made) return made.error();
      technique = std::move(*made);
      const auto start = Clock::now();
      if (auto ok = store ? technique->load_baked(scene, *store) : technique->load(scene); !ok)
        return ok.error();
      record.load_s = ms_since(start) / 1000.0;
      if (store) {
        auto bytes = store->total_bytes(name + "/");
        if (!bytes) return bytes.error();
        record.store_bytes = *bytes;
        auto bake_s = store->get_meta(name + "/bake_s");
        if (!bake_s) return bake_s.error();
        if (*bake_s) record.bake_s = std::strtod((*bake_s)->c_str(), nullptr);
      }
      record.description = technique->describe();
      const ProxyMesh* proxies = technique->proxies();
      if (auto ok = (*renderer)->set_proxies(proxies ? *proxies : ProxyMesh{}); !ok)
        return ok.error();
    } else {
      record.description = "all triangles in one indexed draw, no per-object work";
    }
    auto render = [&](const View& view, FrameRecord& f) {
      const auto start = Clock::now();
      gpu::FrameStats stats;
      if (technique) {
        technique->select(view, FrameBudget{}, list);
        f.cpu_ms = ms_since(start);
        f.proxy_triangles = list.proxy_triangle_count();
        stats = (*renderer)->draw(view, list);
      } else {
        stats = (*renderer)->draw_everything_at_once(view);
      }
      glFinish();
      f.frame_ms = ms_since(start);
      f.gpu_ms = stats.gpu_ms;
      f.triangles = stats.triangles;
      f.draw_calls = stats.draw_calls;
    };
    auto view_at = [&](uint32_t f) {
      View v;
      v.pose = path.frames[f];
      v.width = options.width;
      v.height = options.height;
      v.hfov_deg = options.hfov_deg;
      return v;
    };

    progress.start("bench " + name, frames);
    FrameRecord ignored;
    for (uint32_t w = 0; w < std::min(options.warmup_frames, frames); ++w) render(view_at(w), ignored);
    for (uint32_t f = 0; f < frames; ++f) {
      FrameRecord record_f;
      render(view_at(f), record_f);
      if (compared(f)) {  // outside the timed region
        Image image = (*renderer)->capture();
        const bool sample = std::binary_search(samples.begin(), samples.end(), f);
        if (name == "brute") {
          record_f.compared = true;
          record_f.psnr_db = compare_images(image, image).psnr_db;
          if (sample) {
            if (auto ok = write_png(image, frame_file(options.out_dir, name, f, "")); !ok)
              return ok.error();
          }
          reference[f] = std::move(image);
        } else {
          const Image& ref = reference.at(f);
          const ImageComparison c = compare_images(ref, image);
          record_f.compared = true;
          record_f.psnr_db = c.psnr_db;
          record_f.differing_pixels = c.differing_pixels;
          if (sample) {
            if (auto ok = write_png(image, frame_file(options.out_dir, name, f, "")); !ok)
              return ok.error();
            if (auto ok = write_png(difference_image(ref, image),
                                    frame_file(options.out_dir, name, f, "_diff"));
                !ok)
              return ok.error();
          }
        }
        if (sample && options.birdseye_height > 0) {
          // paper 000, Fig. 5-2: the same frame's selection seen from above.
          const View eye = view_at(f);
          if (technique) technique->annotate(eye, list);
          else list.clear();
          add_frustum_lines(eye, options.birdseye_height * 0.5f, list);
          const View above = birdseye_view(eye, options.birdseye_height);
          if (technique) (*renderer)->draw(above, list);
          else (*renderer)->draw_everything_at_once(above);
          if (auto ok = write_png((*renderer)->capture(),
                                  frame_file(options.out_dir, name, f, "_birdseye"));
              !ok)
            return ok.error();
        }
      }
      record.frames.push_back(record_f);
      progress.advance();
      if (technique) {
        if (std::string failure = technique->failure(); !failure.empty())
          return make_error(name, ": ", failure);
      }
    }
    progress.finish();
    if (technique) record.figures = technique->figures();  // after the run: counts included
    record.peak_rss_mb = peak_rss_mb();
    report.techniques.push_back(std::move(record));
  }

  const std::string json_path = (std::filesystem::path(options.out_dir) / "bench.json").string();
  if (auto ok = write_file_atomically(json_path, bench_json(report, options, scene, path)); !ok)
    return ok.error();
  if (options.plot) {
    const std::string png = (std::filesystem::path(options.out_dir) / "frame_times.png").string();
    if (auto ok = plot_frame_times(json_path, png); !ok) return ok.error();
  }
  return report;
}

}  // namespace farfield
