#include "farfield/techniques/clusters/lod_set.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <numeric>

#include "farfield/core/text.hpp"
#include "farfield/scene/instances.hpp"
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

// Per object, its instance or kNoInstance (LodSet::object_instance); empty without any.
std::vector<uint32_t> object_instances(const Scene& scene) {
  std::vector<uint32_t> out;
  if (scene.instances.empty()) return out;
  out.assign(scene.objects.size(), kNoInstance);
  for (uint32_t k = 0; k < scene.instances.size(); ++k) out[scene.instances[k].object] = k;
  return out;
}

// The chains (per object, finest first; an instance's empty) laid out in pages of neighbours
// in `order` (lod_set.hpp), each group's chains freed once laid out, so that the chains and
// the set together stay about one set's size (the arrays reserved whole: `vertices`,
// `indices` in all). An instance's levels are its prototype's ranges, each error stretched
// as the instance stretches distances (instances.hpp: largest_stretch), so that it still
// bounds the copy's distance from its level.
LodSet lay_out_pages(std::vector<PartList>& chains, std::span<const Instance> instances,
                     std::span<const uint32_t> order, uint64_t page_triangles, bool textured,
                     size_t vertices, size_t indices) {
  LodSet set;
  set.vertices.reserve(vertices);
  if (textured) set.uvs.reserve(vertices);
  set.indices.reserve(indices);
  const size_t objects = chains.size();
  set.first_lod.reserve(objects + 1);
  for (size_t i = 0, next = 0; i < objects; ++i) {
    set.first_lod.push_back(uint32_t(set.lods.size()));
    const bool copy = next < instances.size() && instances[next].object == i;
    const float stretch = copy ? float(largest_stretch(instances[next].linear)) : 1.0f;
    for (const SimplifiedPart& lod : chains[copy ? instances[next].prototype : i])
      set.lods.push_back(
          {uint32_t(i), 0, uint32_t(lod.mesh.indices.size()), lod.error_m * stretch});
    next += copy;
  }
  set.first_lod.push_back(uint32_t(set.lods.size()));
  set.lod_page.assign(set.lods.size(), 0);
  std::vector<uint32_t> index_ends;
  for (size_t begin = 0; begin < order.size();) {
    size_t end = begin;
    for (uint64_t triangles = 0; end < order.size() && (end == begin || triangles < page_triangles);
         ++end)
      if (!chains[order[end]].empty()) triangles += chains[order[end]][0].mesh.triangle_count();
    for (uint32_t level = 0;; ++level) {
      bool any = false;
      for (size_t i = begin; i < end; ++i) {
        const uint32_t object = order[i];
        if (level >= chains[object].size()) continue;
        any = true;
        const MeshPart& mesh = chains[object][level].mesh;
        const uint32_t k = set.first_lod[object] + level;
        const size_t base = set.vertices.size();
        set.lods[k].first_index = uint32_t(set.indices.size());
        set.lod_page[k] = uint32_t(index_ends.size());
        set.vertices.insert(set.vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
        if (textured) {
          if (mesh.uvs.empty())
            set.uvs.resize(set.vertices.size());
          else
            set.uvs.insert(set.uvs.end(), mesh.uvs.begin(), mesh.uvs.end());
        }
        for (uint32_t v : mesh.indices) set.indices.push_back(uint32_t(base + v));
      }
      if (!any) break;
      index_ends.push_back(uint32_t(set.indices.size()));
    }
    for (size_t i = begin; i < end; ++i) chains[order[i]] = {};
    begin = end;
  }
  set.pages = pages_of_runs(set.indices, uint32_t(set.vertices.size()), index_ends);
  for (const Instance& instance : instances)
    for (uint32_t l = 0; l < set.first_lod[instance.object + 1] - set.first_lod[instance.object];
         ++l) {
      const uint32_t theirs = set.first_lod[instance.prototype] + l;
      const uint32_t ours = set.first_lod[instance.object] + l;
      set.lods[ours].first_index = set.lods[theirs].first_index;
      set.lod_page[ours] = set.lod_page[theirs];
    }
  return set;
}

}  // namespace

Result<LodSet> build_lod_set(const Scene& scene, const LodSetOptions& o, Progress& progress,
                             Store* keep, const BakeShards* shards,
                             std::span<const uint32_t> page_order) {
  if (o.max_levels < 1 || o.min_reduction <= 0 || o.min_reduction >= 1)
    return make_error("LOD chains need at least one level and a reduction in (0, 1)");
  const auto start = std::chrono::steady_clock::now();
  const size_t objects = scene.objects.size();
  std::vector<uint32_t> scene_order;
  if (page_order.empty()) {
    scene_order.resize(objects);
    std::iota(scene_order.begin(), scene_order.end(), 0u);
  }
  const std::span<const uint32_t> order_of_pages = page_order.empty() ? scene_order : page_order;
  if (order_of_pages.size() != objects)
    return make_error(formatted("LOD pages: an order of %zu objects for a scene of %zu",
                                order_of_pages.size(), objects));
  auto work = BakeWork::open(
      keep, "lods",
      formatted("scene %016llx, %d levels, %u triangles, reduction %.17g, instances moved",
                (unsigned long long)scene_fingerprint(scene), o.max_levels, o.min_triangles,
                o.min_reduction),
      shards);
  if (!work) return work.error();
  // Only objects that are not instances are simplified (the work's items); an instance's chain
  // is its prototype's, moved.
  std::vector<uint32_t> own;  // per item, its object
  own.reserve(objects - scene.instances.size());
  for (uint32_t i = 0, next = 0; i < objects; ++i)
    if (next < scene.instances.size() && scene.instances[next].object == i)
      ++next;
    else
      own.push_back(i);
  // The objects with the most triangles first, so that the last to finish are small.
  std::vector<uint32_t> order(own.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t l, uint32_t r) {
    return scene.objects[own[l]].index_count > scene.objects[own[r]].index_count;
  });
  auto simplified = work->run("simplify objects", "objects", own.size(), order, 64, o.threads,
                              progress, [&](uint32_t i) { return lod_chain(scene, own[i], o); });
  if (!simplified) return simplified.error();
  std::vector<PartList> chains(objects);
  for (size_t i = 0; i < own.size(); ++i) chains[own[i]] = std::move((*simplified)[i]);

  const PartSizes sizes = sizes_of(chains);
  if (!sizes.fit_uint32())
    return make_error("the scene's LODs need more than 2^32 vertices or indices");
  LodSet set = lay_out_pages(chains, scene.instances, order_of_pages, o.page_triangles,
                             !scene.uvs.empty(), sizes.vertices, sizes.indices);
  set.object_instance = object_instances(scene);
  set.bake_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return set;
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
  for (const Instance& instance : scene.instances) {
    const uint32_t ours = set.first_lod[instance.object];
    const uint32_t theirs = set.first_lod[instance.prototype];
    if (set.first_lod[instance.object + 1] - ours !=
        set.first_lod[instance.prototype + 1] - theirs)
      return inconsistent("an instance's levels not its prototype's");
    for (uint32_t l = 0; l < set.first_lod[instance.object + 1] - ours; ++l)
      if ((*lods)[ours + l].first_index != (*lods)[theirs + l].first_index ||
          (*lods)[ours + l].index_count != (*lods)[theirs + l].index_count)
        return inconsistent("an instance's levels not its prototype's");
  }
  set.object_instance = object_instances(scene);
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
