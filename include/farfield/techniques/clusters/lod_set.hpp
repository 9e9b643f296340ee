// Levels of detail of every object of a scene (paper 001, Sec. 4.1.2: each conceptual object
// has "full geometry" and "a chain of simplified LODs"): simplified by scene/simplify from the
// full object at halving triangle counts, each with the distance in metres it may stray from
// the object. The first piece of the clusters technique; the cluster hierarchy of Sec. 4.4
// builds on it.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/techniques/clusters/mesh_pages.hpp"

namespace farfield {

class Store;
struct BakeShards;

// One simplified version of an object: a range of LodSet::indices, its geometric error. An
// instance's (Scene::instances) levels are its prototype's ranges, drawn with the instance's
// placement (DrawRange::instance), so that a field of copies stores and uploads one chain;
// its errors are the prototype's stretched as the instance stretches distances.
struct Lod {
  uint32_t object;
  uint32_t first_index, index_count;  // into LodSet::indices (absolute into its vertices)
  float error_m;                      // never below the previous level's
};
static_assert(sizeof(Lod) == 16);

// A group of neighbouring objects' levels of one rank (their finest, their second, ...) is
// one page (mesh_pages.hpp): what a walk loads at once, and one range of indices, so that
// neighbours drawn at the same level are one draw, where a draw costs as much as hundreds of
// triangles on llvmpipe. Groups are consecutive objects of the page order (the hierarchy's
// depth-first order, whose neighbours are near each other) whose finest levels hold about
// page_triangles.
inline constexpr uint64_t kLodPageTriangles = 32768;

struct LodSetOptions {
  int max_levels = 6;          // simplified levels an object may have
  uint32_t min_triangles = 8;  // an object this small gets no (further) level
  double min_reduction = 0.8;  // a level keeps at most this share of the previous one's triangles
  int threads = 0;             // 0: all cores
  uint64_t page_triangles = kLodPageTriangles;  // of a group's finest levels (below)
};

struct LodSet {
  std::vector<Vertex> vertices;  // empty where loaded GeometryLoad::index_only
  std::vector<glm::vec2> uvs;    // one per vertex (zero on untextured objects), or empty
  std::vector<uint32_t> indices;
  std::vector<Lod> lods;            // by object, finest first
  std::vector<uint32_t> first_lod;  // per object, and one past the last: its lods' range
  std::vector<MeshPage> pages;
  std::vector<uint32_t> lod_page;  // per lod: the page holding it
  // Per object, its instance (into Scene::instances) or kNoInstance; empty in a scene without
  // instances.
  std::vector<uint32_t> object_instance;
  double bake_s = 0;
  uint64_t triangle_count() const { return triangles_of_pages(pages); }
  // The instance whose placement draws `object`'s levels, or kNoInstance.
  uint32_t instance_of(uint32_t object) const {
    return object_instance.empty() ? kNoInstance : object_instance[object];
  }
};

// Laid out in pages of groups of neighbours in `page_order` (every object once; empty: scene
// order), each group's levels a page each, finest first. `keep`: a pack where finished chains
// are kept as the work goes, so that a bake killed and run again redoes only the rest
// (bake_work.hpp); null: nothing kept. `shards`: the bake is spread over ranks
// (technique.hpp); other ranks than 0 get their share.
Result<LodSet> build_lod_set(const Scene& scene, const LodSetOptions& options, Progress& progress,
                             Store* keep = nullptr, const BakeShards* shards = nullptr,
                             std::span<const uint32_t> page_order = {});

// Blobs under "clusters/lod*" (replacing a set there: the levels `clusters/lods` and the pages
// `clusters/lod_pages`, `clusters/lod_page/N`) and back, refusing a missing or inconsistent
// one (ranges past their pages, objects not of `scene`).
Result<void> save_lod_set(const LodSet& set, Store& store);
Result<LodSet> load_lod_set(const Store& store, const Scene& scene,
                            GeometryLoad geometry = GeometryLoad::whole);
// The name prefix of the set's pages (read_mesh_page).
inline constexpr const char* kLodPagePrefix = "clusters/lod";

}  // namespace farfield
