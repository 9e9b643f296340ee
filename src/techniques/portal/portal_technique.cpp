#include "portal_technique.hpp"

#include <cstdio>
#include <numeric>

namespace farfield {

namespace {

constexpr SettingSpec kSettings[] = {
    {.key = "max_depth",
     .type = SettingType::integer,
     .default_value = "64",
     .help = "portals in one chain; beyond, what the chain sees is drawn by frustum culling",
     .unit = "portals",
     .min = 1,
     .max = 4096},
    {.key = "leaf_objects",
     .type = SettingType::integer,
     .default_value = "8",
     .help = "a node of a cell's octree holding more objects is split",
     .unit = "objects",
     .min = 1,
     .max = 1e6},
};

constexpr uint32_t kCellColour = 0xff00ffffu;    // yellow, RGBA8 with R in the low byte
constexpr uint32_t kPortalColour = 0xffff00ffu;  // magenta

PortalTechniqueOptions options_from(const SettingValues& v, PortalClip clip) {
  PortalTechniqueOptions o;
  o.walk.clip = clip;
  o.walk.max_depth = uint32_t(v.integer("max_depth"));
  o.objects_per_leaf = uint32_t(v.integer("leaf_objects"));
  return o;
}

}  // namespace

const TechniqueDescriptor portal_descriptor{
    .name = "portal",
    .summary =
        "cells and portals: the eye's room, then what each portal in view shows, the "
        "view clipped by each portal polygon in turn",
    .paper = "004, plan to implement portals",
    .settings = kSettings,
    .make = [](const SettingValues& v,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      return std::unique_ptr<Technique>(
          std::make_unique<PortalTechnique>("portal", options_from(v, PortalClip::exact)));
    },
};

const TechniqueDescriptor portal_paper_descriptor{
    .name = "portal-paper",
    .summary =
        "cells and portals with paper 004's screen rectangles of the portals, "
        "intersected (Luebke and Georges' cull boxes): looser, cheaper",
    .paper = "004, plan to implement portals",
    .settings = kSettings,
    .make = [](const SettingValues& v,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      return std::unique_ptr<Technique>(std::make_unique<PortalTechnique>(
          "portal-paper", options_from(v, PortalClip::rectangles)));
    },
};

Result<void> PortalTechnique::load(const LoadContext& context) {
  // A scene without cells loads too (every technique runs on every scene): each frame then
  // falls back to frustum culling, counted in fallback_frames and said by describe().
  const Scene& scene = context.scene;
  scene_ = &scene;
  OctreeOptions tree;
  tree.objects_per_leaf = options_.objects_per_leaf;
  std::vector<Bounds3> bounds;
  cell_trees_.clear();
  for (const Cell& cell : scene.cells) {
    bounds.clear();
    for (uint32_t o : scene.objects_of(cell)) bounds.push_back(scene.objects[o].bounds);
    cell_trees_.push_back(build_octree(bounds, tree));
  }
  bounds.clear();
  for (const Object& o : scene.objects) bounds.push_back(o.bounds);
  scene_tree_ = build_octree(bounds, tree);
  all_objects_.resize(scene.objects.size());
  std::iota(all_objects_.begin(), all_objects_.end(), 0u);
  walk_ = std::make_unique<PortalWalk>(scene, options_.walk);
  visible_ = std::make_unique<ObjectSet>(scene);
  visits_.reserve(256);
  return {};
}

void PortalTechnique::collect(const Octree& tree, std::span<const uint32_t> objects,
                              const ConvexVolume& volume, const Bounds3* near_box) {
  if (tree.nodes.empty()) return;
  stack_.clear();
  stack_.push_back(0);
  while (!stack_.empty()) {
    const OctreeNode& node = tree.nodes[stack_.back()];
    stack_.pop_back();
    const Visibility v = volume.classify(node.bounds);
    if (v == Visibility::none || (near_box && !meet(node.bounds, *near_box))) continue;
    if (v == Visibility::partial && !node.leaf()) {
      for (uint32_t c = 0; c < node.child_count; ++c) stack_.push_back(node.first_child + c);
      continue;
    }
    for (uint32_t i = node.items_begin; i < node.items_end; ++i) {
      const uint32_t object = objects[tree.items[i]];
      const Bounds3& b = scene_->objects[object].bounds;
      if (v == Visibility::partial && volume.classify(b) == Visibility::none) continue;
      if (near_box && !meet(b, *near_box)) continue;
      visible_->insert(object);
    }
  }
}

void PortalTechnique::select(const FrameInput& input, DrawList& out) {
  if (input.region.kind == Region::Kind::far_field) return;
  const Bounds3* near_box = input.region.kind == Region::Kind::near ? &input.region.box : nullptr;
  ++frames_;
  visible_->clear();
  const auto cell =
      scene_->cells.empty() ? std::nullopt : cell_containing(*scene_, input.view.pose.position);
  if (!cell) {
    // Outside every cell: nothing says what is hidden; frustum culling keeps the image.
    ++fallback_frames_;
    visits_.clear();
    collect(scene_tree_, all_objects_, ConvexVolume::of_view(input.view), near_box);
  } else {
    walk_->walk(input.view, *cell, visits_);
    visits_total_ += visits_.size();
    bool limit = false;
    for (const CellVisit& v : visits_) {
      if (v.beyond_limits) {
        limit = true;
        collect(scene_tree_, all_objects_, v.volume, near_box);
      } else {
        collect(cell_trees_[v.cell], scene_->objects_of(scene_->cells[v.cell]), v.volume, near_box);
      }
    }
    limit_frames_ += limit;
  }
  visible_->emit(out);
}

std::string PortalTechnique::describe() const {
  char line[160];
  if (scene_->cells.empty())
    return "no cells in the scene: every frame falls back to frustum culling (generate building, "
           "or import with the naming convention of docs/portals.md)";
  std::snprintf(line, sizeof line, "%zu cells, %zu portals, %s", scene_->cells.size(),
                scene_->portals.size(),
                options_.walk.clip == PortalClip::exact ? "exact clipping" : "screen rectangles");
  return line;
}

std::vector<std::pair<std::string, double>> PortalTechnique::figures() const {
  const uint64_t walked = frames_ - fallback_frames_;
  return {{"cells", double(scene_->cells.size())},
          {"portals", double(scene_->portals.size())},
          {"mean_cells_visited", walked ? double(visits_total_) / double(walked) : 0.0},
          {"frames_past_limits", double(limit_frames_)}};
}

void PortalTechnique::annotate(const View&, DrawList& list) const {
  // The cells visited (yellow boxes) and the portals passed (magenta outlines).
  for (const CellVisit& v : visits_) {
    const Bounds3& b = scene_->cells[v.cell].bounds;
    auto corner = [&](int i) {
      return glm::vec3(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y,
                       i & 4 ? b.max.z : b.min.z);
    };
    for (int i = 0; i < 8; ++i)
      for (int axis = 1; axis < 8; axis <<= 1)
        if (!(i & axis)) list.lines.push_back({corner(i), corner(i | axis), kCellColour});
    if (v.portal == UINT32_MAX) continue;
    const auto points = scene_->points_of(scene_->portals[v.portal]);
    for (size_t i = 0; i < points.size(); ++i)
      list.lines.push_back({points[i], points[(i + 1) % points.size()], kPortalColour});
  }
}

}  // namespace farfield
