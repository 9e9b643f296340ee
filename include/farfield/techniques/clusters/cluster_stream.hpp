// The clusters walk of a scene left on disk (issue 16; bench and view --cache-mb): the
// hierarchy's tables stay in memory (cluster_tree.hpp and lod_set.hpp loaded index only), its
// meshes come page by page from the pack (mesh_pages.hpp) and whole objects chunk by chunk from
// the scene file, through one bounded pool of GPU meshes (gpu/mesh_pool.hpp) loaded on a
// background thread. A frame never waits for them: a choice whose page is not resident is
// asked for (the nearest first) and stood in for by the nearest coarser representation that
// is: a coarser level or the box or average-colour box (average_boxes.hpp: always in memory)
// of the same object, else the cluster (or box) of the lowest node above it whose is, which
// then stands for everything beneath it, so that the frame has no holes and draws nothing
// twice. Boxes wait for their tile (box_atlas.hpp), their average-colour boxes drawn meanwhile.
// The first pages of the hierarchy (its top: the root's
// cluster and the nodes below it, breadth first) are read when the walk starts and never
// leave, so that there is always something to stand in.
#pragma once

#include <chrono>
#include <cstdint>
#include <glm/vec3.hpp>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "farfield/gpu/device.hpp"
#include "farfield/gpu/draw_list.hpp"
#include "farfield/gpu/mesh_pool.hpp"
#include "farfield/scene/chunked_scene.hpp"
#include "farfield/techniques/clusters/box_atlas.hpp"
#include "farfield/techniques/clusters/box_set.hpp"
#include "farfield/techniques/clusters/choice_anchors.hpp"
#include "farfield/techniques/clusters/cluster_selection.hpp"
#include "farfield/techniques/clusters/cluster_tree.hpp"
#include "farfield/techniques/clusters/lod_set.hpp"

namespace farfield {

class Store;

class ClusterStream {
 public:
  // `lods` and `tree` (loaded index only), `boxes`, `box_pages` and `scene` outlive the
  // stream; `store` is the pack they came from (the top pages are read from it now; the loader
  // thread opens the same file again). `budget_bytes` bounds the pages and chunks resident
  // together.
  static Result<std::unique_ptr<ClusterStream>> create(const ChunkedScene& scene,
                                                       const Store& store, const LodSet& lods,
                                                       const ClusterTree& tree, const BoxSet& boxes,
                                                       BoxAtlas& atlas, gpu::Device& device,
                                                       uint64_t budget_bytes,
                                                       bool averages = false);
  ~ClusterStream();
  ClusterStream(const ClusterStream&) = delete;
  ClusterStream& operator=(const ClusterStream&) = delete;

  // A representation as drawn this frame: from `mesh`, its indices less `index_base` (the
  // first index of the page or chunk that mesh holds); boxes have no mesh.
  struct Placed {
    Choice choice;
    MeshHandle mesh;
    uint32_t index_base = 0;
  };
  // This frame's choices as drawn (replacing `out`'s), the missing asked for; returns how many
  // were stood in for.
  uint64_t place(std::span<const Choice> choices, const glm::vec3& eye, std::vector<Placed>& out);
  // Asks, after this frame's own, for what `choices` (a selection for where the viewer is
  // expected to be, `eye`) would draw and is not resident, the nearest to `eye` first.
  void prefetch(std::span<const Choice> choices, const glm::vec3& eye);
  // After place and prefetch (MeshPool::end_frame); returns the wants missed.
  uint64_t end_frame(DrawList& out) { return pool_->end_frame(out); }
  void wait_for_loads(
      std::chrono::steady_clock::time_point until = std::chrono::steady_clock::time_point::max()) {
    pool_->wait_for_loads(until);
  }
  uint64_t ready_bytes() const { return pool_->ready_bytes(); }
  void set_upload_bytes_per_frame(uint64_t bytes) { pool_->set_upload_bytes_per_frame(bytes); }
  const gpu::MeshPoolCounters& counters() const { return pool_->counters(); }
  std::string failure() const { return pool_->failure(); }
  // Bytes of the top pages held for the whole walk (outside the pool's budget).
  uint64_t pinned_bytes() const { return pinned_bytes_; }

 private:
  ClusterStream(const ChunkedScene& scene, const LodSet& lods, const ClusterTree& tree,
                const BoxSet& boxes, BoxAtlas& atlas, gpu::Device& device);
  // Where a choice's triangles are: the pool's key for the page or chunk that holds them
  // (kPinned: the pinned top; kNoMesh: a box, `index_base`; kInMemory: an average-colour box),
  // how near (the pool's priority), and the first index of that page or chunk.
  static constexpr uint64_t kPinned = UINT64_MAX, kNoMesh = UINT64_MAX - 1,
                            kInMemory = UINT64_MAX - 2;
  struct Source {
    uint64_t key;
    float priority;
    uint32_t index_base;
  };
  Source source_of(const Choice& choice, const glm::vec3& eye) const;
  // A page's mesh when resident, not asked for.
  std::optional<MeshHandle> resident_lod_page(uint32_t page);
  std::optional<MeshHandle> resident_tree_page(uint32_t page);
  // Where a tree page's indices start in the mesh that holds it (pinned pages share one mesh).
  uint32_t tree_index_base(uint32_t page) const;
  // The representation standing in for `choice` (its coarser resident one): one of the same
  // object, or a node's (marked in standing_), or none.
  enum class StandIn : uint8_t { none, object, node };
  StandIn stand_in(const Choice& choice, Placed& out);
  StandIn node_stand_in(uint32_t node, Placed& out);
  bool covered(uint32_t node, bool self) const;  // beneath (or at) a node standing in

  const ChunkedScene& scene_;
  const LodSet& lods_;
  const ClusterTree& tree_;
  const BoxSet& boxes_;
  bool averages_ = false;  // every box has an average-colour box (always drawable)
  BoxAtlas& atlas_;
  gpu::Device& device_;
  std::unique_ptr<gpu::MeshPool> pool_;
  MeshHandle pinned_;  // tree pages [0, pinned_pages_), end to end
  uint32_t pinned_pages_ = 0;
  uint64_t pinned_bytes_ = 0;
  ChoiceAnchors anchors_;
  std::vector<uint32_t> box_object_;     // per box: its object; UINT32_MAX: a node's
  std::vector<uint8_t> standing_;        // per node: standing in this frame (2: placed)
  std::vector<uint32_t> standing_list_;  // those nodes
  struct Candidate {
    Placed placed;
    uint32_t node;  // it lies at
    StandIn stand_in;
  };
  std::vector<Candidate> candidates_;
};

}  // namespace farfield
