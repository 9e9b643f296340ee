// clusters: paper 001's walk over its cluster hierarchy (cluster_tree.hpp): textured boxes of
// clusters and objects (box_set.hpp, from a bake), clusters' merged meshes, objects' levels
// of detail (lod_set.hpp) and whole objects, chosen by
// cluster_selection.hpp: without a frame-time budget the coarsest whose geometric error
// projects below `clusters.error_px` pixels (the screen-space error rule of 3D Tiles); under
// the engine's budget (bench --budget-ms) the paper's best-first refinement (Sec. 4.5.2),
// the budget turned into triangles by a cost model fitted to the frames measured.
#pragma once

#include <chrono>
#include <memory>

#include "farfield/core/frustum.hpp"
#include "farfield/spatial/occluders.hpp"
#include "farfield/spatial/occlusion_map.hpp"
#include "farfield/techniques/clusters/accuracy_table.hpp"
#include "farfield/techniques/clusters/average_boxes.hpp"
#include "farfield/techniques/clusters/budget_target.hpp"
#include "farfield/techniques/clusters/cluster_selection.hpp"
#include "farfield/techniques/clusters/cluster_stream.hpp"
#include "farfield/techniques/clusters/cluster_tree.hpp"
#include "farfield/techniques/clusters/frame_cost.hpp"
#include "farfield/techniques/clusters/lod_set.hpp"
#include "farfield/techniques/clusters/pseudo_maps.hpp"
#include "farfield/techniques/clusters/switch_fades.hpp"
#include "farfield/techniques/clusters/upload_cost.hpp"
#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

extern const TechniqueDescriptor clusters_descriptor;

struct ClustersOptions {
  LodSetOptions lods;
  ClusterTreeOptions tree;
  bool boxes = true;  // bake textured boxes (BoxSetOptions::clusters: of clusters too)
  BoxSetOptions box;
  // Object boxes drawn as billboards: of trees, of every object, or none.
  enum class Billboards : uint8_t { trees, all, none } billboards = Billboards::trees;
  bool accuracy_tables = true;  // bake the accuracy tables
  AccuracyOptions accuracy;
  // Where the pack has tables: image, their errors down to their finest texel and the
  // geometric ones below it; tables, their errors at every scale (extrapolated below their
  // finest texel); geometric, the geometric errors alone.
  enum class Errors : uint8_t { image, tables, geometric };
  Errors errors = Errors::image;
  BenefitWeights benefit;
  float error_px = 1.0f;    // the largest projected geometric error, pixels
  float average_px = 1.0f;  // boxes of subjects smaller on screen: average-colour boxes
  ClusterTraversal traversal = ClusterTraversal::refined;
  int hysteresis = 12;       // frames (paper 001, Sec. 4.6)
  double over_share = 0.03;  // under a budget, frames let run over 1.1x it (budget_target.hpp)
  int pseudo_px = 0;     // > 0: the boxes drawn as pseudo-texture maps of at most this many texels
  int blend_frames = 0;  // a switch cross-faded over this many frames (Sec. 5.4); 0: at once
  bool cost_pixels = false;  // the cost model has a part per pixel covered (frame_cost.hpp)
  HysteresisRule hysteresis_rule = HysteresisRule::paper;
  bool wait = false;         // scene on disk: wait for the pages chosen (tests, references)
  int prefetch_frames = 15;  // scene on disk: ask for where the viewer will be; 0: not
  int box_tile_px = 0;    // the boxes' tiles (box_atlas.hpp); 0: 512 on disk, the pages in memory
  bool occlusion = true;  // cull with what the nearest opaque objects hide
  // Boxes inside them, their own triangles, or boxes under a budget and triangles without.
  enum class Occluders : uint8_t { automatic, boxes, meshes } occluders = Occluders::automatic;
  uint32_t occluder_count = 128;  // a frame, nearest first (OccluderOptions::per_frame)
};

class ClustersTechnique final : public Technique {
 public:
  explicit ClustersTechnique(const ClustersOptions& options) : options_(options) {}
  std::string_view name() const override { return "clusters"; }
  Result<void> bake(const BakeContext& context) override;
  Result<void> load(const LoadContext& context) override;
  void select(const FrameInput& input, DrawList& out) override;
  std::string describe() const override;
  std::vector<std::pair<std::string, double>> figures() const override;
  std::string failure() const override;
  // Whole objects grey, levels of detail green, clusters orange.
  void tint(DrawList& list) const override;

 private:
  Result<void> use(LodSet lods, ClusterTree tree, BoxSet boxes, std::vector<AverageBox> averages,
                   AccuracyTable accuracy, const LoadContext& context);
  bool starting() const;  // a walk from disk's start-up frames (waiting for their pages)
  void place(DrawList& out);
  size_t add_averages(DrawList& out);
  // The pixels this frame's drawn choices (and those fading out) cover on screen, overlaps
  // counted as often as they overlap (projected_pixels of their bounds).
  double covered_pixels(const View& view) const;
  Bounds3 bounds_of(const Choice& choice) const;
  bool has_averages() const { return !averages_.empty(); }

  ClustersOptions options_;
  const Scene* scene_ = nullptr;
  LodSet lods_;
  ClusterTree tree_;
  size_t clusters_ = 0;               // nodes of tree_ with a cluster
  BoxSet boxes_;                      // without pixels: they are atlas_'s
  std::vector<AverageBox> averages_;  // one per box, or none
  std::vector<uint32_t> averages_chosen_;
  PseudoMaps pseudo_;  // clusters.pseudo_px: the boxes' images as meshes; else empty
  std::vector<uint32_t> pseudo_chosen_;
  std::vector<uint8_t> billboard_;  // per box: drawn as a billboard
  std::vector<uint32_t> billboards_chosen_;
  MeshHandle average_mesh_;  // this frame's average-colour and pseudo-texture boxes
  TextureHandle white_;
  AccuracyTable accuracy_;
  float accuracy_px_ = 0.0f;  // texels across a subject at the tables' finest comparison
  std::unique_ptr<BoxAtlas> atlas_;
  std::vector<uint32_t> boxes_chosen_;
  bool upload_frame_ = false;        // the last frame uploaded every page at once
  double last_predicted_ms_ = -1.0;  // the last frame's; < 0: none
  double last_needed_ = INFINITY;    // SelectionStats::needed of the last frame
  double probe_triangles_ = 0.0;     // the budget asked while the cost model learns
  BudgetTarget budget_target_;
  glm::vec3 last_eye_{0.0f};
  gpu::OwnedResources resources_;
  MeshHandle lod_mesh_, cluster_mesh_;  // lods_ and tree_'s clusters as scene meshes
  std::unique_ptr<ClusterSelection> selection_;
  std::unique_ptr<SwitchFades> fades_;  // blended switches, with the scene in memory
  std::unique_ptr<ObjectSet> full_;     // this frame's objects drawn whole
  std::vector<Choice> choices_;
  std::unique_ptr<ClusterStream> stream_;  // the scene on disk: meshes streamed, else null
  std::vector<ClusterStream::Placed> placed_, streamed_whole_;
  // The scene on disk: a selection of its own (its temporal state apart) for where the
  // viewer is expected, made every few frames and prefetched every frame.
  std::unique_ptr<ClusterSelection> ahead_selection_;
  std::vector<Choice> ahead_choices_;
  glm::vec3 ahead_eye_{0.0f};
  std::vector<Bounds3> occluder_boxes_;        // per object, from the bake; empty: none baked
  std::unique_ptr<Occluders> occluders_;       // boxes; null: none (clusters.occlusion=0)
  std::unique_ptr<Occluders> mesh_occluders_;  // the objects' own triangles
  OcclusionMap occlusion_;
  FrameCostModel cost_;  // budget mode: fitted to measured frames, less their uploads
  UploadCost upload_cost_;
  UploadBytes last_upload_bytes_;  // the last frame's list's
  double last_pixels_ = 0.0;       // the last frame's choices on screen (projected_pixels)
  // figures()
  uint64_t frames_ = 0, clusters_drawn_ = 0, lods_drawn_ = 0, full_drawn_ = 0, visited_ = 0;
  std::vector<double> selection_ms_;  // the hierarchy's traversal alone, each frame
  uint64_t boxes_drawn_ = 0, averages_drawn_ = 0, billboards_drawn_ = 0;
  uint64_t switches_ = 0;
  uint64_t coarser_frames_ = 0, stood_in_ = 0;  // with the scene on disk
  double budget_ms_ = 0.0;  // this frame's frame-time budget; 0: chosen by error alone
  bool budgeted() const { return budget_ms_ > 0.0; }
  std::chrono::steady_clock::time_point frame_start_;  // select() of this frame began
};

}  // namespace farfield
