#include "farfield/techniques/clusters/lod_set.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <numeric>

#include "farfield/core/text.hpp"
#include "farfield/scene/simplify.hpp"
#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/clusters/bake_work.hpp"

namespace farfield {

namespace {

constexpr const char* kLods = "clusters/lods";

// An object's chain: each level simplified from the full object (errors do not add up), kept
// while it removes enough triangles; errors made non-decreasing (a larger bound still bounds).
std::vector<SimplifiedPart> lod_chain(const Scene& scene, uint32_t object, const LodSetOptions& o) {
  std::vector<SimplifiedPart> chain;
  const uint32_t ids[] = {object};
  const MeshPart full = gather_part(scene, ids, scene.objects[object].material);
  uint64_t previous = full.triangle_count();
  float error = 0.0f;
  double ratio = 0.5;
  for (int level = 0; level < o.max_levels && previous > o.min_triangles; ++level, ratio *= 0.5) {
    SimplifiedPart lod = simplify_part(full, {.target_ratio = ratio});
    const uint64_t triangles = lod.mesh.triangle_count();
    if (triangles == 0 || double(triangles) > o.min_reduction * double(previous)) continue;
    error = std::max(error, lod.error_m);
    lod.error_m = error;
    previous = triangles;
    chain.push_back(std::move(lod));
  }
  return chain;
}

}  // namespace

Result<LodSet> build_lod_set(const Scene& scene, const LodSetOptions& o, Progress& progress,
                             Store* keep, const BakeShards* shards) {
  if (o.max_levels < 1 || o.min_reduction <= 0 || o.min_reduction >= 1)
    return make_error("LOD chains need at least one level and a reduction in (0, 1)");
  const auto start = std::chrono::steady_clock::now();
  const size_t objects = scene.objects.size();
  auto work = BakeWork::open(keep, "lods",
                             formatted("scene %016llx, %d levels, %u triangles, reduction %.17g",
                                       (unsigned long long)scene_fingerprint(scene), o.max_levels,
                                       o.min_triangles, o.min_reduction),
                             shards);
  if (!work) return work.error();
  // The objects with the most triangles first, so that the last to finish are small.
  std::vector<uint32_t> order(objects);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t l, uint32_t r) {
    return scene.objects[l].index_count > scene.objects[r].index_count;
  });
  auto chains = work->run("simplify objects", "objects", objects, order, 64, o.threads, progress,
                          [&](uint32_t i) { return lod_chain(scene, i, o); });
  if (!chains) return chains.error();

  LodSet set;
  const bool textured = !scene.uvs.empty();
  set.first_lod.reserve(objects + 1);
  for (size_t i = 0; i < objects; ++i) {
    set.first_lod.push_back(uint32_t(set.lods.size()));
    for (SimplifiedPart& lod : (*chains)[i]) {
      const uint32_t base = uint32_t(set.vertices.size());
      if (uint64_t(base) + lod.mesh.vertices.size() >= UINT32_MAX ||
          set.indices.size() + lod.mesh.indices.size() >= UINT32_MAX)
        return make_error("the scene's LODs need more than 2^32 vertices or indices");
      set.lods.push_back({uint32_t(i), uint32_t(set.indices.size()),
                          uint32_t(lod.mesh.indices.size()), lod.error_m});
      set.vertices.insert(set.vertices.end(), lod.mesh.vertices.begin(), lod.mesh.vertices.end());
      if (textured) {
        if (lod.mesh.uvs.empty())
          set.uvs.resize(set.vertices.size());
        else
          set.uvs.insert(set.uvs.end(), lod.mesh.uvs.begin(), lod.mesh.uvs.end());
      }
      for (uint32_t v : lod.mesh.indices) set.indices.push_back(base + v);
    }
    (*chains)[i] = {};
  }
  set.first_lod.push_back(uint32_t(set.lods.size()));
  std::vector<uint32_t> scene_order(objects);
  std::iota(scene_order.begin(), scene_order.end(), 0u);
  page_lods(set, scene_order);
  set.bake_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return set;
}

void page_lods(LodSet& set, std::span<const uint32_t> order, uint64_t page_triangles) {
  std::vector<Vertex> vertices;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> indices, index_ends;
  vertices.reserve(set.vertices.size());
  uvs.reserve(set.uvs.size());
  indices.reserve(set.indices.size());
  set.lod_page.assign(set.lods.size(), 0);
  for (size_t begin = 0; begin < order.size();) {
    size_t end = begin;
    for (uint64_t triangles = 0; end < order.size() && (end == begin || triangles < page_triangles);
         ++end) {
      const uint32_t object = order[end];
      if (set.first_lod[object] < set.first_lod[object + 1])
        triangles += set.lods[set.first_lod[object]].index_count / 3;
    }
    for (uint32_t level = 0;; ++level) {
      bool any = false;
      for (size_t i = begin; i < end; ++i) {
        const uint32_t k = set.first_lod[order[i]] + level;
        if (k >= set.first_lod[order[i] + 1]) continue;
        any = true;
        Lod& lod = set.lods[k];
        // A level's vertices are one run, as it was appended.
        const auto first = set.indices.begin() + lod.first_index;
        const auto [low, high] = std::minmax_element(first, first + lod.index_count);
        const uint32_t base = uint32_t(vertices.size());
        vertices.insert(vertices.end(), set.vertices.begin() + *low,
                        set.vertices.begin() + *high + 1);
        if (!set.uvs.empty())
          uvs.insert(uvs.end(), set.uvs.begin() + *low, set.uvs.begin() + *high + 1);
        const uint32_t from = *low;
        lod.first_index = uint32_t(indices.size());
        for (auto it = first; it != first + lod.index_count; ++it)
          indices.push_back(*it - from + base);
        set.lod_page[k] = uint32_t(index_ends.size());
      }
      if (!any) break;
      index_ends.push_back(uint32_t(indices.size()));
    }
    begin = end;
  }
  set.pages = pages_of_runs(indices, uint32_t(vertices.size()), index_ends);
  set.vertices = std::move(vertices);
  set.uvs = std::move(uvs);
  set.indices = std::move(indices);
}

Result<void> save_lod_set(const LodSet& set, Store& store) {
  auto transaction = store.begin();
  if (!transaction) return transaction.error();
  if (auto erased = store.erase(kLodPagePrefix); !erased) return erased.error();
  if (auto ok = store.put(kLods, bytes_of(set.lods)); !ok) return ok;
  if (auto ok = save_mesh_pages(store, kLodPagePrefix, set.vertices, set.uvs, set.indices,
                                set.pages);
      !ok)
    return ok;
  return transaction->commit();
}

Result<LodSet> load_lod_set(const Store& store, const Scene& scene, GeometryLoad geometry) {
  LodSet set;
  auto lods = read_array<Lod>(store, kLods);
  if (!lods) return lods.error();
  auto pages = load_mesh_page_table(store, kLodPagePrefix);
  if (!pages) return pages.error();
  auto inconsistent = [&](const char* what) {
    return make_error(store.path(), ": clusters bake is inconsistent (", what, ")");
  };
  set.first_lod.assign(scene.objects.size() + 1, 0);
  set.lod_page.resize(lods->size());
  for (size_t k = 0; k < lods->size(); ++k) {
    const Lod& l = (*lods)[k];
    if (l.object >= scene.objects.size() || (k > 0 && l.object < (*lods)[k - 1].object))
      return inconsistent("LODs not of this scene's objects, in order");
    // The page whose indices begin at or before the level's.
    const auto page = std::upper_bound(pages->begin(), pages->end(), l.first_index,
                                       [](uint32_t first, const MeshPage& p) {
                                         return first < p.first_index;
                                       });
    if (l.first_index % 3 != 0 || l.index_count % 3 != 0 || l.index_count == 0 ||
        page == pages->begin() || !(page - 1)->holds(l.first_index, l.index_count))
      return inconsistent("a LOD's triangles");
    set.lod_page[k] = uint32_t(page - 1 - pages->begin());
    if (!(l.error_m >= 0.0f)) return inconsistent("a LOD's error");
    ++set.first_lod[l.object + 1];
  }
  for (size_t i = 1; i < set.first_lod.size(); ++i) set.first_lod[i] += set.first_lod[i - 1];
  if (geometry == GeometryLoad::whole)
    if (auto read = read_mesh_pages(store, kLodPagePrefix, *pages, set.vertices, set.uvs,
                                    set.indices);
        !read)
      return read.error();
  set.lods = std::move(*lods);
  set.pages = std::move(*pages);
  return set;
}

}  // namespace farfield
