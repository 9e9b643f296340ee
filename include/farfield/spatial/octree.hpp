// An octree of items (objects, or triangles) over their bounding cube (paper 004, Sec. 2.1):
// each node is split into eight equal children until it holds few items or reaches the
// maximum depth, or (paper 002's colour-cube tree, Sec. 4.1) every node down to a fixed depth;
// empty children are pruned; an item is listed in every leaf its box overlaps. A child is
// half-open towards the centre ([min, mid) below, [mid, max] above), so a box that only
// touches the centre plane from above is not listed below it.
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
  uint32_t max_depth = 12;          // levels below the root
  uint32_t objects_per_leaf = 8;    // a node holding more is split
  bool split_to_max_depth = false;  // split every node down to max_depth, whatever it holds
  Bounds3 root;                     // the cube to subdivide; empty: the items' bounding cube
};

struct OctreeNode {
  Bounds3 bounds;            // the node's cube, not its objects' bounds
  uint32_t first_child = 0;  // index of the first child in `nodes`; children are contiguous
  uint32_t child_count = 0;  // 0 for a leaf
  uint32_t items_begin = 0;  // the objects below this node: items[items_begin, items_end)
  uint32_t items_end = 0;
  bool leaf() const { return child_count == 0; }
};

struct Octree {
  std::vector<OctreeNode> nodes;
  std::vector<uint32_t> items;
  uint32_t depth = 0;  // deepest level reached
  uint32_t leaves = 0;
};

// `object_bounds[i]` is item i's box; empty boxes, and boxes outside a given root, are skipped.
Octree build_octree(std::span<const Bounds3> object_bounds, const OctreeOptions& options);

}  // namespace farfield
