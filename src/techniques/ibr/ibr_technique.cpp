#include "ibr_technique.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/core/image_pyramid.hpp"
#include "farfield/core/text.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/path_generator.hpp"
#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"
#include "farfield/store/viewpoint_blobs.hpp"

namespace farfield {

namespace {

const ViewpointBlobs kBlobs("ibr", "full");  // "full" is written last

constexpr SettingSpec kSettings[] = {
    kDThetaSetting,
    kDPhiSetting,
    kRadiusSetting,
    {.key = "fov",
     .type = SettingType::number,
     .default_value = "",
     .help = "the viewpoints' field of view, square; default: the scene's bounding sphere seen "
             "from the radius, and 5% around it",
     .unit = "deg",
     .min = 1,
     .max = 170,
     .baked = true},
    {.key = "resolution",
     .type = SettingType::integer,
     .default_value = "512",
     .help = "W: the viewpoints' images are W x W (divisible by 2^(levels - 1))",
     .unit = "px",
     .symbol = "W (003, Sec. 2.2)",
     .min = 16,
     .max = 4096,
     .baked = true},
    {.key = "levels",
     .type = SettingType::integer,
     .default_value = "3",
     .help = "levels of the image pyramid, each half the last's resolution",
     .symbol = "n (003, Sec. 2.2)",
     .min = 1,
     .max = 8,
     .baked = true},
    {.key = "quality",
     .type = SettingType::integer,
     .default_value = "80",
     .help = "JPEG quality of the stored levels (the paper's 80)",
     .min = 1,
     .max = 100,
     .baked = true},
    {.key = "difference_quality",
     .type = SettingType::integer,
     .default_value = "75",
     .help = "JPEG quality of the stored differences, the highest under ibr.max_storage (the "
             "paper's is ibr.quality, 80, for every level; 75 costs nothing measurable: "
             "docs/techniques/ibr.md)",
     .min = 1,
     .max = 100,
     .baked = true},
    {.key = "max_storage",
     .type = SettingType::number,
     .default_value = "1.18",
     .help = "a viewpoint's stored levels take at most this many times its level-0 image as "
             "JPEG alone (the paper's Table 1: 0.99 to 1.18): its differences at the highest "
             "quality, from ibr.difference_quality down to 40, that fits; 0: no limit",
     .min = 0,
     .max = 100,
     .baked = true},
    {.key = "pyramid",
     .type = SettingType::choice,
     .default_value = "mean",
     .help = "how a level halves the one below: min (the paper's Eq. 1-3, differences >= 0, "
             "magnified texel by texel) or mean (differences signed, magnified bilinearly: "
             "smaller and closer to the model, core/image_pyramid.hpp)",
     .choices = "min|mean",
     .baked = true},
    {.key = "level",
     .type = SettingType::choice,
     .default_value = "auto",
     .help = "the finest level drawn (0 the finest); auto: by the viewer's speed (003, Sec. "
             "2.3), the finest when still, the coarsest from ibr.fast_deg a frame",
     .choices = "auto|0|1|2|3|4|5|6|7"},
    {.key = "blend",
     .type = SettingType::choice,
     .default_value = "bilinear",
     .help = "between viewpoints: nearest (the paper's), or the four around the eye blended by "
             "their bilinear weights in longitude and latitude",
     .choices = "nearest|bilinear"},
    {.key = "fast_deg",
     .type = SettingType::number,
     .default_value = "",
     .help = "the viewer's speed, degrees of the sphere a frame, from which the coarsest level "
             "is drawn (finer levels below it in equal steps); default: one step of longitude",
     .unit = "deg",
     .min = 0,
     .min_open = true},
};

std::string level_blob(uint32_t view, int level) {
  return kBlobs.name(view, "l" + std::to_string(level));
}

// The sphere and field of view of the options for `scene`, or why there are none.
Result<ViewSphere> sphere_for(const Scene& scene, const IbrOptions& o, float& fov_deg) {
  const double r = std::max(0.5 * double(glm::length(scene.bounds.size())), 1e-3);
  const double radius = o.sphere.radius_for(scene);
  if (o.fov_deg > 0) {
    fov_deg = o.fov_deg;
  } else {
    if (radius <= 1.05 * r)
      return make_error(formatted(
          "ibr: viewpoints %.3g m from the centre stand inside the scene's bounding sphere "
          "(%.3g m) and its 5%% margin: give a larger ibr.radius, or an ibr.fov",
          radius, r));
    fov_deg = float(glm::degrees(2.0 * std::asin(1.05 * r / radius)));
  }
  if (o.resolution % (1 << (o.levels - 1)) != 0)
    return make_error(formatted("ibr: a resolution of %d px does not halve %d times (levels %d)",
                                o.resolution, o.levels - 1, o.levels));
  return o.sphere.sphere_for(scene);
}

// max_storage is a 13th field since it came (a pack with 12 was baked without a limit).
std::string params_text(const ViewSphere& s, float fov_deg, const IbrOptions& o) {
  return formatted("%d %d %.9g %.9g %.9g %.9g %.9g %d %d %d %d %s %.9g", s.longitudes, s.latitudes,
                   s.centre.x, s.centre.y, s.centre.z, s.radius, fov_deg, o.resolution, o.levels,
                   o.quality, o.difference_quality, o.rule == PyramidRule::min ? "min" : "mean",
                   o.max_storage);
}

// One viewpoint's stored levels (paper 003, Sec. 2.2, Steps 1-5): the coarsest as given (its
// JPEG bytes and their decoding), each finer one as its difference, at `difference_quality`,
// from the level above as the viewer will have it (decoded), so that JPEG's errors do not add
// up level to level.
Result<std::vector<Bytes>> stored_levels(const std::vector<Image>& levels, const Bytes& coarsest,
                                         const Image& coarsest_decoded, int difference_quality,
                                         PyramidRule rule) {
  std::vector<Bytes> stored(levels.size());
  stored.back() = coarsest;
  Image decoded = coarsest_decoded;
  for (size_t l = levels.size() - 1; l-- > 0;) {
    const Image up = magnified(decoded, rule);
    auto d = encode_jpeg(difference(levels[l], up, rule), difference_quality);
    if (!d) return make_error("ibr: ", d.error().message);
    stored[l] = std::move(*d);
    if (l == 0) break;
    auto back = decode_jpeg(stored[l]);
    if (!back) return make_error("ibr: ", back.error().message);
    decoded = accumulated(up, *back, rule);
  }
  return stored;
}

uint64_t total_bytes(const std::vector<Bytes>& stored) {
  uint64_t total = 0;
  for (const Bytes& b : stored) total += b.size();
  return total;
}

}  // namespace

const TechniqueDescriptor ibr_descriptor{
    .name = "ibr",
    .summary = "multi-level images from viewpoints on a sphere around the model, JPEG "
               "differences refined by the viewer's speed (paper 003, Sec. 2)",
    .paper = "003, Sec. 2",
    .settings = kSettings,
    .bake = BakeUse::required,
    .bake_format = 1,
    .bake_renders = true,
    .describe_bake = [](const Store& store) -> Result<std::string> {
      auto s = ibr_storage(store);
      if (!s) return s.error();
      std::string text = formatted("ibr: %u viewpoints;", s->views);
      uint64_t total = 0;
      for (size_t l = s->stored.size(); l-- > 0;) {
        total += s->stored[l];
        text += formatted(" level %zu %.2f MB (%s %.2f MB alone)", l, double(s->stored[l]) / 1e6,
                          l + 1 == s->stored.size() ? "image" : "difference; its image",
                          double(s->full[l]) / 1e6);
      }
      if (!s->full.empty() && s->full[0] > 0)
        text += formatted("; total %.2f MB, %.2fx the level-0 images alone", double(total) / 1e6,
                          double(total) / double(s->full[0]));
      return text;
    },
    .make = [](const SettingValues& v,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      IbrOptions o;
      o.sphere = SphereSettings::from(v);
      o.fov_deg = float(v.number_or("fov", 0.0));
      o.resolution = v.integer("resolution");
      o.levels = v.integer("levels");
      o.quality = v.integer("quality");
      o.difference_quality = v.integer("difference_quality");
      o.max_storage = v.number("max_storage");
      o.rule = v.text("pyramid") == "min" ? PyramidRule::min : PyramidRule::mean;
      o.level = v.text("level") == "auto" ? -1 : std::atoi(v.text("level").c_str());
      o.blend = v.text("blend") == "bilinear";
      o.fast_deg = float(v.number_or("fast_deg", 0.0));
      return std::unique_ptr<Technique>(std::make_unique<IbrTechnique>(o));
    },
};

Result<IbrStorage> ibr_storage(const Store& store) {
  IbrStorage out;
  auto blobs = store.list("ibr/view/");
  if (!blobs) return blobs.error();
  for (const BlobInfo& b : *blobs) {
    const size_t slash = b.name.rfind('/');
    const std::string what = b.name.substr(slash + 1);
    if (what == "full") {
      auto sizes = read_array<uint64_t>(store, b.name.c_str());
      if (!sizes) return sizes.error();
      if (out.full.size() < sizes->size()) out.full.resize(sizes->size(), 0);
      for (size_t l = 0; l < sizes->size(); ++l) out.full[l] += (*sizes)[l];
      ++out.views;
    } else if (what.size() > 1 && what[0] == 'l') {
      const size_t level = size_t(std::atoi(what.c_str() + 1));
      if (out.stored.size() <= level) out.stored.resize(level + 1, 0);
      out.stored[level] += b.stored_size;
    }
  }
  return out;
}

// Paper 003, Sec. 2.1-2.2: per viewpoint the level-0 image, the min-rule pyramid, the
// coarsest level and the finer levels' differences as JPEG. A viewpoint is one transaction,
// so a bake killed and run again goes on from the viewpoints it has.
Result<void> IbrTechnique::bake(const BakeContext& context) {
  if (!context.renderer) return make_error("ibr: the bake needs a renderer");
  auto made_renderer = context.renderer();
  if (!made_renderer) return made_renderer.error();
  const Scene& scene = context.scene;
  Store& store = context.store;
  auto sphere = sphere_for(scene, options_, fov_deg_);
  if (!sphere) return sphere.error();
  sphere_ = *sphere;
  if (auto ok = kBlobs.start(store, params_text(sphere_, fov_deg_, options_), sphere_.count());
      !ok)
    return ok;

  ObjectSet everything(scene);
  everything.insert_all();
  DrawList list;
  everything.emit(list);
  View view;
  view.width = view.height = options_.resolution;
  view.hfov_deg = fov_deg_;
  view.near_m = near_plane_for(scene.bounds);
  gpu::Renderer& renderer = **made_renderer;
  renderer.set_offscreen(view.width, view.height);
  context.progress.start("bake ibr viewpoints", sphere_.count());
  for (uint32_t id = 0; id < sphere_.count(); ++id) {
    auto done = kBlobs.done(store, id);
    if (!done) return done.error();
    if (*done) {
      context.progress.advance();
      continue;
    }
    view.pose = sphere_.pose(id);
    renderer.draw(view, list);
    const std::vector<Image> levels = pyramid(renderer.capture(), options_.levels, options_.rule);
    std::vector<uint64_t> full(options_.levels);
    Bytes coarsest;
    for (int l = options_.levels - 1; l >= 0; --l) {
      auto alone = encode_jpeg(levels[l], options_.quality);
      if (!alone) return make_error("ibr: ", alone.error().message);
      full[l] = alone->size();
      if (l == options_.levels - 1) coarsest = std::move(*alone);
    }
    auto coarsest_decoded = decode_jpeg(coarsest);
    if (!coarsest_decoded) return make_error("ibr: ", coarsest_decoded.error().message);
    auto at_quality = [&](int quality) {
      return stored_levels(levels, coarsest, *coarsest_decoded, quality, options_.rule);
    };
    int quality = options_.difference_quality;
    auto stored = at_quality(quality);
    if (!stored) return stored.error();
    if (const double limit = options_.max_storage * double(full[0]);
        options_.max_storage > 0 && double(total_bytes(*stored)) > limit) {
      // The highest quality that fits, by bisection (bytes grow with the quality); the lowest
      // where none does. `stored` is the attempt at `quality`.
      int lo = std::min(kLowestDifferenceQuality, quality), hi = quality - 1;
      while (lo < hi) {
        const int mid = (lo + hi + 1) / 2;
        auto trial = at_quality(mid);
        if (!trial) return trial.error();
        if (double(total_bytes(*trial)) <= limit) {
          lo = mid;
          quality = mid;
          stored = std::move(trial);
        } else {
          hi = mid - 1;
        }
      }
      if (quality != lo) stored = at_quality(lo);
      if (!stored) return stored.error();
    }
    auto transaction = store.begin();
    if (!transaction) return transaction.error();
    for (int l = 0; l < options_.levels; ++l)
      if (auto ok = store.put(level_blob(id, l), (*stored)[l], Codec::kNone); !ok) return ok;
    if (auto ok = store.put(kBlobs.name(id, "full"), bytes_of(full), Codec::kNone); !ok) return ok;
    if (auto ok = transaction->commit(); !ok) return ok;
    context.progress.advance();
  }
  context.progress.finish();
  renderer.set_offscreen(0, 0);
  auto storage = ibr_storage(store);
  if (!storage) return storage.error();
  storage_ = *storage;
  return {};
}

Result<void> IbrTechnique::load(const LoadContext& context) {
  const Scene& scene = context.scene;
  if (!context.store)
    return make_error("ibr draws only from a bake: run `farfield bake SCENE --technique ibr "
                      "--out PACK.ffpack`, then pass --store PACK.ffpack");
  const Store& store = *context.store;
  // The viewpoints are the bake's (its settings, and the scene's centre and radius then).
  auto params = kBlobs.params(store);
  if (!params) return params.error();
  char rule[8] = {};
  options_.max_storage = 0.0;
  const int fields =
      std::sscanf(params->c_str(), "%d %d %f %f %f %f %f %d %d %d %d %7s %lf", &sphere_.longitudes,
                  &sphere_.latitudes, &sphere_.centre.x, &sphere_.centre.y, &sphere_.centre.z,
                  &sphere_.radius, &fov_deg_, &options_.resolution, &options_.levels,
                  &options_.quality, &options_.difference_quality, rule, &options_.max_storage);
  if ((fields != 12 && fields != 13) || sphere_.longitudes < 1 || sphere_.latitudes < 1 ||
      !(sphere_.radius > 0) || !(fov_deg_ > 0 && fov_deg_ < 180) || options_.levels < 1 ||
      options_.levels > 8 || options_.resolution < 1 ||
      options_.resolution % (1 << (options_.levels - 1)) != 0)
    return make_error(store.path(), ": its ibr bake has no readable parameters; re-bake it");
  options_.rule = std::string(rule) == "min" ? PyramidRule::min : PyramidRule::mean;
  if (auto complete = kBlobs.check_complete(store, sphere_.count()); !complete)
    return complete.error();
  jpegs_.assign(sphere_.count(), {});
  context.progress.start("read ibr viewpoints", sphere_.count());
  for (uint32_t id = 0; id < sphere_.count(); ++id) {
    for (int l = 0; l < options_.levels; ++l) {
      auto bytes = store.get(level_blob(id, l));
      if (!bytes) return bytes.error();
      jpegs_[id].push_back(std::move(*bytes));
    }
    context.progress.advance();
  }
  context.progress.finish();
  auto storage = ibr_storage(store);
  if (!storage) return storage.error();
  storage_ = *storage;
  scene_ = &scene;
  resources_.bind(context.device);
  // Room for the four viewpoints of this frame and the last, every level.
  slots_.assign(size_t(8 * options_.levels), {});
  for (Slot& s : slots_) s.texture = resources_.texture();
  objects_ = std::make_unique<ObjectSet>(scene);
  frames_ = fallback_frames_ = decodes_ = levels_drawn_ = 0;
  decode_ms_ = 0.0;
  return {};
}

TextureHandle IbrTechnique::resident(uint32_t view, uint32_t level, uint64_t frame,
                                     DrawList& out) {
  Slot* oldest = &slots_[0];
  for (Slot& s : slots_) {
    if (s.view == view && s.level == level) {
      s.used = frame;
      return s.texture;
    }
    if (s.used < oldest->used) oldest = &s;
  }
  const auto start = std::chrono::steady_clock::now();
  auto image = decode_jpeg(jpegs_[view][level],
                           uint64_t(options_.resolution) * uint64_t(options_.resolution));
  decode_ms_ +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ++decodes_;
  const int side = options_.resolution >> level;
  if (!image || image->width != side || image->height != side) {
    if (failure_.empty())
      failure_ = formatted("ibr: viewpoint %u, level %u: %s", view, level,
                           image ? "an image of the wrong size" : image.error().message.c_str());
    return {};
  }
  auto pixels = std::make_shared<Image>(std::move(*image));
  // The min rule's levels add up texel by texel (nearest); the mean's are magnified
  // bilinearly, as the bake did (core/image_pyramid.hpp).
  out.uploads.push_back({oldest->texture, side, side, 3, pixels->rgb.data(), pixels, false,
                         options_.rule == PyramidRule::min});
  oldest->view = view;
  oldest->level = level;
  oldest->used = frame;
  return oldest->texture;
}

void IbrTechnique::select(const FrameInput& input, DrawList& out) {
  if (!scene_ || input.region.kind == Region::Kind::far_field) return;
  const glm::vec3 eye = input.view.pose.position;
  if (input.region.kind == Region::Kind::near) {
    objects_->clear();
    objects_->insert_meeting(input.region.box);
    objects_->emit(out);
    return;
  }
  ++frames_;
  // Far from the sphere the images no longer stand for the model: the geometry instead.
  if (!sphere_.stands_for(eye)) {
    ++fallback_frames_;
    objects_->clear();
    objects_->insert_all();
    objects_->emit(out);
    last_eye_ = eye;
    return;
  }
  // Paper 003, Sec. 2.3: the faster the viewer moves round the model, the coarser the level.
  int level = options_.level >= 0 ? std::min(options_.level, options_.levels - 1) : 0;
  if (options_.level < 0 && frames_ > 1) {
    const glm::vec3 a = eye - sphere_.centre, b = last_eye_ - sphere_.centre;
    const float cosine = glm::dot(a, b) / std::max(glm::length(a) * glm::length(b), 1e-12f);
    const float speed = glm::degrees(std::acos(std::clamp(cosine, -1.0f, 1.0f)));
    const float fast = options_.fast_deg > 0 ? options_.fast_deg : sphere_.d_theta_deg();
    level = std::min(int(std::floor(speed / fast * float(options_.levels - 1) + 0.5f)),
                     options_.levels - 1);
  }
  last_eye_ = eye;
  levels_drawn_ += uint64_t(level);
  std::array<ViewSphere::Weighted, 4> views = sphere_.around(input.view.pose);
  if (!options_.blend) views = {ViewSphere::Weighted{sphere_.nearest(input.view.pose), 1.0f}, {}, {}, {}};
  std::sort(views.begin(), views.end(),
            [](const auto& a, const auto& b) { return a.weight > b.weight; });
  const float half = sphere_.radius * std::tan(glm::radians(fov_deg_) * 0.5f);
  float total = 0.0f;
  for (const ViewSphere::Weighted& v : views) {
    if (v.weight <= 1e-4f) continue;
    total += v.weight;
    const float opacity = v.weight / total;  // the weighted mean, drawn one over the other
    const CameraPose pose = sphere_.pose(v.id);
    const glm::vec3 r = pose.right() * half, u = pose.up() * half, c = sphere_.centre;
    const std::array<glm::vec3, 4> corners = {c - r + u, c + r + u, c + r - u, c - r - u};
    for (int l = options_.levels - 1; l >= level; --l) {
      const TextureHandle texture = resident(v.id, uint32_t(l), input.frame + 1, out);
      if (!texture) return;
      out.backdrop.push_back({corners, texture, opacity,
                              l == options_.levels - 1          ? TexturedQuad::Blend::over
                              : options_.rule == PyramidRule::min ? TexturedQuad::Blend::add
                                                                  : TexturedQuad::Blend::add_signed});
    }
  }
}

std::optional<CameraPose> IbrTechnique::start_pose() const {
  if (!scene_) return std::nullopt;
  return sphere_.pose(sphere_.nearest(pose_on_sphere(sphere_.centre, sphere_.radius, 0.0f, 25.0f)));
}

std::string IbrTechnique::describe() const {
  uint64_t total = 0;
  for (uint64_t b : storage_.stored) total += b;
  const uint64_t alone = storage_.full.empty() ? 0 : storage_.full[0];
  return formatted(
      "%u viewpoints (%d x %d, every %.2f x %.2f deg) %.4g m from the centre, %.2f deg, %d x %d "
      "px, %d levels: %.2f MB (%.2fx the level-0 images alone)",
      sphere_.count(), sphere_.longitudes, sphere_.latitudes, sphere_.d_theta_deg(),
      sphere_.d_phi_deg(), sphere_.radius, fov_deg_, options_.resolution, options_.resolution,
      options_.levels, double(total) / 1e6, alone ? double(total) / double(alone) : 0.0);
}

std::vector<std::pair<std::string, double>> IbrTechnique::figures() const {
  uint64_t total = 0;
  for (uint64_t b : storage_.stored) total += b;
  std::vector<std::pair<std::string, double>> out = {
      {"viewpoints", double(sphere_.count())},
      {"store_bytes", double(total)},
      {"mean_decode_ms", frames_ ? decode_ms_ / double(frames_) : 0.0},
      {"decodes", double(decodes_)},
      {"mean_level", frames_ ? double(levels_drawn_) / double(frames_) : 0.0}};
  for (size_t l = 0; l < storage_.stored.size(); ++l) {
    out.push_back({formatted("level%zu_stored_bytes", l), double(storage_.stored[l])});
    out.push_back({formatted("level%zu_image_bytes", l), double(storage_.full[l])});
  }
  return out;
}

}  // namespace farfield
