#include "octree_technique.hpp"

#include <cstdio>

namespace farfield {

Result<void> OctreeTechnique::load(const Scene& scene) {
  scene_ = &scene;
  std::vector<Bounds3> bounds(scene.objects.size());
  for (size_t i = 0; i < bounds.size(); ++i) bounds[i] = scene.objects[i].bounds;
  tree_ = build_octree(bounds, options_.tree);
  visible_ = std::make_unique<ObjectSet>(scene);
  stack_.reserve(8 * (tree_.depth + 1) + 1);
  return {};
}

Visibility OctreeTechnique::classify(const Frustum& frustum, const Bounds3& box) const {
  return options_.paper_visibility_test ? frustum.classify_paper004(box) : frustum.classify(box);
}

void OctreeTechnique::select(const View& view, const FrameBudget&, DrawList& out) {
  out.clear();
  if (tree_.nodes.empty()) return;
  visible_->clear();
  const Frustum frustum(view);
  // paper 004, testVolume(): full draws the subtree, partial recurses, none skips.
  stack_.clear();
  stack_.push_back(0);
  while (!stack_.empty()) {
    const OctreeNode& node = tree_.nodes[stack_.back()];
    stack_.pop_back();
    const Visibility v = classify(frustum, node.bounds);
    if (v == Visibility::none) continue;
    if (v == Visibility::partial && !node.leaf()) {
      for (uint32_t c = 0; c < node.child_count; ++c) stack_.push_back(node.first_child + c);
      continue;
    }
    const bool test = v == Visibility::partial && options_.test_objects_in_leaves;
    for (uint32_t i = node.items_begin; i < node.items_end; ++i) {
      const uint32_t object = tree_.items[i];
      if (test && frustum.classify(scene_->objects[object].bounds) == Visibility::none) continue;
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
