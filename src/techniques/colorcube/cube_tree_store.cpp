// The colour-cube tree in a .ffpack store: the cells, proxy vertices and indices, the leaves'
// scene ranges and the
// statistics as zstd blobs, paper 002's Table 1 as metadata. Which scene it was made for is
// the bake record's business (store/bake_record.hpp). Reading checks every index before the
// tree is used.
#include <cstring>
#include <string>

#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/colorcube/cube_tree.hpp"

namespace farfield {

namespace {

constexpr const char* kCells = "colorcube/cells";
constexpr const char* kVertices = "colorcube/proxy_vertices";
constexpr const char* kIndices = "colorcube/proxy_indices";
constexpr const char* kSceneRanges = "colorcube/scene_ranges";
constexpr const char* kStats = "colorcube/stats";

// A scene range as stored (the layout DrawRange had when the format was made; a leaf's ranges
// are the scene's own, placed by no instance).
struct StoredRange {
  uint32_t first_index, index_count, material, mesh;
};
static_assert(sizeof(StoredRange) == 16);

}  // namespace

Result<void> save_cube_tree(const CubeTree& tree, Store& store) {
  auto transaction = store.begin();
  if (!transaction) return transaction.error();
  if (auto erased = store.erase("colorcube/"); !erased) return erased.error();
  if (auto ok = store.put(kCells, bytes_of(tree.cells)); !ok) return ok;
  if (auto ok = store.put(kVertices, bytes_of(tree.proxies.vertices)); !ok) return ok;
  if (auto ok = store.put(kIndices, bytes_of(tree.proxies.indices)); !ok) return ok;
  std::vector<StoredRange> ranges;
  ranges.reserve(tree.scene_ranges.size());
  for (const DrawRange& r : tree.scene_ranges)
    ranges.push_back({r.first_index, r.index_count, r.material, r.mesh.id});
  if (auto ok = store.put(kSceneRanges, bytes_of(ranges)); !ok) return ok;
  const std::vector<CubeTreeStats> stats{tree.stats};
  if (auto ok = store.put(kStats, bytes_of(stats)); !ok) return ok;
  const CubeTreeStats& s = tree.stats;
  const std::string table =
      "cells " + std::to_string(s.cells) + ", levels " + std::to_string(s.levels) + ", cluster " +
      std::to_string(s.cluster) + ", oversampling " + std::to_string(s.oversampling) +
      ", cube faces " + std::to_string(s.cube_faces) + " (inner faces dropped " +
      std::to_string(s.inner_faces_dropped) + ")" + ", preprocessing " +
      std::to_string(s.leaf_bake_s) + " s + " + std::to_string(s.hierarchy_s) + " s";
  if (auto ok = store.set_meta("colorcube/table1", table); !ok) return ok;
  return transaction->commit();
}

Result<CubeTree> load_cube_tree(const Store& store, const Scene& scene) {
  CubeTree tree;
  auto cells = read_array<CubeCell>(store, kCells);
  if (!cells) return cells.error();
  auto vertices = read_array<ProxyVertex>(store, kVertices);
  if (!vertices) return vertices.error();
  auto indices = read_array<uint32_t>(store, kIndices);
  if (!indices) return indices.error();
  auto scene_ranges = read_array<StoredRange>(store, kSceneRanges);
  if (!scene_ranges) return scene_ranges.error();
  auto stats = read_array<CubeTreeStats>(store, kStats);
  if (!stats) return stats.error();
  auto inconsistent = [&](const char* what) {
    return make_error(store.path(), ": colorcube bake is inconsistent (", what, ")");
  };
  if (stats->size() != 1) return inconsistent("statistics");
  if (cells->empty()) return inconsistent("no cells");
  for (uint32_t index : *indices)
    if (index >= vertices->size()) return inconsistent("a proxy index past the vertices");
  for (const StoredRange& r : *scene_ranges)
    if (r.first_index % 3 != 0 || r.index_count % 3 != 0 ||
        uint64_t(r.first_index) + r.index_count > scene.indices.size() ||
        r.material >= scene.materials.size() || r.mesh != 0)
      return inconsistent("a scene range past the scene");
  for (size_t i = 0; i < cells->size(); ++i) {
    const CubeCell& c = (*cells)[i];
    if (c.child_count > 8 ||
        (c.child_count > 0 &&
         (c.first_child <= i || uint64_t(c.first_child) + c.child_count > cells->size())))
      return inconsistent("a cell's children");
    auto range_ok = [&](uint32_t first, uint32_t count) {
      return first % 3 == 0 && count % 3 == 0 && uint64_t(first) + count <= indices->size();
    };
    for (int f = 0; f < 6; ++f)
      if (!range_ok(c.faces_begin[f], c.faces_count[f])) return inconsistent("a face batch");
    if (!range_ok(c.geometry_begin, c.geometry_count)) return inconsistent("a leaf's triangles");
    if (uint64_t(c.scene_ranges_begin) + c.scene_ranges_count > scene_ranges->size())
      return inconsistent("a leaf's textured triangles");
  }
  tree.cells = std::move(*cells);
  tree.proxies.vertices = std::move(*vertices);
  tree.proxies.indices = std::move(*indices);
  tree.scene_ranges.reserve(scene_ranges->size());
  for (const StoredRange& r : *scene_ranges)
    tree.scene_ranges.push_back({r.first_index, r.index_count, r.material});
  tree.stats = (*stats)[0];
  return tree;
}

}  // namespace farfield
