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
#include "farfield/techniques/clusters/mesh_arrays.hpp"

namespace farfield {

namespace {

constexpr const char* kVertices = "clusters/lod_vertices";
constexpr const char* kUvs = "clusters/lod_uvs";
constexpr const char* kIndices = "clusters/lod_indices";
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
  set.bake_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return set;
}

void order_lods_by_level(LodSet& set, std::span<const uint32_t> order) {
  std::vector<uint32_t> indices;
  indices.reserve(set.indices.size());
  for (uint32_t level = 0;; ++level) {
    bool any = false;
    for (uint32_t object : order) {
      const uint32_t k = set.first_lod[object] + level;
      if (k >= set.first_lod[object + 1]) continue;
      any = true;
      Lod& lod = set.lods[k];
      const uint32_t first = uint32_t(indices.size());
      indices.insert(indices.end(), set.indices.begin() + lod.first_index,
                     set.indices.begin() + lod.first_index + lod.index_count);
      lod.first_index = first;
    }
    if (!any) break;
  }
  set.indices = std::move(indices);
}

Result<void> save_lod_set(const LodSet& set, Store& store) {
  auto transaction = store.begin();
  if (!transaction) return transaction.error();
  if (auto erased = store.erase("clusters/lod"); !erased) return erased.error();
  if (auto ok = store.put(kVertices, bytes_of(set.vertices)); !ok) return ok;
  if (auto ok = store.put(kUvs, bytes_of(set.uvs)); !ok) return ok;
  if (auto ok = store.put(kIndices, bytes_of(set.indices)); !ok) return ok;
  if (auto ok = store.put(kLods, bytes_of(set.lods)); !ok) return ok;
  return transaction->commit();
}

Result<LodSet> load_lod_set(const Store& store, const Scene& scene) {
  LodSet set;
  auto vertices = read_array<Vertex>(store, kVertices);
  if (!vertices) return vertices.error();
  auto uvs = read_array<glm::vec2>(store, kUvs);
  if (!uvs) return uvs.error();
  auto indices = read_array<uint32_t>(store, kIndices);
  if (!indices) return indices.error();
  auto lods = read_array<Lod>(store, kLods);
  if (!lods) return lods.error();
  auto inconsistent = [&](const char* what) {
    return make_error(store.path(), ": clusters bake is inconsistent (", what, ")");
  };
  if (const char* problem = mesh_arrays_problem(vertices->size(), uvs->size(), *indices))
    return inconsistent(problem);
  set.first_lod.assign(scene.objects.size() + 1, 0);
  for (size_t k = 0; k < lods->size(); ++k) {
    const Lod& l = (*lods)[k];
    if (l.object >= scene.objects.size() || (k > 0 && l.object < (*lods)[k - 1].object))
      return inconsistent("LODs not of this scene's objects, in order");
    if (l.first_index % 3 != 0 || l.index_count % 3 != 0 || l.index_count == 0 ||
        uint64_t(l.first_index) + l.index_count > indices->size())
      return inconsistent("a LOD's triangles");
    if (!(l.error_m >= 0.0f)) return inconsistent("a LOD's error");
    ++set.first_lod[l.object + 1];
  }
  for (size_t i = 1; i < set.first_lod.size(); ++i) set.first_lod[i] += set.first_lod[i - 1];
  set.vertices = std::move(*vertices);
  set.uvs = std::move(*uvs);
  set.indices = std::move(*indices);
  set.lods = std::move(*lods);
  return set;
}

}  // namespace farfield
