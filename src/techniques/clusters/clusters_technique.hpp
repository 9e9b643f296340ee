// clusters: paper 001's walk, first step: every object drawn as the coarsest of its levels of
// detail (lod_set.hpp) whose geometric error projects below `clusters.error_px` pixels from
// the eye, the full object where none does (the screen-space error rule of 3D Tiles; the
// paper's frame-time budget and its cluster hierarchy come next, docs/techniques/clusters.md).
#pragma once

#include <memory>

#include "farfield/core/frustum.hpp"
#include "farfield/spatial/octree.hpp"
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

  ClustersOptions options_;
  const Scene* scene_ = nullptr;
  LodSet lods_;
  gpu::OwnedResources resources_;
  MeshHandle mesh_;                  // lods_ as one scene mesh
  Octree tree_;                      // of objects, for frustum culling
  std::unique_ptr<ObjectSet> full_;  // this frame's objects drawn whole
  std::unique_ptr<ObjectSet> seen_;  // this frame's objects drawn either way
  std::vector<uint32_t> stack_;
  // figures()
  uint64_t frames_ = 0, lods_drawn_ = 0, full_drawn_ = 0;
};

}  // namespace farfield
