#include "hybrid_technique.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "farfield/core/occupancy_codec.hpp"
#include "farfield/core/text.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/path_generator.hpp"
#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"
#include "farfield/store/viewpoint_blobs.hpp"

namespace farfield {

namespace {

constexpr const char* kParamsKey = "hybrid/params";
const ViewpointBlobs kBlobs("hybrid", "sizes");  // "sizes" is written last
constexpr size_t kCachedViews = 8;

constexpr SettingSpec kSettings[] = {
    kDThetaSetting,
    kDPhiSetting,
    kRadiusSetting,
    {.key = "width",
     .type = SettingType::integer,
     .default_value = "1024",
     .help = "the width of the frames whose visible triangles are found (the walk's, or more: "
             "003, Sec. 3.2)",
     .unit = "px",
     .min = 16,
     .max = 16384,
     .baked = true},
    {.key = "height",
     .type = SettingType::integer,
     .default_value = "768",
     .help = "their height",
     .unit = "px",
     .min = 16,
     .max = 16384,
     .baked = true},
    {.key = "hfov",
     .type = SettingType::number,
     .default_value = "90",
     .help = "their horizontal field of view (the walk's)",
     .unit = "deg",
     .min = 1,
     .max = 179,
     .baked = true},
    {.key = "scale",
     .type = SettingType::integer,
     .default_value = "3",
     .help = "the triangles found in the frame of width x height and also in the same frame at "
             "this odd multiple of its resolution (whose pixel centres include the walk's): "
             "triangles smaller than a pixel that the eye sees between viewpoints (003, Sec. "
             "3.2: 'or finer'); 1: the walk's resolution alone",
     .min = 1,
     .max = 5,
     .baked = true},
    {.key = "codec",
     .type = SettingType::choice,
     .default_value = "paper",
     .help = "how a viewpoint's visible triangles are stored: paper (run lengths of the "
             "occupancy bit vector's bytes, Huffman coded: 003, Sec. 3.1.2) or zstd (zstd over "
             "the lengths of its runs of bits); both are measured at bake (info)",
     .choices = "paper|zstd",
     .baked = true},
    {.key = "union",
     .type = SettingType::choice,
     .default_value = "around",
     .help = "which viewpoints' triangles a frame draws: nearest (the paper's) or around (the "
             "union of the four at the corners of the cell holding the eye, so that between "
             "viewpoints less is missing)",
     .choices = "nearest|around"},
};

// Per viewpoint: visible triangles, bit vector, run-length bytes, paper and zstd streams.
constexpr size_t kSizeFields = 5;

View view_of(const ViewSphere& sphere, uint32_t id, const HybridOptions& o, const Scene& scene) {
  View v;
  v.pose = sphere.pose(id);
  v.width = o.width;
  v.height = o.height;
  v.hfov_deg = o.hfov_deg;
  v.near_m = near_plane_for(scene.bounds);
  return v;
}

std::string params_text(const ViewSphere& s, const HybridOptions& o, uint64_t triangles) {
  return formatted("%d %d %.9g %.9g %.9g %.9g %d %d %.9g %d %s %llu", s.longitudes, s.latitudes,
                   s.centre.x, s.centre.y, s.centre.z, s.radius, o.width, o.height, o.hfov_deg,
                   o.scale, o.zstd ? "zstd" : "paper", (unsigned long long)triangles);
}

}  // namespace

const TechniqueDescriptor hybrid_descriptor{
    .name = "hybrid",
    .summary = "the visible triangles of viewpoints on a sphere around the model, compressed, "
               "drawn as real geometry (paper 003, Sec. 3)",
    .paper = "003, Sec. 3",
    .settings = kSettings,
    .bake = BakeUse::required,
    .bake_format = 2,
    .bake_renders = true,
    .describe_bake = [](const Store& store) -> Result<std::string> {
      auto s = hybrid_storage(store);
      if (!s) return s.error();
      auto ratio = [](uint64_t a, uint64_t b) { return b ? double(a) / double(b) : 0.0; };
      return formatted(
          "hybrid: %u viewpoints, %.2f%% of the triangles visible on average; run-length ratio "
          "%.2f, Huffman ratio %.2f, total %.2f (paper's codec); zstd over the run lengths "
          "%.2f; stored %.2f MB",
          s->views, 100.0 * s->mean_visible_share, ratio(s->bit_vector, s->run_length),
          ratio(s->run_length, s->paper), ratio(s->bit_vector, s->paper),
          ratio(s->bit_vector, s->zstd), double(s->stored) / 1e6);
    },
    .make = [](const SettingValues& v,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      HybridOptions o;
      o.sphere = SphereSettings::from(v);
      o.width = v.integer("width");
      o.height = v.integer("height");
      o.hfov_deg = float(v.number("hfov"));
      o.scale = v.integer("scale");
      if (o.scale % 2 == 0)
        return make_error("hybrid.scale=", std::to_string(o.scale),
                          ": an odd multiple (1, 3 or 5), so that the finer frame's pixel centres "
                          "include the walk's");
      o.zstd = v.text("codec") == "zstd";
      o.around = v.text("union") == "around";
      return std::unique_ptr<Technique>(std::make_unique<HybridTechnique>(o));
    },
};

Result<HybridStorage> hybrid_storage(const Store& store) {
  HybridStorage out;
  auto params = store.get_meta(kParamsKey);
  if (!params) return params.error();
  if (*params) {
    const char* last = std::strrchr((*params)->c_str(), ' ');
    if (last) out.triangles = std::strtoull(last + 1, nullptr, 10);
  }
  auto blobs = store.list("hybrid/view/");
  if (!blobs) return blobs.error();
  double shares = 0.0;
  for (const BlobInfo& b : *blobs) {
    if (b.name.ends_with("/set")) {
      out.stored += b.stored_size;
      continue;
    }
    if (!b.name.ends_with("/sizes")) continue;
    auto sizes = read_array<uint64_t>(store, b.name.c_str());
    if (!sizes) return sizes.error();
    if (sizes->size() != kSizeFields)
      return make_error(store.path(), ": blob '", b.name, "' is not a hybrid viewpoint's sizes");
    ++out.views;
    if (out.triangles) shares += double((*sizes)[0]) / double(out.triangles);
    out.bit_vector += (*sizes)[1];
    out.run_length += (*sizes)[2];
    out.paper += (*sizes)[3];
    out.zstd += (*sizes)[4];
  }
  out.mean_visible_share = out.views ? shares / double(out.views) : 0.0;
  return out;
}

// Paper 003, Sec. 3.1: per viewpoint the visible triangles, as an occupancy bit vector
// compressed by both codecs (their sizes kept for Table 3), the chosen one stored. A viewpoint
// is one transaction: a bake killed and run again goes on from the viewpoints it has.
Result<void> HybridTechnique::bake(const BakeContext& context) {
  if (!context.renderer) return make_error("hybrid: the bake needs a renderer");
  auto made_renderer = context.renderer();
  if (!made_renderer) return made_renderer.error();
  const Scene& scene = context.scene;
  Store& store = context.store;
  if (scene.triangle_count() > UINT32_MAX)
    return make_error("hybrid: a scene of more than 2^32 triangles");
  sphere_ = options_.sphere.sphere_for(scene);
  const uint32_t triangles = uint32_t(scene.triangle_count());
  if (auto ok = kBlobs.start(store, params_text(sphere_, options_, triangles), sphere_.count());
      !ok)
    return ok;

  ObjectSet everything(scene);
  everything.insert_all();
  DrawList list;
  everything.emit(list);
  gpu::Renderer& renderer = **made_renderer;
  renderer.set_offscreen(options_.width, options_.height);
  context.progress.start("bake hybrid viewpoints", sphere_.count());
  for (uint32_t id = 0; id < sphere_.count(); ++id) {
    auto done = kBlobs.done(store, id);
    if (!done) return done.error();
    if (!*done) {
      const View view = view_of(sphere_, id, options_, scene);
      std::vector<uint32_t> visible = renderer.visible_triangles(view, list);
      if (options_.scale > 1) {
        // Finer (Sec. 3.2), and still the walk's own: at the finer resolution a triangle nearest
        // at a walk pixel's centre may lose to a coplanar one by rounding (seen: ~50 pixels of
        // the default city's frames differed at viewpoints with the finer set alone).
        View finer = view;
        finer.width *= options_.scale;
        finer.height *= options_.scale;
        renderer.set_offscreen(finer.width, finer.height);
        const std::vector<uint32_t> more = renderer.visible_triangles(finer, list);
        renderer.set_offscreen(view.width, view.height);
        std::vector<uint32_t> both;
        both.reserve(visible.size() + more.size());
        std::set_union(visible.begin(), visible.end(), more.begin(), more.end(),
                       std::back_inserter(both));
        visible.swap(both);
      }
      OccupancySizes paper, zstd;
      Bytes paper_bytes = encode_occupancy(visible, triangles, OccupancyCodec::paper, &paper);
      Bytes zstd_bytes = encode_occupancy(visible, triangles, OccupancyCodec::zstd, &zstd);
      const std::vector<uint64_t> sizes = {visible.size(), paper.bit_vector, paper.run_length,
                                           paper.encoded, zstd.encoded};
      auto transaction = store.begin();
      if (!transaction) return transaction.error();
      if (auto ok = store.put(kBlobs.name(id, "set"), options_.zstd ? zstd_bytes : paper_bytes,
                              Codec::kNone);
          !ok)
        return ok;
      if (auto ok = store.put(kBlobs.name(id, "sizes"), bytes_of(sizes), Codec::kNone); !ok)
        return ok;
      if (auto ok = transaction->commit(); !ok) return ok;
    }
    context.progress.advance();
  }
  context.progress.finish();
  renderer.set_offscreen(0, 0);
  auto storage = hybrid_storage(store);
  if (!storage) return storage.error();
  storage_ = *storage;
  return {};
}

Result<void> HybridTechnique::load(const LoadContext& context) {
  const Scene& scene = context.scene;
  if (!context.store)
    return make_error("hybrid draws only from a bake: run `farfield bake SCENE --technique "
                      "hybrid --out PACK.ffpack`, then pass --store PACK.ffpack");
  const Store& store = *context.store;
  // The viewpoints are the bake's.
  auto params = kBlobs.params(store);
  if (!params) return params.error();
  char codec[8] = {};
  unsigned long long triangles = 0;
  if (std::sscanf(params->c_str(), "%d %d %f %f %f %f %d %d %f %d %7s %llu",
                  &sphere_.longitudes, &sphere_.latitudes, &sphere_.centre.x, &sphere_.centre.y,
                  &sphere_.centre.z, &sphere_.radius, &options_.width, &options_.height,
                  &options_.hfov_deg, &options_.scale, codec, &triangles) != 12 ||
      sphere_.longitudes < 1 || sphere_.latitudes < 1 || !(sphere_.radius > 0))
    return make_error(store.path(), ": its hybrid bake has no readable parameters; re-bake it");
  if (triangles != scene.triangle_count())
    return make_error(store.path(), ": its hybrid bake is of a scene of ", std::to_string(triangles),
                      " triangles, not this one's ", std::to_string(scene.triangle_count()));
  if (auto complete = kBlobs.check_complete(store, sphere_.count()); !complete)
    return complete.error();
  sets_.assign(sphere_.count(), {});
  context.progress.start("read hybrid viewpoints", sphere_.count());
  for (uint32_t id = 0; id < sphere_.count(); ++id) {
    auto bytes = store.get(kBlobs.name(id, "set"));
    if (!bytes) return bytes.error();
    sets_[id] = std::move(*bytes);
    context.progress.advance();
  }
  context.progress.finish();
  auto storage = hybrid_storage(store);
  if (!storage) return storage.error();
  storage_ = *storage;
  scene_ = &scene;
  object_end_.clear();
  for (const Object& o : scene.objects) object_end_.push_back((o.first_index + o.index_count) / 3);
  objects_ = std::make_unique<ObjectSet>(scene);
  cache_.clear();
  view_count_ = 0;
  frames_ = fallback_frames_ = decodes_ = visible_drawn_ = ranges_drawn_ = 0;
  decode_ms_ = 0.0;
  return {};
}

const std::vector<uint32_t>* HybridTechnique::decoded(uint32_t view) {
  for (size_t k = 0; k < cache_.size(); ++k)
    if (cache_[k].view == view) {
      std::rotate(cache_.begin() + long(k), cache_.begin() + long(k) + 1, cache_.end());
      return &cache_.back().visible;
    }
  if (cache_.size() == kCachedViews) cache_.erase(cache_.begin());
  const auto start = std::chrono::steady_clock::now();
  cache_.push_back({view, {}});
  auto ok = decode_occupancy(sets_[view], uint32_t(scene_->triangle_count()), cache_.back().visible);
  decode_ms_ +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ++decodes_;
  if (!ok) {
    if (failure_.empty()) failure_ = formatted("hybrid: viewpoint %u: %s", view, ok.error().message.c_str());
    cache_.pop_back();
    return nullptr;
  }
  return &cache_.back().visible;
}

// The union of views_'s triangles as scene ranges: runs of consecutive triangles, cut where
// an object ends, in scene order (the order brute draws them in).
void HybridTechnique::build_ranges() {
  merged_.clear();
  for (size_t k = 0; k < view_count_; ++k) {
    const std::vector<uint32_t>* visible = decoded(views_[k]);
    if (!visible) return;
    scratch_.clear();
    std::set_union(merged_.begin(), merged_.end(), visible->begin(), visible->end(),
                   std::back_inserter(scratch_));
    merged_.swap(scratch_);
  }
  // Visible triangles are scattered (on the default city, runs of one or two): as ranges of
  // the scene's indices they cost a draw command each (31,447 a frame there, 0.38x brute's
  // time); as indexed runs of one material, one command a run of objects of that material.
  ranges_.clear();
  uint32_t object = 0;
  DrawRange* run = nullptr;
  for (const uint32_t t : merged_) {
    while (object_end_[object] <= t) ++object;
    const uint32_t material = scene_->objects[object].material;
    auto& into = scene_->materials[material].transparent() ? ranges_.indexed_transparent
                                                            : ranges_.indexed_opaque;
    const uint32_t at = uint32_t(ranges_.scene_indices.size());
    if (!run || run->material != material || run->first_index + run->index_count != at ||
        (&into.back() != run)) {
      into.push_back({at, 0, material, {}});
      run = &into.back();
    }
    run->index_count += 3;
    for (int c = 0; c < 3; ++c) ranges_.scene_indices.push_back(scene_->indices[3 * size_t(t) + c]);
    ranges_.scene_triangles.push_back(t);
  }
}

void HybridTechnique::select(const FrameInput& input, DrawList& out) {
  if (!scene_ || input.region.kind == Region::Kind::far_field) return;
  const glm::vec3 eye = input.view.pose.position;
  if (input.region.kind == Region::Kind::near) {
    objects_->clear();
    objects_->insert_meeting(input.region.box);
    objects_->emit(out);
    return;
  }
  ++frames_;
  if (!sphere_.stands_for(eye)) {
    ++fallback_frames_;
    objects_->clear();
    objects_->insert_all();
    objects_->emit(out);
    return;
  }
  std::array<uint32_t, 4> views{};
  size_t count = 0;
  if (options_.around) {
    // All four corners of the cell holding the eye, whatever their weights: an eye on a row
    // of viewpoints (as path --kind orbit's) sees triangles that only the row above saw, as
    // between two of the row's (the default city at 3x: 38 dB from the row's two, 41 from four).
    for (const ViewSphere::Weighted& w : sphere_.around(input.view.pose))
      if (std::find(views.begin(), views.begin() + long(count), w.id) ==
          views.begin() + long(count))
        views[count++] = w.id;
    for (size_t i = 1; i < count; ++i)  // ascending, so that the set compares across frames
      for (size_t j = i; j > 0 && views[j - 1] > views[j]; --j) std::swap(views[j - 1], views[j]);
  } else {
    views[count++] = sphere_.nearest(input.view.pose);
  }
  if (count != view_count_ || !std::equal(views.begin(), views.begin() + long(count), views_.begin())) {
    views_ = views;
    view_count_ = count;
    build_ranges();
  }
  visible_drawn_ += merged_.size();
  ranges_drawn_ += ranges_.indexed_opaque.size() + ranges_.indexed_transparent.size();
  const uint32_t base = uint32_t(out.scene_indices.size());
  out.scene_indices.insert(out.scene_indices.end(), ranges_.scene_indices.begin(),
                           ranges_.scene_indices.end());
  out.scene_triangles.insert(out.scene_triangles.end(), ranges_.scene_triangles.begin(),
                             ranges_.scene_triangles.end());
  for (const auto& [from, into] : {std::pair{&ranges_.indexed_opaque, &out.indexed_opaque},
                                   std::pair{&ranges_.indexed_transparent, &out.indexed_transparent}})
    for (DrawRange r : *from) {
      r.first_index += base;
      into->push_back(r);
    }
}

std::optional<CameraPose> HybridTechnique::start_pose() const {
  if (!scene_) return std::nullopt;
  return sphere_.pose(sphere_.nearest(pose_on_sphere(sphere_.centre, sphere_.radius, 0.0f, 25.0f)));
}

std::string HybridTechnique::describe() const {
  return formatted(
      "%u viewpoints (%d x %d, every %.2f x %.2f deg) %.4g m from the centre, %d x %d px (and "
      "x%d) at %.1f deg: %.2f%% of the triangles visible on average, %.2f MB",
      sphere_.count(), sphere_.longitudes, sphere_.latitudes, sphere_.d_theta_deg(),
      sphere_.d_phi_deg(), sphere_.radius, options_.width, options_.height, options_.scale,
      options_.hfov_deg,
      100.0 * storage_.mean_visible_share, double(storage_.stored) / 1e6);
}

std::vector<std::pair<std::string, double>> HybridTechnique::figures() const {
  auto mean = [&](double sum) { return frames_ ? sum / double(frames_) : 0.0; };
  auto ratio = [](uint64_t a, uint64_t b) { return b ? double(a) / double(b) : 0.0; };
  return {{"viewpoints", double(sphere_.count())},
          {"store_bytes", double(storage_.stored)},
          {"mean_visible_share", storage_.mean_visible_share},
          {"run_length_ratio", ratio(storage_.bit_vector, storage_.run_length)},
          {"huffman_ratio", ratio(storage_.run_length, storage_.paper)},
          {"total_ratio", ratio(storage_.bit_vector, storage_.paper)},
          {"zstd_ratio", ratio(storage_.bit_vector, storage_.zstd)},
          {"mean_decode_ms", mean(decode_ms_)},
          {"decodes", double(decodes_)},
          {"mean_triangles_drawn", mean(double(visible_drawn_))},
          {"mean_ranges", mean(double(ranges_drawn_))}};
}

}  // namespace farfield
