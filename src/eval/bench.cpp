#include "farfield/eval/bench.hpp"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include "bench_report.hpp"
#include "farfield/core/text.hpp"
#include "farfield/core/assert.hpp"
#include "farfield/core/atomic_file.hpp"
#include "farfield/eval/chunked_reference.hpp"
#include "farfield/eval/frame_loop.hpp"
#include "farfield/core/image_pyramid.hpp"
#include "farfield/eval/image_metrics.hpp"
#include "farfield/eval/run_plan.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/chunked_scene.hpp"
#include "farfield/store/store.hpp"
#include "frame_plot.hpp"

namespace farfield {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Resident memory from /proc/self/status: "VmRSS" now, "VmHWM" the peak since the last reset.
double status_mb(const char* field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.compare(0, std::strlen(field), field) == 0 && line[std::strlen(field)] == ':')
      return std::strtod(line.c_str() + std::strlen(field) + 1, nullptr) / 1024.0;  // kB
  return 0.0;
}

// Starts a new peak (Linux: writing 5 to clear_refs resets VmHWM to the current RSS), after
// handing freed heap back to the system so that an earlier technique's peak is not counted.
void reset_peak_memory() {
  ::malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";
}

Result<void> check_options(const BenchOptions& o, const CameraPath& path) {
  if (o.width < kMinImageSide || o.height < kMinImageSide || o.width > kMaxImageSide ||
      o.height > kMaxImageSide)
    return make_error("--width and --height must be within 16..16384 (got ",
                      std::to_string(o.width), "x", std::to_string(o.height), ")");
  if (!(o.hfov_deg >= kMinHfovDeg && o.hfov_deg <= kMaxHfovDeg))
    return make_error("--hfov must be within [1, 179] degrees (got ", number_text(o.hfov_deg), ")");
  if (path.frames.empty()) return make_error("the camera path has no frames");
  if (o.techniques.empty()) return make_error("--technique names no technique");
  if (!(o.budget_ms >= 0.0 && o.budget_ms <= 10000.0))
    return make_error("--budget-ms must be within 0..10000 ms");
  if (!(std::abs(o.light_heading_deg) <= 360.0f && std::abs(o.light_elevation_deg) <= 90.0f))
    return make_error("--light: a heading within -360..360 and an elevation within -90..90 "
                      "degrees (got ",
                      number_text(o.light_heading_deg), ", ", number_text(o.light_elevation_deg),
                      ")");
  if (o.interleave && o.pipelined)
    return make_error(
        "--interleave and --pipelined cannot be combined: a pipelined run "
        "overlaps one technique's frames, an interleaved one alternates them");
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

// Removes what an earlier bench wrote into `dir` (bench.json, the plot, NAME_frameNNNN*.png),
// so that a reused folder holds this run's files only; other files are left alone.
void remove_earlier_outputs(const std::string& dir) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const size_t at = name.rfind("_frame");
    const bool frame_image = at != std::string::npos && name.ends_with(".png") &&
                             name.size() >= at + 10 &&
                             std::all_of(name.begin() + at + 6, name.begin() + at + 10,
                                         [](char c) { return c >= '0' && c <= '9'; });
    if (entry.is_regular_file(ec) &&
        (frame_image || name == "bench.json" || name == "frame_times.png"))
      std::filesystem::remove(entry.path(), ec);
  }
}

// One technique (or the raw bound, technique == null) in a run.
struct Entry {
  std::unique_ptr<Technique> technique;
  TechniqueRecord record;
  FrameTiming last;               // for the next frame's budget
  uint64_t gpu_bytes_before = 0;  // the renderer's resources before the technique loaded
};

class BenchRun {
 public:
  BenchRun(const Scene& scene, const CameraPath& path, const BenchOptions& options,
           const Store* store, const std::vector<PlannedTechnique>& plan, gpu::Renderer& renderer,
           Progress& progress, const ChunkedScene* on_disk)
      : scene_(scene),
        on_disk_(on_disk),
        path_(path),
        o_(options),
        store_(store),
        plan_(plan),
        renderer_(renderer),
        loop_(renderer),
        progress_(progress),
        samples_(sample_frames(uint32_t(path.frames.size()), options.sample_images)) {}

  Result<std::vector<TechniqueRecord>> run(const std::vector<std::string>& names) {
    std::vector<TechniqueRecord> records;
    if (o_.interleave) {
      std::vector<Entry> entries;
      for (const std::string& name : names) {
        entries.emplace_back();
        if (auto ok = load(name, entries.back()); !ok) return ok.error();
      }
      for (Entry& e : entries) warm_up(e);
      progress_.start("bench " + std::to_string(names.size()) + " techniques, interleaved",
                      frames());
      for (uint32_t f = 0; f < frames(); ++f) {
        for (Entry& e : entries)
          if (auto ok = frame(e, f); !ok) return ok.error();
        progress_.advance();
      }
      progress_.finish();
      for (Entry& e : entries) {
        finish(e);
        e.record.peak_rss_mb = status_mb("VmHWM");
        records.push_back(std::move(e.record));
      }
      return records;
    }
    for (const std::string& name : names) {
      reset_peak_memory();
      const double before = status_mb("VmRSS");
      Entry e;
      if (auto ok = load(name, e); !ok) return ok.error();
      warm_up(e);
      progress_.start("bench " + name, frames());
      for (uint32_t f = 0; f < frames(); ++f) {
        if (auto ok = frame(e, f); !ok) return ok.error();
        progress_.advance();
      }
      progress_.finish();
      if (o_.pipelined && e.technique)
        if (auto ok = pipelined(e); !ok) return ok.error();
      finish(e);
      e.record.resident_before_mb = before;
      e.record.peak_rss_mb = std::max(0.0, status_mb("VmHWM") - before);
      records.push_back(std::move(e.record));
    }
    return records;
  }

 private:
  uint32_t frames() const { return uint32_t(path_.frames.size()); }

  View view_at(uint64_t f) const {
    View v;
    v.pose = path_.frames[f];
    v.width = o_.width;
    v.height = o_.height;
    v.hfov_deg = o_.hfov_deg;
    v.near_m = near_plane_for(scene_.bounds);
    return v;
  }

  bool compared(uint32_t f) const {
    return o_.brute && ((o_.reference_every && f % o_.reference_every == 0) || sample(f));
  }
  bool sample(uint32_t f) const { return std::binary_search(samples_.begin(), samples_.end(), f); }

  Result<void> load(const std::string& name, Entry& e) {
    e.record.name = name;
    if (name == kRawBound) {
      e.record.description = "all triangles in one indexed draw, no per-object work";
      return {};
    }
    auto made = make_technique(name, o_.settings);
    if (!made) return made.error();
    e.technique = std::move(*made);
    const auto planned = std::find_if(plan_.begin(), plan_.end(), [&](const PlannedTechnique& p) {
      return p.descriptor->name == name;
    });
    if (planned != plan_.end() && planned->bake) {
      e.record.from_bake = true;
      e.record.bake_s = planned->bake->bake_s;
    }
    if (store_) {
      auto bytes = store_->total_bytes(name + "/");
      if (!bytes) return bytes.error();
      e.record.store_bytes = *bytes;
    }
    e.gpu_bytes_before = renderer_.resource_bytes();
    const auto start = Clock::now();
    Progress quiet(true);
    if (auto ok = e.technique->load(
            {scene_, store_, renderer_, quiet, on_disk_, o_.cache_mb * 1000000});
        !ok)
      return ok.error();
    e.record.load_s = seconds_since(start);
    e.record.description = e.technique->describe();
    return {};
  }

  FrameTiming draw(Entry& e, uint64_t f) {
    if (!e.technique) return loop_.run_raw(view_at(f));
    return loop_.run(*e.technique, view_at(f), f, next_budget(o_.budget_ms, e.last));
  }

  void warm_up(Entry& e) {
    for (uint32_t w = 0; w < std::min(o_.warmup_frames, frames()); ++w) e.last = draw(e, w);
  }

  // Compares frame f as drawn with brute's (capturing brute's as the reference).
  Result<void> compare(Entry& e, uint32_t f, FrameRecord& record, bool save) {
    Image image = renderer_.capture();
    record.compared = true;
    const std::string& name = e.record.name;
    if (name == "brute" && on_disk_) {
      // A walk of a scene on disk may draw a frame before all of it is loaded: the reference
      // is brute force's complete frame, drawn in parts through the same cache's bytes, and
      // brute's own frame is compared with it.
      if (auto ok = draw_chunked_reference(renderer_, *on_disk_, view_at(f), o_.cache_mb * 1000000);
          !ok)
        return make_error("brute's reference: ", ok.error().message);
      Image reference = renderer_.capture();
      const ImageComparison c = compare_images(reference, image);
      record.psnr_db = c.psnr_db;
      record.differing_pixels = c.differing_pixels;
      if (save) {
        if (auto ok = write_png(reference, frame_file(o_.out_dir, name, f, "_reference")); !ok)
          return ok;
        if (auto ok = write_png(image, frame_file(o_.out_dir, name, f, "")); !ok) return ok;
      }
      reference_[f] = std::move(reference);
      return supersample(e, f, image, record);
    }
    if (name == "brute") {
      record.psnr_db = compare_images(image, image).psnr_db;
      if (save)
        if (auto ok = write_png(image, frame_file(o_.out_dir, name, f, "")); !ok) return ok;
      if (auto ok = supersample(e, f, image, record); !ok) return ok;
      reference_[f] = std::move(image);
      return {};
    }
    const Image& ref = reference_.at(f);
    const ImageComparison c = compare_images(ref, image);
    record.psnr_db = c.psnr_db;
    record.differing_pixels = c.differing_pixels;
    if (auto it = supersampled_.find(f); it != supersampled_.end())
      record.psnr_supersampled_db = compare_images(it->second, image).psnr_db;
    if (!save) return {};
    if (auto ok = write_png(image, frame_file(o_.out_dir, name, f, "")); !ok) return ok;
    return write_png(difference_image(ref, image), frame_file(o_.out_dir, name, f, "_diff"));
  }

  // With reference_supersample > 1, brute's frame f drawn at that many times the width and
  // height and box-filtered back to the frame's size: kept as the antialiased reference, and
  // brute's own `image` compared with it.
  Result<void> supersample(Entry& brute, uint32_t f, const Image& image, FrameRecord& record) {
    const int k = o_.reference_supersample;
    if (k <= 1) return {};
    View large = view_at(f);
    large.width *= k;
    large.height *= k;
    renderer_.set_offscreen(large.width, large.height);
    Result<void> drawn = {};
    if (on_disk_)
      drawn = draw_chunked_reference(renderer_, *on_disk_, large, o_.cache_mb * 1000000);
    else
      loop_.run(*brute.technique, large, f, FrameBudget{});
    Image reference = drawn ? renderer_.capture() : Image();
    renderer_.set_offscreen(o_.width, o_.height);
    if (!drawn) return make_error("brute's supersampled reference: ", drawn.error().message);
    reference = box_downsample(reference, k);
    if (sample(f))
      if (auto ok = write_png(reference, frame_file(o_.out_dir, "brute", f, "_supersampled")); !ok)
        return ok;
    record.psnr_supersampled_db = compare_images(reference, image).psnr_db;
    supersampled_[f] = std::move(reference);
    return {};
  }

  Result<void> frame(Entry& e, uint32_t f) {
    const FrameTiming t = draw(e, f);
    e.last = t;
    FrameRecord r;
    r.frame_ms = t.frame_ms;
    r.cpu_ms = t.select_ms;
    r.gpu_ms = t.gpu_ms;
    r.triangles = t.triangles;
    r.draw_calls = t.draw_calls;
    r.proxy_triangles = t.mesh_triangles;
    r.predicted_ms = t.predicted_ms;
    r.occlusion_ms = t.occlusion_ms;
    r.upload_ms = t.upload_ms;
    if (!o_.brute && sample(f))  // outside the timed region
      if (auto ok = write_png(renderer_.capture(), frame_file(o_.out_dir, e.record.name, f, ""));
          !ok)
        return ok;
    if (compared(f)) {  // outside the timed region
      if (auto ok = compare(e, f, r, sample(f)); !ok) return ok;
      if (sample(f) && o_.birdseye_height > 0) {
        // paper 000, Fig. 5-2: the same frame's selection seen from above.
        loop_.draw_birdseye(e.technique.get(), view_at(f), o_.birdseye_height);
        if (auto ok = write_png(renderer_.capture(),
                                frame_file(o_.out_dir, e.record.name, f, "_birdseye"));
            !ok)
          return ok;
      }
    }
    e.record.frames.push_back(r);
    if (e.technique)
      if (std::string failure = e.technique->failure(); !failure.empty())
        return make_error(e.record.name, ": ", failure);
    return {};
  }

  // The path again with selection one frame ahead; compared frames checked again (the same
  // selection must give the same pixels), nothing saved.
  Result<void> pipelined(Entry& e) {
    progress_.start("bench " + e.record.name + " pipelined", frames());
    std::optional<Error> error;
    loop_.run_pipelined(
        *e.technique, 0, frames(), [&](uint64_t f) { return view_at(f); },
        FrameBudget{o_.budget_ms, 0, 0, 0},
        [&](uint64_t f, const FrameTiming& t) {
          FrameRecord& r = e.record.frames[f];
          r.pipelined_frame_ms = t.frame_ms;
          r.pipelined_latency_ms = t.latency_ms;
          if (!error && compared(uint32_t(f)) && e.record.name != "brute") {
            FrameRecord again;
            if (auto ok = compare(e, uint32_t(f), again, false); !ok)
              error = ok.error();
            else if (again.differing_pixels != r.differing_pixels)
              error = make_error(e.record.name, ": frame ", std::to_string(f),
                                 " drawn pipelined differs from the same frame drawn in turn");
          }
          progress_.advance();
        });
    progress_.finish();
    if (error) return *error;
    if (std::string failure = e.technique->failure(); !failure.empty())
      return make_error(e.record.name, ": ", failure);
    return {};
  }

  void finish(Entry& e) {
    if (!e.technique) return;
    e.record.figures = e.technique->figures();  // after the run: counts included
    e.record.fallback_frames = e.technique->fallback_frames();
    // After the run: textures are sized by their uploads.
    e.record.gpu_resource_bytes = renderer_.resource_bytes() - e.gpu_bytes_before;
  }

  const Scene& scene_;
  const ChunkedScene* on_disk_;
  const CameraPath& path_;
  const BenchOptions& o_;
  const Store* store_;
  const std::vector<PlannedTechnique>& plan_;
  gpu::Renderer& renderer_;
  FrameLoop loop_;
  Progress& progress_;
  const std::vector<uint32_t> samples_;
  std::map<uint32_t, Image> reference_;  // brute's frames that others are compared with
  std::map<uint32_t, Image> supersampled_;  // the same supersampled (reference_supersample)
};

}  // namespace

Result<BenchReport> run_bench(const Scene& scene, const CameraPath& path,
                              const BenchOptions& options, Progress& progress,
                              const ChunkedScene* on_disk) {
  // Everything asked is checked before the first frame or file.
  if (auto ok = check_options(options, path); !ok) return ok.error();
  FF_ASSERT((on_disk != nullptr) == (options.cache_mb > 0), "cache of %llu MB, scene %s disk",
            (unsigned long long)options.cache_mb, on_disk ? "on" : "not on");
  if (on_disk && std::find(options.techniques.begin(), options.techniques.end(),
                           std::string(kRawBound)) != options.techniques.end())
    return make_error(kRawBound, " draws the scene's own buffers: not with --cache-mb");
  std::vector<std::string> names;
  if (options.brute) names.push_back("brute");  // first: the reference of every other technique
  else if (std::find(options.techniques.begin(), options.techniques.end(), "brute") !=
           options.techniques.end())
    return make_error(
        "--no-brute leaves brute out: name the techniques to time with --technique, brute not "
        "among them");
  for (const std::string& n : options.techniques)
    if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
  std::vector<std::string> techniques;
  for (const std::string& n : names)
    if (n != kRawBound) techniques.push_back(n);
  std::optional<Store> store;
  if (!options.store_file.empty()) {
    auto opened = Store::open(options.store_file, Store::Mode::kRead);
    if (!opened) return opened.error();
    store.emplace(std::move(*opened));
  }
  auto plan =
      plan_run(techniques, options.settings, store ? &*store : nullptr, scene, false, on_disk);
  if (!plan) return plan.error();
  if (auto ok = check_writable_folder(options.out_dir); !ok) return ok.error();
  remove_earlier_outputs(options.out_dir);

  auto context = gpu::create_headless_context();
  if (!context) return context.error();
  auto renderer = gpu::Renderer::create(scene, gpu::kSceneChunkBytes,
                                        options.expand_instances
                                            ? gpu::InstanceDrawing::expanded
                                            : gpu::InstanceDrawing::placed);
  if (!renderer) return renderer.error();
  (*renderer)->set_offscreen(options.width, options.height);
  (*renderer)->set_light(options.light_heading_deg, options.light_elevation_deg);

  BenchReport report;
  report.renderer = (*context)->renderer_name();
  report.scene_texture_gpu_bytes = (*renderer)->scene_texture_bytes();
  report.scene_geometry_gpu_bytes = (*renderer)->scene_geometry_bytes();
  report.instances_placed = (*renderer)->draws_instanced() ? scene.instances.size() : 0;
  report.scene_triangles = on_disk ? on_disk->triangle_count() : scene.triangle_count();
  report.interleaved = options.interleave;
  report.pipelined = options.pipelined;
  report.width = options.width;
  report.height = options.height;
  report.budget_ms = options.budget_ms;
  if (options.noise_floor) {
    // Measured with the scene and the renderer loaded, just before the techniques load and
    // run, so that the machine is about as they find it.
    const double work_ms = options.budget_ms > 0 ? options.budget_ms : 30.0;
    progress.start(formatted("noise floor, a fixed %.1f ms workload on every core", work_ms), 1);
    report.noise_floor = measure_timing_noise(work_ms, uint32_t(path.frames.size()));
    progress.advance();
    progress.finish();
  }
  {
    BenchRun run(scene, path, options, store ? &*store : nullptr, *plan, **renderer, progress,
                 on_disk);
    auto records = run.run(names);
    if (!records) return records.error();
    report.techniques = std::move(*records);
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
