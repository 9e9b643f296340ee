// clusters: paper 001's walk, first steps: every object drawn as one of its levels of detail
// (lod_set.hpp) or whole: without a frame-time budget the coarsest level whose geometric error
// projects below `clusters.error_px` pixels (the screen-space error rule of 3D Tiles); under
// the engine's budget (bench --budget-ms) the paper's best-first refinement (Sec. 4.5.2)
// among objects. The cluster hierarchy comes next (docs/techniques/clusters.md).
#pragma once

#include <memory>

#include "farfield/core/frustum.hpp"
#include "farfield/spatial/octree.hpp"
#include "farfield/techniques/clusters/frame_cost.hpp"
#include "farfield/techniques/clusters/lod_set.hpp"
#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

extern const TechniqueDescriptor clusters_descriptor;

struct ClustersOptions {
  LodSetOptions lods;
  float error_px = 1.0f;  // the largest projected geometric error, pixels
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

 private:
  Result<void> use(LodSet set, const Scene& scene, gpu::Device& device);
  void choose_by_error(float pixel);
  bool choose_under_budget(const FrameBudget& budget, float pixel);

  static constexpr uint32_t kWhole = UINT32_MAX;  // a Candidate drawn as the full object
  struct Candidate {
    uint32_t object;
    float distance;  // from the eye to the object's box
    uint32_t level;  // into lods_.lods, or kWhole
  };

  ClustersOptions options_;
  const Scene* scene_ = nullptr;
  LodSet lods_;
  gpu::OwnedResources resources_;
  MeshHandle mesh_;                  // lods_ as one scene mesh
  Octree tree_;                      // of objects, for frustum culling
  std::unique_ptr<ObjectSet> full_;  // this frame's objects drawn whole
  std::unique_ptr<ObjectSet> seen_;  // this frame's objects drawn either way
  std::vector<uint32_t> stack_;
  std::vector<Candidate> visible_;                  // this frame's objects in view
  std::vector<std::pair<float, uint32_t>> refine_;  // budget mode: error px, candidate
  FrameCostModel cost_;                             // budget mode: fitted to measured frames
  // figures()
  uint64_t frames_ = 0, lods_drawn_ = 0, full_drawn_ = 0;
};

}  // namespace farfield
