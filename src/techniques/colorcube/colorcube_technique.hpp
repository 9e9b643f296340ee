// colorcube: the colour-cube octree of paper 002, walked like Barnes-Hut (Sec. 3.1): cells
// outside the frustum are skipped (the paper planned this, Sec. 6.4); a cell whose cubes
// project below the pixel tolerance (cube size / depth < epsilon) draws its cube faces, only
// the orientations that can face the eye; a leaf nearer than that draws the triangles it owns
// (each triangle once per frame); other cells recurse into their children, nearest first.
#pragma once

#include <memory>
#include <string>

#include "farfield/spatial/occlusion_buffer.hpp"
#include "farfield/techniques/colorcube/cube_tree.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

struct ColorcubeOptions {
  CubeTreeOptions tree;
  float pixel_tolerance = 1.0f;  // epsilon as pixels at the view's resolution and field of view
  // Skip cells hidden behind cube faces already drawn this frame (not in the paper, which
  // draws every cell that passes frustum culling). Leaves the image unchanged.
  bool occlusion = true;
  // Bake even when no leaf cube would shrink below the tolerance from where the scene is
  // seen whole (the walk would be octree culling).
  bool force = false;
};

extern const TechniqueDescriptor colorcube_descriptor;

class ColorcubeTechnique final : public Technique {
 public:
  explicit ColorcubeTechnique(const ColorcubeOptions& options) : options_(options) {}
  std::string_view name() const override { return "colorcube"; }
  Result<void> bake(const BakeContext& context) override;
  Result<void> load(const LoadContext& context) override;
  void select(const FrameInput& input, DrawList& out) override;
  std::string describe() const override;
  std::vector<std::pair<std::string, double>> figures() const override;
  const CubeTree& tree() const { return tree_; }

 private:
  Result<void> use(CubeTree tree, const Scene& scene, gpu::Device& device);
  void index_outlines();
  void mark_occluders(uint32_t cell);

  ColorcubeOptions options_;
  CubeTree tree_;
  const Scene* scene_ = nullptr;  // the loaded scene: its materials for the scene ranges
  gpu::OwnedResources resources_;
  MeshHandle mesh_;  // tree_.proxies
  std::vector<uint32_t> stack_;
  OcclusionBuffer occlusion_;
  // Boxes of cubes with an opaque outline, in cubes of the cluster (hi exclusive); those of
  // cell i are outlines_[outline_first_[i] .. outline_first_[i + 1]).
  struct CubeOutline {
    uint8_t lo[3], hi[3];
  };
  std::vector<CubeOutline> outlines_;
  std::vector<uint32_t> outline_first_;
  std::vector<Bounds3> boxes_;  // mark_occluders' scratch
  // figures()
  uint64_t frames_ = 0, cube_faces_drawn_ = 0, leaf_triangles_drawn_ = 0, cells_occluded_ = 0;
};

}  // namespace farfield
