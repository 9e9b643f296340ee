#include "farfield/spatial/octree.hpp"

#include <algorithm>
#include <bit>

#include "farfield/core/assert.hpp"

namespace farfield {

namespace {

// The children of `cube` a box overlaps, as a bit mask over child numbers (bit 0 of a child
// number: upper in x, bit 1: in y, bit 2: in z), for a box known to overlap `cube`.
uint32_t children_overlapped(const Bounds3& cube, const Bounds3& box) {
  const glm::vec3 mid = cube.center();
  uint32_t axis_halves[3];  // per axis: bit 0 the lower half, bit 1 the upper half
  for (int a = 0; a < 3; ++a)
    axis_halves[a] = uint32_t(box.min[a] < mid[a]) | uint32_t(box.max[a] >= mid[a]) << 1;
  uint32_t mask = 0;
  for (int child = 0; child < 8; ++child)
    if ((axis_halves[0] >> (child & 1) & 1) && (axis_halves[1] >> (child >> 1 & 1) & 1) &&
        (axis_halves[2] >> (child >> 2 & 1) & 1))
      mask |= 1u << child;
  return mask;
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
    bool split = depth < options_.max_depth &&
                 (options_.split_to_max_depth || objects.size() > options_.objects_per_leaf);
    if (split) {
      const Bounds3 cube = tree_.nodes[index].bounds;
      for (uint32_t o : objects)
        for (uint32_t m = children_overlapped(cube, bounds_[o]); m != 0; m &= m - 1)
          parts[std::countr_zero(m)].push_back(o);
      // When two children would each hold every object, they all straddle the centre and
      // splitting only repeats them.
      const auto everything = [&](const std::vector<uint32_t>& p) {
        return p.size() == objects.size();
      };
      split = options_.split_to_max_depth || std::count_if(parts, parts + 8, everything) <= 1;
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
  FF_ASSERT(object_bounds.size() < UINT32_MAX, "%zu items", object_bounds.size());
  Octree tree;
  Bounds3 all;
  std::vector<uint32_t> objects;
  for (uint32_t i = 0; i < object_bounds.size(); ++i) {
    if (object_bounds[i].empty() ||
        (!options.root.empty() && !meet(options.root, object_bounds[i])))
      continue;
    all.expand(object_bounds[i]);
    objects.push_back(i);
  }
  if (objects.empty()) return tree;
  OctreeNode root;
  if (!options.root.empty()) {
    root.bounds = options.root;
  } else {
    // The bounding cube: equal subvolumes at every level (paper 004, Sec. 2.1).
    const float half =
        0.5f * std::max({all.size().x, all.size().y, all.size().z}) * 1.0001f + 1e-6f;
    root.bounds.min = all.center() - glm::vec3(half);
    root.bounds.max = all.center() + glm::vec3(half);
  }
  tree.nodes.push_back(root);
  Builder(object_bounds, options, tree).fill(0, std::move(objects), 0);
  return tree;
}

}  // namespace farfield
