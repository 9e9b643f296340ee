// The colour-cube octree of paper 002 (Sec. 4.1, 4.2): the scene's bounding cube subdivided
// to a depth, every triangle associated with each leaf it overlaps, empty cells pruned; each
// cell holds a cluster of c x c x c colour-cubes, the leaves' baked from their triangles
// (leaf_baker.hpp), the parents' combined from their children's. Faces whose coverage does
// not exceed a threshold are dropped; the rest become proxy quads, kept in six batches per
// cell (one per orientation) so that a frame draws only the orientations facing the eye. The
// leaves' own triangles are copied into the same proxy mesh with their lighting baked per
// vertex, so that a frame gathers cubes and near geometry into one stream; textured triangles
// stay in the scene's buffers, named by index range.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "farfield/core/bounds.hpp"
#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/techniques/colorcube/leaf_baker.hpp"
#include "farfield/gpu/draw_list.hpp"

namespace farfield {

class Store;

// How depth 0 is resolved (docs/techniques/colorcube.md, "Depth from the scene").
enum class DepthRule : uint8_t {
  detail,   // leaf cubes about the size of the scene's triangles (median_triangle_edge)
  density,  // paper 002, Sec. 6.4: about triangles_per_leaf triangles a leaf
};

struct CubeTreeOptions {
  int depth = 0;  // levels below the root; 0 derives it by `depth_rule`
  DepthRule depth_rule = DepthRule::detail;
  int triangles_per_leaf = 4000;  // the density rule's target
  // A derived depth is lowered until at most this many leaves are occupied: the bake needs
  // about 10 KB a leaf (3.0 GB measured for 262,586 leaves of a 64-tree field).
  uint64_t max_leaves = uint64_t(1) << 18;
  LeafBakeOptions leaf{.oversampling = 1, .cluster = 4, .coverage = CoverageMode::binary};
  float coverage_threshold = 0.0f;  // a face is drawn when its coverage exceeds this
  bool coverage_as_alpha = false;   // draw coverage as transparency (paper 002, Sec. 4.1)
  bool drop_inner_faces = true;     // drop faces against a solid neighbour (the paper keeps them)
  int threads = 0;                  // leaf bake threads; 0: all cores
};

struct CubeCell {
  Bounds3 bounds;  // a cube
  // The cell and every triangle owned by a leaf below it: a large triangle reaches out of
  // its owner's cell, so culling and the near/far decision use this box, never dropping it.
  Bounds3 reach;
  uint32_t first_child = 0;  // children contiguous in `cells`
  uint32_t child_count = 0;  // 0 for a leaf
  uint32_t level = 0;        // 0 at the root
  // Leaves: the triangles the leaf owns (those whose centroid lies in it), so that each is
  // drawn once per frame. Untextured ones as a proxy index range, lit per vertex as the
  // renderer lights them; textured ones as scene ranges (CubeTree::scene_ranges).
  uint32_t geometry_begin = 0, geometry_count = 0;
  uint32_t scene_ranges_begin = 0, scene_ranges_count = 0;
  // Proxy index ranges of the cell's drawn faces, one per orientation (face index of
  // color_cube.hpp), into CubeTree::proxies.indices.
  std::array<uint32_t, 6> faces_begin{}, faces_count{};
  bool leaf() const { return child_count == 0; }
};

struct CubeTreeStats {  // paper 002, Table 1
  uint32_t cells = 0, leaves = 0, levels = 0, cluster = 0, oversampling = 0;
  uint64_t cube_faces = 0;           // faces kept in the model (drawable)
  uint64_t inner_faces_dropped = 0;  // faces against a solid neighbour, never seen
  uint64_t geometry_triangles = 0;   // the leaves' own triangles (each scene triangle once)
  double leaf_bake_s = 0;            // phase I: leaves rendered
  double hierarchy_s = 0;            // phase II: parents combined, proxies built
};

struct CubeTree {
  std::vector<CubeCell> cells;  // root first
  ProxyMesh proxies;
  std::vector<DrawRange> scene_ranges;  // the leaves' textured triangles, by leaf
  CubeTreeStats stats;
};

Result<CubeTree> build_cube_tree(const Scene& scene, const CubeTreeOptions& options,
                                 Progress& progress);

// A built tree into a store (blobs under "colorcube/", replacing a tree there), with its
// statistics as metadata; and back, refusing a missing or inconsistent one (scene ranges are
// checked against `scene`). Whether the bake belongs to the scene is checked before, from its
// bake record (usable_bake).
Result<void> save_cube_tree(const CubeTree& tree, Store& store);
Result<CubeTree> load_cube_tree(const Store& store, const Scene& scene);

// The depth build_cube_tree uses: options.depth, or the one its rule derives.
struct ResolvedDepth {
  int depth = 1;
  int detail_depth = 1;  // where leaf cubes reach the scene's triangle size (a given depth: it)
  bool limited_by_leaves = false;  // lowered to stay under options.max_leaves
};
ResolvedDepth resolve_depth(const Scene& scene, const CubeTreeOptions& options);
// Leaves holding a triangle centroid at a depth of the scene's bounding cube.
uint64_t occupied_leaves(const Scene& scene, int depth);
// The side of a leaf cube at a depth: the bounding cube's side / 2^depth / cluster.
double leaf_cube_side(const Scene& scene, int depth, int cluster);

}  // namespace farfield
