#include "clusters_technique.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/core/text.hpp"
#include "farfield/store/bake_record.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

namespace {

constexpr SettingSpec kSettings[] = {
    {.key = "error_px",
     .type = SettingType::number,
     .default_value = "1",
     .help = "an object is drawn as the coarsest level whose geometric error projects below "
             "this many pixels (the full object where none does)",
     .unit = "px",
     .min = 0,
     .max = 1e4},
    {.key = "levels",
     .type = SettingType::integer,
     .default_value = "6",
     .help = "simplified levels an object may have, each about half the triangles of the last",
     .min = 1,
     .max = 16,
     .baked = true},
    {.key = "min_triangles",
     .type = SettingType::integer,
     .default_value = "8",
     .help = "an object with no more triangles gets no further level",
     .min = 1,
     .max = 1e6,
     .baked = true},
    {.key = "threads",
     .type = SettingType::integer,
     .default_value = "0",
     .help = "simplification threads; 0: all cores",
     .min = 0,
     .max = 1024},
};

// The distance from the eye to the nearest point of a box (0 inside).
float distance_to(const Bounds3& box, const glm::vec3& eye) {
  const glm::vec3 d = glm::max(glm::max(box.min - eye, eye - box.max), glm::vec3(0.0f));
  return glm::length(d);
}

}  // namespace

const TechniqueDescriptor clusters_descriptor{
    .name = "clusters",
    .summary =
        "objects as meshoptimizer LODs within a projected error or a frame budget (paper 001, "
        "under way)",
    .paper = "001",
    .settings = kSettings,
    .bake = BakeUse::optional,
    .bake_format = 1,
    .make = [](const SettingValues& v,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      ClustersOptions o;
      o.error_px = float(v.number("error_px"));
      o.lods.max_levels = v.integer("levels");
      o.lods.min_triangles = uint32_t(v.integer("min_triangles"));
      o.lods.threads = v.integer("threads");
      return std::unique_ptr<Technique>(std::make_unique<ClustersTechnique>(o));
    },
};

Result<void> ClustersTechnique::bake(const BakeContext& context) {
  auto set = build_lod_set(context.scene, options_.lods, context.progress);
  if (!set) return make_error("clusters: ", set.error().message);
  if (auto ok = save_lod_set(*set, context.store); !ok) return ok;
  lods_ = std::move(*set);
  return {};
}

Result<void> ClustersTechnique::load(const LoadContext& context) {
  // A pack that holds a clusters bake is read; without one the LODs are made now.
  auto record = context.store ? read_bake_record(*context.store, "clusters")
                              : Result<std::optional<BakeRecord>>(std::optional<BakeRecord>{});
  if (!record) return record.error();
  if (*record) {
    if (auto usable = usable_bake(*context.store, "clusters", clusters_descriptor.bake_format,
                                  scene_fingerprint(context.scene));
        !usable)
      return usable.error();
    auto set = load_lod_set(*context.store, context.scene);
    if (!set) return set.error();
    return use(std::move(*set), context.scene, context.device);
  }
  auto set = build_lod_set(context.scene, options_.lods, context.progress);
  if (!set) return make_error("clusters: ", set.error().message);
  return use(std::move(*set), context.scene, context.device);
}

Result<void> ClustersTechnique::use(LodSet set, const Scene& scene, gpu::Device& device) {
  lods_ = std::move(set);
  scene_ = &scene;
  resources_.bind(device);
  mesh_ = {};
  if (!lods_.indices.empty()) {
    auto mesh = resources_.scene_mesh(lods_.vertices, lods_.uvs, lods_.indices);
    if (!mesh) return make_error("clusters: ", mesh.error().message);
    mesh_ = *mesh;
  }
  std::vector<Bounds3> bounds(scene.objects.size());
  for (size_t i = 0; i < bounds.size(); ++i) bounds[i] = scene.objects[i].bounds;
  tree_ = build_octree(bounds, {});
  full_ = std::make_unique<ObjectSet>(scene);
  seen_ = std::make_unique<ObjectSet>(scene);
  stack_.reserve(8 * (tree_.depth + 1) + 1);
  frames_ = lods_drawn_ = full_drawn_ = 0;
  cost_ = {};
  visible_.reserve(scene.objects.size());
  refine_.reserve(scene.objects.size());
  return {};
}

void ClustersTechnique::select(const FrameInput& input, DrawList& out) {
  if (tree_.nodes.empty() || input.region.kind == Region::Kind::far_field) return;
  const View& view = input.view;
  ++frames_;
  const Frustum frustum(view);
  const glm::vec3 eye = view.pose.position;
  const bool near = input.region.kind == Region::Kind::near;
  // The objects in view, each once (an object may lie in several leaves).
  visible_.clear();
  seen_->clear();
  stack_.clear();
  stack_.push_back(0);
  while (!stack_.empty()) {
    const OctreeNode& node = tree_.nodes[stack_.back()];
    stack_.pop_back();
    const Visibility v = frustum.classify(node.bounds);
    if (v == Visibility::none || (near && !meet(node.bounds, input.region.box))) continue;
    if (v == Visibility::partial && !node.leaf()) {
      for (uint32_t c = 0; c < node.child_count; ++c) stack_.push_back(node.first_child + c);
      continue;
    }
    for (uint32_t i = node.items_begin; i < node.items_end; ++i) {
      const uint32_t object = tree_.items[i];
      const Object& o = scene_->objects[object];
      if (v == Visibility::partial && frustum.classify(o.bounds) == Visibility::none) continue;
      if (near && !meet(o.bounds, input.region.box)) continue;
      if (seen_->contains(object)) continue;
      seen_->insert(object);
      visible_.push_back({object, distance_to(o.bounds, eye), kWhole});
    }
  }
  // A length e at distance d covers e / (d * pixel) pixels at the centre of the view.
  const float pixel = 2.0f * std::tan(glm::radians(view.hfov_deg) * 0.5f) / float(view.width);
  if (!(input.budget.target_ms > 0.0) || !choose_under_budget(input.budget, pixel))
    choose_by_error(pixel);
  full_->clear();
  for (const Candidate& c : visible_) {
    const Object& o = scene_->objects[c.object];
    if (c.level == kWhole) {
      full_->insert(c.object);
      ++full_drawn_;
      continue;
    }
    ++lods_drawn_;
    const Lod& lod = lods_.lods[c.level];
    (scene_->materials[o.material].transparent() ? out.transparent : out.opaque)
        .push_back({lod.first_index, lod.index_count, o.material, mesh_});
  }
  full_->emit(out);  // the whole objects, in scene order
}

// Each object as the coarsest level whose error, seen from its nearest point, covers at most
// error_px pixels; the whole object where none does.
void ClustersTechnique::choose_by_error(float pixel) {
  const float allowed = options_.error_px * pixel;  // metres of error per metre of distance
  for (Candidate& c : visible_) {
    const float within = allowed * c.distance;
    c.level = kWhole;
    for (uint32_t k = lods_.first_lod[c.object]; k < lods_.first_lod[c.object + 1]; ++k) {
      if (lods_.lods[k].error_m > within) break;
      c.level = k;
    }
  }
}

// Paper 001, Sec. 4.5.2, among objects until the cluster hierarchy exists: a complete
// representation first (every object at its coarsest level), then the object whose drawn
// error covers the most pixels refined one level at a time while the predicted frame time
// stays within the budget. The prediction is the cost model fitted to the frames measured so
// far (frame_cost.hpp), with a tenth of the budget held back; before any frame was measured
// there is none, and the error rule decides.
bool ClustersTechnique::choose_under_budget(const FrameBudget& budget, float pixel) {
  cost_.observe(double(budget.last_triangles), budget.last_frame_ms);
  if (!cost_.ready()) return false;
  const double allowed = cost_.triangles_within(0.9 * budget.target_ms);
  auto triangles = [&](uint32_t object, uint32_t level) -> double {
    return level == kWhole ? double(scene_->objects[object].index_count / 3)
                           : double(lods_.lods[level].index_count / 3);
  };
  auto error_px = [&](const Candidate& c) {
    return c.level == kWhole ? 0.0f
                             : lods_.lods[c.level].error_m / (std::max(c.distance, 1e-3f) * pixel);
  };
  double cost = 0.0;
  refine_.clear();
  for (size_t i = 0; i < visible_.size(); ++i) {
    Candidate& c = visible_[i];
    const uint32_t first = lods_.first_lod[c.object], end = lods_.first_lod[c.object + 1];
    c.level = end > first ? end - 1 : kWhole;
    cost += triangles(c.object, c.level);
    if (c.level != kWhole) refine_.push_back({error_px(c), uint32_t(i)});
  }
  std::make_heap(refine_.begin(), refine_.end());
  while (!refine_.empty()) {
    std::pop_heap(refine_.begin(), refine_.end());
    Candidate& c = visible_[refine_.back().second];
    refine_.pop_back();
    const uint32_t finer = c.level == lods_.first_lod[c.object] ? kWhole : c.level - 1;
    const double more = triangles(c.object, finer) - triangles(c.object, c.level);
    if (cost + more > allowed) continue;  // a cheaper refinement may still fit
    cost += more;
    c.level = finer;
    if (finer != kWhole) {
      refine_.push_back({error_px(c), uint32_t(&c - visible_.data())});
      std::push_heap(refine_.begin(), refine_.end());
    }
  }
  return true;
}

std::string ClustersTechnique::describe() const {
  uint64_t triangles = lods_.indices.size() / 3;
  return formatted("%zu levels of detail for %zu objects, %llu triangles in them, made in %.2f s",
                   lods_.lods.size(),
                   lods_.first_lod.empty() ? size_t(0) : lods_.first_lod.size() - 1,
                   (unsigned long long)triangles, lods_.bake_s);
}

std::vector<std::pair<std::string, double>> ClustersTechnique::figures() const {
  return {{"lods", double(lods_.lods.size())},
          {"lod_triangles", double(lods_.indices.size() / 3)},
          {"mean_objects_as_lods", frames_ ? double(lods_drawn_) / double(frames_) : 0.0},
          {"mean_objects_full", frames_ ? double(full_drawn_) / double(frames_) : 0.0},
          {"cost_fixed_ms", cost_.fixed_ms()},
          {"cost_ms_per_triangle", cost_.ms_per_triangle()}};
}

}  // namespace farfield
