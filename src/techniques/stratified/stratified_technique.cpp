#include "stratified_technique.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/core/frustum.hpp"
#include "farfield/store/bake_record.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/stratified/box_faces.hpp"

namespace farfield {

using namespace stratified;

namespace {
constexpr size_t kTextureSets = 42;      // viewcells resident on the GPU at once
constexpr size_t kCacheCells = 24;       // decoded viewcells kept in memory
constexpr uint32_t kCyan = 0xffffff00u;  // RGBA8, R in the low byte
}  // namespace

const TechniqueDescriptor stratified_descriptor{
    .name = "stratified",
    .summary = "viewcells with far-field boxes",
    .paper = "000",
    .settings = stratified_settings(),
    .bake = BakeUse::required,
    .bake_format = 2,  // 2: box sides in the order of core/cube_faces.hpp
    .bake_renders = true,
    .describe_bake = [](const Store& store) -> Result<std::string> {
      auto text = store.get_meta(kParamsKey);
      if (!text) return text.error();
      if (!*text) return std::string();
      auto params = parse_params(**text);
      if (!params) return make_error(store.path(), ": ", params.error().message);
      std::string out;
      for (size_t s = 0; s < params->shells.size(); ++s) {
        auto cells = baked_cells(store, int(s));
        if (!cells) return cells.error();
        char line[160];
        std::snprintf(line, sizeof line, "shell %zu: %zu viewcells baked, v %.3g m, box %.3g m\n",
                      s, cells->size(), params->shells[s].viewcell, params->shells[s].box);
        out += line;
      }
      return out;
    },
    .make = [](const SettingValues& v,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      auto options = stratified_options(v);
      if (!options) return options.error();
      return std::unique_ptr<Technique>(std::make_unique<StratifiedTechnique>(*options));
    },
};

StratifiedTechnique::~StratifiedTechnique() = default;

Result<void> StratifiedTechnique::load(const LoadContext& context) {
  if (context.store == nullptr)
    return make_error(
        "stratified draws from a bake: run `farfield bake SCENE --technique "
        "stratified --out PACK.ffpack`, then pass --store PACK.ffpack");
  const Scene& scene = context.scene;
  const Store& store = *context.store;
  if (auto usable = usable_bake(store, "stratified", stratified_descriptor.bake_format,
                                scene_fingerprint(scene));
      !usable)
    return usable.error();
  auto text = store.get_meta(kParamsKey);
  if (!text) return text.error();
  if (!*text)
    return make_error(store.path(), ": its stratified bake has no parameters; re-bake it");
  auto params = parse_params(**text);
  if (!params) return make_error(store.path(), ": ", params.error().message);
  params_ = *params;
  scene_ = &scene;
  shells_.clear();
  for (size_t s = 0; s < params_.shells.size(); ++s) {
    auto tree =
        ViewcellTree::create(params_.region, params_.shells[s].viewcell, params_.shells[s].box);
    if (!tree) return make_error(store.path(), ": ", tree.error().message);
    auto cells = baked_cells(store, int(s));
    if (!cells) return cells.error();
    Shell shell{std::move(*tree), {}};
    for (const CellKey& k : *cells) {
      if (!shell.tree.valid(k))
        return make_error(store.path(), ": viewcell ", k.name(), " lies outside the bake's grid");
      shell.baked.push_back(k.packed());
    }
    std::sort(shell.baked.begin(), shell.baked.end());
    shells_.push_back(std::move(shell));
  }
  if (shells_[0].baked.empty())
    return make_error(store.path(), ": its stratified bake has no finished viewcell yet");
  auto loader =
      CellLoader::start(store.path(), params_, uint32_t(scene.objects.size()), kCacheCells);
  if (!loader) return loader.error();
  loader_ = std::move(*loader);
  selected_ = std::make_unique<ObjectSet>(scene);
  resources_.bind(context.device);
  textures_.clear();
  for (size_t i = 0; i < kTextureSets * kFaces; ++i) textures_.push_back(resources_.texture());
  resident_.clear();
  far_box_.reset();
  current_.assign(shells_.size(), std::nullopt);
  previous_.reset();
  last_position_.reset();
  frame_ = crossings_ = stalls_ = unbaked_frames_ = outside_frames_ = damaged_frames_ = 0;
  return {};
}

bool StratifiedTechnique::baked(int shell, const CellKey& key) const {
  const auto& b = shells_[size_t(shell)].baked;
  return std::binary_search(b.begin(), b.end(), key.packed());
}

int StratifiedTechnique::make_resident(const CellId& id,
                                       const std::shared_ptr<const CellRecord>& record,
                                       DrawList& out) {
  for (size_t i = 0; i < resident_.size(); ++i)
    if (resident_[i].id == id) {
      resident_[i].last_used = frame_;
      return int(i);
    }
  uint8_t faces = 0;
  for (int f = 0; f < kFaces; ++f)
    if (record->faces[size_t(f)].channels != 0) faces |= uint8_t(1u << f);
  size_t set = resident_.size();
  if (set < kTextureSets) {
    resident_.push_back({id, faces, frame_});
  } else {
    set = 0;  // the least recently used; never one of this frame's
    for (size_t i = 1; i < resident_.size(); ++i)
      if (resident_[i].last_used < resident_[set].last_used) set = i;
    resident_[set] = {id, faces, frame_};
  }
  // paper 000, Sec. 3.2: on a crossing the new viewcell's textures replace the old ones.
  for (int f = 0; f < kFaces; ++f) {
    const FaceImage& face = record->faces[size_t(f)];
    if (face.channels == 0) continue;
    // The record owns the pixels: the list keeps it alive until it is drawn.
    out.uploads.push_back({textures_[set * kFaces + size_t(f)], face.width, face.height,
                           face.channels, face.pixels.data(), record});
  }
  return int(set);
}

void StratifiedTechnique::add_box(int shell, const CellKey& key, int set, float opacity,
                                  DrawList& out) const {
  const ViewcellTree& tree = shells_[size_t(shell)].tree;
  const glm::vec3 centre = tree.centre(key);
  const uint8_t faces = resident_[size_t(set)].faces;
  for (int f = 0; f < kFaces; ++f)
    if (faces >> f & 1)
      out.backdrop.push_back({face_corners(centre, float(tree.box()), f),
                              textures_[size_t(set) * kFaces + size_t(f)], opacity});
}

void StratifiedTechnique::prefetch_ahead(const glm::vec3& position) {
  const float speed = glm::length(velocity_);
  if (speed < 1e-5f || options_.lookahead == 0) return;
  const glm::vec3 direction = velocity_ / speed;
  // paper 000, Sec. 3.2.1: the viewcells the viewpoint will enter next, from its velocity.
  for (size_t s = 0; s < shells_.size(); ++s) {
    const ViewcellTree& tree = shells_[s].tree;
    const float step = float(tree.viewcell()) * 0.5f;
    const float reach = float(tree.viewcell()) * (float(options_.lookahead) + 0.5f);
    std::optional<CellKey> last = current_[s];
    for (float d = step; d <= reach; d += step) {
      const auto key = tree.locate(position + direction * d);
      if (!key || key == last) continue;
      last = key;
      if (baked(int(s), *key)) loader_->prefetch({int(s), *key});
    }
  }
}

void StratifiedTechnique::select(const FrameInput& input, DrawList& out) {
  const View& view = input.view;
  // Region::far_field (composite): the box alone, the near field left to another technique.
  // Region::near is not one of stratified's: it draws as for the whole scene.
  const bool far_only = input.region.kind == Region::Kind::far_field;
  far_box_.reset();
  ++frame_;
  const glm::vec3 p = view.pose.position;
  if (last_position_) velocity_ = p - *last_position_;
  last_position_ = p;
  selected_->clear();
  const Frustum frustum(view);
  const auto& objects = scene_->objects;
  auto add_visible = [&](uint32_t object) {
    if (frustum.classify(objects[object].bounds) != Visibility::none) selected_->insert(object);
  };
  auto everything_visible = [&] {
    if (far_only) return;  // no far field here: the caller draws the scene itself
    for (uint32_t i = 0; i < objects.size(); ++i) add_visible(i);
    selected_->emit(out);
  };
  if (options_.style == Style::brute) {  // paper 000, Sec. 5.1: every object
    if (far_only) return;
    selected_->insert_all();
    selected_->emit(out);
    return;
  }

  const auto key = shells_[0].tree.locate(p);
  if (!key || !baked(0, *key)) {
    // No far field here: outside the navigable region, or a viewcell the bake left out.
    ++(key ? unbaked_frames_ : outside_frames_);
    std::fill(current_.begin(), current_.end(), std::nullopt);
    everything_visible();
    return;
  }
  bool stalled = false;
  const auto record = loader_->get({0, *key}, &stalled);
  if (!record) {  // damaged: failure() says so; draw correctly meanwhile
    ++damaged_frames_;
    everything_visible();
    return;
  }
  if (current_[0] != key) {
    if (current_[0]) {
      ++crossings_;
      previous_ = current_[0];
      crossed_at_ = frame_;
    }
    current_[0] = key;
  }
  for (size_t s = 1; s < shells_.size(); ++s) {
    const auto k = shells_[s].tree.locate(p);
    current_[s] = k && baked(int(s), *k) ? k : std::nullopt;
  }
  prefetch_ahead(p);

  const std::vector<uint32_t>& near = record->near;
  const Style style = far_only ? Style::far_texture : options_.style;
  switch (style) {
    case Style::full:
    case Style::near_only:
      for (uint32_t object : near) add_visible(object);
      break;
    case Style::far_objects:
      for (uint32_t i = 0; i < objects.size(); ++i)
        if (!std::binary_search(near.begin(), near.end(), i)) add_visible(i);
      break;
    default:
      break;
  }
  selected_->emit(out);

  if (style == Style::full || style == Style::far_texture) {
    far_box_ = shells_[0].tree.box_bounds(*key);
    // Outermost shell first: each inner box is drawn over the one around it (Ch. 4).
    for (size_t s = shells_.size(); s-- > 1;) {
      if (!current_[s]) continue;
      const auto r = loader_->get({int(s), *current_[s]}, &stalled);
      if (!r) continue;
      add_box(int(s), *current_[s], make_resident({int(s), *current_[s]}, r, out), 1.0f, out);
    }
    const int set = make_resident({0, *key}, record, out);
    const uint64_t since = frame_ - crossed_at_;
    if (previous_ && options_.blend_frames > 0 && since < uint64_t(options_.blend_frames)) {
      // paper 000, Sec. 7.1 (interpolation): fade the new far field in over the old one.
      if (auto old = loader_->peek({0, *previous_})) {
        add_box(0, *previous_, make_resident({0, *previous_}, old, out), 1.0f, out);
        add_box(0, *key, set, float(since + 1) / float(options_.blend_frames + 1), out);
      } else {
        add_box(0, *key, set, 1.0f, out);
      }
    } else {
      add_box(0, *key, set, 1.0f, out);
    }
  }
  if (stalled) ++stalls_;
}

void StratifiedTechnique::annotate(const View&, DrawList& list) const {
  list.backdrop_mode = BackdropMode::in_world;
  // The top side would hide the inside from above (paper 000, Fig. 5-2 shows the box open).
  std::erase_if(list.backdrop, [&](const TexturedQuad& q) {
    const auto at = std::find(textures_.begin(), textures_.end(), q.texture);
    return at != textures_.end() && (at - textures_.begin()) % kFaces == 2;  // +Y
  });
  if (current_.empty() || !current_[0]) return;
  const Bounds3 b = shells_[0].tree.cell_bounds(*current_[0]);
  auto corner = [&](int i) {
    return glm::vec3(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y,
                     i & 4 ? b.max.z : b.min.z);
  };
  for (int i = 0; i < 8; ++i)
    for (int axis = 1; axis < 8; axis <<= 1)
      if (!(i & axis)) list.lines.push_back({corner(i), corner(i | axis), kCyan});
}

std::string StratifiedTechnique::failure() const {
  return loader_ ? loader_->error() : "";
}

std::optional<CameraPose> StratifiedTechnique::start_pose() const {
  if (shells_.empty() || shells_[0].baked.empty()) return std::nullopt;
  // The first baked viewcell's viewpoint, facing its nearest baked neighbour: along the
  // street (or path) the bake followed.
  const ViewcellTree& tree = shells_[0].tree;
  const glm::vec3 here = tree.centre(CellKey::unpacked(shells_[0].baked.front()));
  glm::vec3 toward = here + glm::vec3(1, 0, 0);
  float nearest = INFINITY;
  for (size_t i = 1; i < shells_[0].baked.size(); ++i) {
    const glm::vec3 c = tree.centre(CellKey::unpacked(shells_[0].baked[i]));
    const glm::vec2 d(c.x - here.x, c.z - here.z);
    if (glm::dot(d, d) > 0.0f && glm::dot(d, d) < nearest) nearest = glm::dot(d, d), toward = c;
  }
  CameraPose pose;
  pose.position = here;
  pose.yaw_deg = glm::degrees(std::atan2(toward.z - here.z, toward.x - here.x));
  if (pose.yaw_deg < 0.0f) pose.yaw_deg += 360.0f;
  return pose;
}

std::string StratifiedTechnique::describe() const {
  if (shells_.empty()) return bake_summary_;
  char text[256];
  std::snprintf(text, sizeof text,
                "%zu of %llu viewcells baked, v %.3g m, box %.3g m, alpha %.2f deg, %d px %s, "
                "%zu shell(s), style %s",
                shells_[0].baked.size(), (unsigned long long)shells_[0].tree.cell_count(),
                shells_[0].tree.viewcell(), shells_[0].tree.box(), params_.alpha_deg,
                params_.resolution, codec_name(params_.codec.codec), shells_.size(),
                style_name(options_.style));
  return text;
}

std::vector<std::pair<std::string, double>> StratifiedTechnique::figures() const {
  std::vector<std::pair<std::string, double>> f;
  if (shells_.empty()) return f;
  f.emplace_back("alpha_max_deg", params_.alpha_deg);
  f.emplace_back("resolution", params_.resolution);
  for (size_t s = 0; s < shells_.size(); ++s) {
    const std::string p = "shell" + std::to_string(s) + "_";
    f.emplace_back(p + "viewcell_m", shells_[s].tree.viewcell());
    f.emplace_back(p + "box_m", shells_[s].tree.box());
    f.emplace_back(p + "viewcells_baked", double(shells_[s].baked.size()));
    f.emplace_back(p + "viewcells_in_region", double(shells_[s].tree.cell_count()));
  }
  f.emplace_back("crossings", double(crossings_));
  f.emplace_back("stalls", double(stalls_));
  f.emplace_back("viewcell_loads", loader_ ? double(loader_->loads()) : 0.0);
  f.emplace_back("frames_in_unbaked_viewcells", double(unbaked_frames_));
  f.emplace_back("frames_outside_region", double(outside_frames_));
  return f;
}

}  // namespace farfield
