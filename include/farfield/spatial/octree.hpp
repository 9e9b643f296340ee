// An octree of objects over the scene's bounding cube (paper 004, Sec. 2.1): each node is
// split into eight equal children until it holds few objects or reaches the maximum depth;
// empty children are pruned; an object is listed in every leaf its bounds overlap.
//
// Layout: nodes in a flat array (root first, children of a node contiguous); leaf items
// (object numbers) in depth-first order, so the objects below any node are one contiguous
// range of `items` (with repeats where an object spans leaves).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "farfield/core/bounds.hpp"

namespace farfield {

struct OctreeOptions {
  uint32_t max_depth = 12;        // levels below the root
  uint32_t objects_per_leaf = 8;  // a node holding more is split
};

struct OctreeNode {
  Bounds3 bounds;             // the node's cube, not its objects' bounds
  uint32_t first_child = 0;   // index of the first child in `nodes`; children are contiguous
  uint32_t child_count = 0;   // 0 for a leaf
  uint32_t items_begin = 0;   // the objects below this node: items[items_begin, items_end)
  uint32_t items_end = 0;
  bool leaf() const { return child_count == 0; }
};

struct Octree {
  std::vector<OctreeNode> nodes;
  std::vector<uint32_t> items;
  uint32_t depth = 0;  // deepest level reached
  uint32_t leaves = 0;
};

// `object_bounds[i]` is object i's box; empty boxes are skipped.
Octree build_octree(std::span<const Bounds3> object_bounds, const OctreeOptions& options);

}  // namespace farfield
