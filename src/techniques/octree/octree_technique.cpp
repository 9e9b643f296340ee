#include "octree_technique.hpp"

#include <cstdio>

namespace farfield {

namespace {

constexpr SettingSpec kSettings[] = {
    {.key = "depth",
     .type = SettingType::integer,
     .default_value = "12",
     .help = "deepest level of the octree below the root",
     .min = 1,
     .max = 20},
    {.key = "leaf_objects",
     .type = SettingType::integer,
     .default_value = "8",
     .help = "a node holding more objects is split",
     .unit = "objects",
     .min = 1,
     .max = 1e6},
    {.key = "occlusion",
     .type = SettingType::flag,
     .default_value = "0",
     .help = "also skip what the nearest opaque objects hide (docs/occlusion.md; the image is "
             "unchanged); 0 is the paper's culling"},
    {.key = "occluders",
     .type = SettingType::choice,
     .default_value = "meshes",
     .help = "with occlusion: meshes, the nearest objects' own triangles sampled at every pixel; "
             "boxes, boxes inside them on a map of 4 x 4-pixel texels (cheaper, hides less)",
     .choices = "meshes|boxes"},
    {.key = "occluder_count",
     .type = SettingType::integer,
     .default_value = "128",
     .help = "with occlusion: occluders a frame, the nearest objects' first",
     .unit = "objects",
     .min = 1,
     .max = 1e5},
};

OctreeTechniqueOptions options_from(const SettingValues& v) {
  OctreeTechniqueOptions o;
  o.tree.max_depth = uint32_t(v.integer("depth"));
  o.tree.objects_per_leaf = uint32_t(v.integer("leaf_objects"));
  o.occlusion = v.flag("occlusion");
  o.occluders.meshes = v.text("occluders") == "meshes";
  o.occluders.per_frame = uint32_t(v.integer("occluder_count"));
  return o;
}

}  // namespace

const TechniqueDescriptor octree_descriptor{
    .name = "octree",
    .summary = "octree frustum culling (plane test, objects of partial leaves tested)",
    .paper = "004, Sec. 2.1",
    .settings = kSettings,
    .make = [](const SettingValues& v,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      return std::unique_ptr<Technique>(
          std::make_unique<OctreeTechnique>("octree", options_from(v)));
    },
};

const TechniqueDescriptor octree_paper_descriptor{
    .name = "octree-paper",
    .summary = "octree culling with paper 004's own corner-projection test, whole leaves drawn",
    .paper = "004, Sec. 2.1",
    .settings = kSettings,
    .make = [](const SettingValues& v,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      OctreeTechniqueOptions o = options_from(v);
      o.paper_visibility_test = true;
      o.test_objects_in_leaves = false;
      return std::unique_ptr<Technique>(std::make_unique<OctreeTechnique>("octree-paper", o));
    },
};

Result<void> OctreeTechnique::load(const LoadContext& context) {
  const Scene& scene = context.scene;
  scene_ = &scene;
  std::vector<Bounds3> bounds(scene.objects.size());
  for (size_t i = 0; i < bounds.size(); ++i) bounds[i] = scene.objects[i].bounds;
  tree_ = build_octree(bounds, options_.tree);
  visible_ = std::make_unique<ObjectSet>(scene);
  occluders_ =
      options_.occlusion ? std::make_unique<Occluders>(scene, options_.occluders) : nullptr;
  stack_.reserve(8 * (tree_.depth + 1) + 1);
  return {};
}

Visibility OctreeTechnique::classify(const Frustum& frustum, const Bounds3& box) const {
  return options_.paper_visibility_test ? frustum.classify_paper004(box) : frustum.classify(box);
}

void OctreeTechnique::select(const FrameInput& input, DrawList& out) {
  if (tree_.nodes.empty() || input.region.kind == Region::Kind::far_field) return;
  visible_->clear();
  const Frustum frustum(input.view);
  const OcclusionMap* occlusion = nullptr;
  if (occluders_) {
    out.occlusion_ms = occluders_->fill(occlusion_, input.view, frustum);
    occlusion = &occlusion_;
  }
  // Region::near: only what meets the box (the near field of a far-field technique).
  const bool near = input.region.kind == Region::Kind::near;
  const Bounds3& box = input.region.box;
  // paper 004, testVolume(): full draws the subtree, partial recurses, none skips.
  stack_.clear();
  stack_.push_back(0);
  while (!stack_.empty()) {
    const OctreeNode& node = tree_.nodes[stack_.back()];
    stack_.pop_back();
    const Visibility v = classify(frustum, node.bounds);
    if (v == Visibility::none || (near && !meet(node.bounds, box))) continue;
    if (occlusion && occlusion->hidden(node.bounds)) continue;
    if (v == Visibility::partial && !node.leaf()) {
      for (uint32_t c = 0; c < node.child_count; ++c) stack_.push_back(node.first_child + c);
      continue;
    }
    const bool test = v == Visibility::partial && options_.test_objects_in_leaves;
    for (uint32_t i = node.items_begin; i < node.items_end; ++i) {
      const uint32_t object = tree_.items[i];
      const Bounds3& bounds = scene_->objects[object].bounds;
      if (test && frustum.classify(bounds) == Visibility::none) continue;
      if (near && !meet(bounds, box)) continue;
      if (occlusion && occlusion->hidden(bounds)) continue;
      visible_->insert(object);
    }
  }
  visible_->emit(out);
}

std::string OctreeTechnique::describe() const {
  char line[160];
  std::snprintf(line, sizeof(line), "%zu nodes, %u leaves, depth %u, %zu object entries",
                tree_.nodes.size(), tree_.leaves, tree_.depth, tree_.items.size());
  return line;
}

}  // namespace farfield
