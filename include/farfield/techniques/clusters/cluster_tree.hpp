// The cluster hierarchy of paper 001, Sec. 4.4, built bottom-up over octree cells: each object
// lies in the smallest cell that wholly contains it (objects on a cell's boundaries are grouped
// higher up; with ClusterTreeOptions::loose, the default, cells grown by a share of their size
// take what crosses their edges, as a loose octree does), and a cell where more than one object
// lies wholly inside gets a cluster: one merged mesh of those objects per material, simplified from
// the real objects (never from the clusters below it) by scene/simplify, with its geometric error
// in metres (a modern HLOD: the paper's cluster representation is a textured box; this is the
// geometric one beside it). A node's error is never below its children's, so that refining never
// makes the error worse. Where the objects beneath a node hold more than
// ClusterTreeOptions::input_triangles, its mesh is simplified from their finest levels of detail
// that hold no more (the levels' error added to its own: a distance between surfaces obeys the
// triangle inequality), so that a node's work and memory stay bounded whatever the scene's size
// (the root of a 100M-triangle city would otherwise simplify all of it at once).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "farfield/core/bounds.hpp"
#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/techniques/clusters/lod_set.hpp"
#include "farfield/techniques/clusters/mesh_pages.hpp"

namespace farfield {

class Store;
struct BakeShards;

struct ClusterNode {
  Bounds3 bounds;                             // of the objects beneath it, children's included
  uint32_t first_child = 0, child_count = 0;  // children are consecutive nodes
  // ClusterTree::objects: [objects_begin, own_end) lie at this node (on its children's
  // boundaries, or in a leaf), [objects_begin, objects_end) beneath it.
  uint32_t objects_begin = 0, own_end = 0, objects_end = 0;
  uint32_t parts_begin = 0, parts_end = 0;  // ClusterTree::parts: its merged mesh; none: no cluster
  uint32_t triangles = 0;                   // of its merged mesh
  float error_m = 0;                        // of its merged mesh, at least its children's
  uint32_t unused = 0;
  bool clustered() const { return parts_end > parts_begin; }
  bool leaf() const { return child_count == 0; }
};
static_assert(sizeof(ClusterNode) == 64);

// One material of a cluster's mesh: a range of ClusterTree::indices.
struct ClusterPart {
  uint32_t first_index = 0, index_count = 0;
  uint32_t material = 0;
  uint32_t unused = 0;
};
static_assert(sizeof(ClusterPart) == 16);

struct ClusterTreeOptions {
  uint32_t leaf_objects = 16;         // a cell with more objects wholly inside is split
  int max_depth = 16;                 // cells this deep are not split
  uint32_t cluster_triangles = 2048;  // triangles of a cluster's mesh, at most half its objects'
  // A loose octree: an octant takes the objects whose centre it holds that fit in it grown by
  // this share of its size on every side; 0: the paper's cells (an object across a middle
  // stays in the cell, so a city's root holds every object on its two middle lines).
  float loose = 0.5f;
  // A cluster is simplified from at most this many triangles of its objects: their full
  // geometry where it holds no more, else their finest levels that do (the coarsest where none
  // does); 0: always the full geometry (the paper's, whose root takes the whole scene).
  uint64_t input_triangles = uint64_t(1) << 20;
  int threads = 0;  // 0: all cores
};

// The clusters' meshes in pages (mesh_pages.hpp), each what a walk needs at once: page 0 the
// root's, page p > 0 the children of the p-th node that has any (consecutive nodes: the
// nodes are laid out breadth first), which opening that node draws.
struct ClusterTree {
  std::vector<ClusterNode> nodes;  // nodes[0] is the root
  std::vector<uint32_t> objects;   // every object of the scene once, by node (depth first)
  std::vector<ClusterPart> parts;
  std::vector<Vertex> vertices;  // the clusters' meshes (none where GeometryLoad::index_only)
  std::vector<glm::vec2> uvs;    // one per vertex, or empty (untextured scene)
  std::vector<uint32_t> indices;
  std::vector<MeshPage> pages;
  std::vector<uint32_t> node_page;  // per node
  double bake_s = 0;
  uint64_t triangle_count() const { return triangles_of_pages(pages); }
};

// The cells and the objects in them, without meshes (fast: for tests and the mesh bake).
ClusterTree build_cluster_cells(const Scene& scene, const ClusterTreeOptions& options);
// The cells and every cluster's mesh (clusters_triangles each, at most half of its objects').
// `keep`: a pack where finished clusters are kept as the work goes (as build_lod_set's).
// `lods`: the objects' levels (with their meshes) for the clusters of more than
// input_triangles; null: every cluster from the full geometry. Spread over ranks, those
// clusters are rank 0's (the only one to hold every level).
Result<ClusterTree> build_cluster_tree(const Scene& scene, const ClusterTreeOptions& options,
                                       Progress& progress, Store* keep = nullptr,
                                       const BakeShards* shards = nullptr,
                                       const LodSet* lods = nullptr);

// Blobs under "clusters/tree_*" (the pages `clusters/tree_pages`, `clusters/tree_page/N`) and
// back, refusing a missing or inconsistent tree (children or ranges past the arrays, meshes
// outside their pages, objects not each of `scene` once, materials not of `scene`).
Result<void> save_cluster_tree(const ClusterTree& tree, Store& store);
Result<ClusterTree> load_cluster_tree(const Store& store, const Scene& scene,
                                      GeometryLoad geometry = GeometryLoad::whole);
// The name prefix of the tree's pages (read_mesh_page).
inline constexpr const char* kTreePagePrefix = "clusters/tree";

}  // namespace farfield
