#include "farfield/spatial/octree.hpp"

#include <algorithm>

#include "farfield/core/assert.hpp"

namespace farfield {

namespace {

bool overlaps(const Bounds3& a, const Bounds3& b) {
  return a.min.x <= b.max.x && a.max.x >= b.min.x && a.min.y <= b.max.y && a.max.y >= b.min.y &&
         a.min.z <= b.max.z && a.max.z >= b.min.z;
}

Bounds3 child_cube(const Bounds3& cube, int child) {
  const glm::vec3 mid = cube.center();
  Bounds3 b;
  b.min = {child & 1 ? mid.x : cube.min.x, child & 2 ? mid.y : cube.min.y,
           child & 4 ? mid.z : cube.min.z};
  b.max = {child & 1 ? cube.max.x : mid.x, child & 2 ? cube.max.y : mid.y,
           child & 4 ? cube.max.z : mid.z};
  return b;
}

class Builder {
 public:
  Builder(std::span<const Bounds3> bounds, const OctreeOptions& options, Octree& tree)
      : bounds_(bounds), options_(options), tree_(tree) {}

  // Fills node `index` (already allocated with its cube) from `objects`, depth first, so the
  // items of a subtree are contiguous.
  void fill(uint32_t index, std::vector<uint32_t> objects, uint32_t depth) {
    tree_.depth = std::max(tree_.depth, depth);
    tree_.nodes[index].items_begin = static_cast<uint32_t>(tree_.items.size());
    std::vector<uint32_t> parts[8];
    bool split = objects.size() > options_.objects_per_leaf && depth < options_.max_depth;
    if (split) {
      const Bounds3 cube = tree_.nodes[index].bounds;
      for (int c = 0; c < 8; ++c) {
        const Bounds3 child = child_cube(cube, c);
        for (uint32_t o : objects)
          if (overlaps(bounds_[o], child)) parts[c].push_back(o);
      }
      // When two children would each hold every object, they all straddle the centre and
      // splitting only repeats them.
      const auto everything = [&](const std::vector<uint32_t>& p) {
        return p.size() == objects.size();
      };
      split = std::count_if(parts, parts + 8, everything) <= 1;
    }
    if (!split) {
      tree_.items.insert(tree_.items.end(), objects.begin(), objects.end());
      tree_.nodes[index].items_end = static_cast<uint32_t>(tree_.items.size());
      tree_.leaves++;
      return;
    }
    const Bounds3 cube = tree_.nodes[index].bounds;
    const uint32_t first = static_cast<uint32_t>(tree_.nodes.size());
    uint32_t count = 0;
    for (int c = 0; c < 8; ++c) {
      if (parts[c].empty()) continue;  // paper 004 Sec. 2.2 planned this pruning; we do it
      OctreeNode child;
      child.bounds = child_cube(cube, c);
      tree_.nodes.push_back(child);
      ++count;
    }
    tree_.nodes[index].first_child = first;
    tree_.nodes[index].child_count = count;
    objects = {};  // free before recursing
    uint32_t slot = first;
    for (int c = 0; c < 8; ++c) {
      if (parts[c].empty()) continue;
      fill(slot++, std::move(parts[c]), depth + 1);
    }
    tree_.nodes[index].items_end = static_cast<uint32_t>(tree_.items.size());
  }

 private:
  std::span<const Bounds3> bounds_;
  const OctreeOptions& options_;
  Octree& tree_;
};

}  // namespace

Octree build_octree(std::span<const Bounds3> object_bounds, const OctreeOptions& options) {
  FF_ASSERT(options.objects_per_leaf > 0, "objects_per_leaf %u", options.objects_per_leaf);
  Octree tree;
  Bounds3 all;
  std::vector<uint32_t> objects;
  for (uint32_t i = 0; i < object_bounds.size(); ++i) {
    if (object_bounds[i].empty()) continue;
    all.expand(object_bounds[i]);
    objects.push_back(i);
  }
  if (objects.empty()) return tree;
  // The bounding cube: equal subvolumes at every level (paper 004, Sec. 2.1).
  const float half = 0.5f * std::max({all.size().x, all.size().y, all.size().z}) * 1.0001f + 1e-6f;
  OctreeNode root;
  root.bounds.min = all.center() - glm::vec3(half);
  root.bounds.max = all.center() + glm::vec3(half);
  tree.nodes.push_back(root);
  Builder(object_bounds, options, tree).fill(0, std::move(objects), 0);
  return tree;
}

}  // namespace farfield
