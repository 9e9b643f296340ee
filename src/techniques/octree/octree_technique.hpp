// octree: view-frustum culling with an octree of objects (paper 004, Sec. 2.1). A node fully
// inside the frustum draws everything below it without further tests; a partial node
// recurses; a node outside is skipped. Objects that span several leaves are drawn once.
//
// Two variants:
//   octree        plane test (conservative), and objects of a partially visible leaf tested
//                 one by one against the frustum;
//   octree-paper  the paper's corner-projection test and whole leaves drawn (paper 004,
//                 "Determining the Visibility of a Volume"); not conservative, see frustum.hpp.
#pragma once

#include <memory>

#include "farfield/core/frustum.hpp"
#include "farfield/spatial/occluders.hpp"
#include "farfield/spatial/occlusion_map.hpp"
#include "farfield/spatial/octree.hpp"
#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

extern const TechniqueDescriptor octree_descriptor;
extern const TechniqueDescriptor octree_paper_descriptor;

struct OctreeTechniqueOptions {
  OctreeOptions tree;
  bool paper_visibility_test = false;  // paper 004's corner projection instead of planes
  bool test_objects_in_leaves = true;  // cull the objects of a partially visible leaf
  bool occlusion = false;              // also cull what the nearest objects hide (issue 14)
  OccluderOptions occluders;
};

class OctreeTechnique final : public Technique {
 public:
  OctreeTechnique(std::string name, const OctreeTechniqueOptions& options)
      : name_(std::move(name)), options_(options) {}
  std::string_view name() const override { return name_; }
  Result<void> load(const LoadContext& context) override;
  void select(const FrameInput& input, DrawList& out) override;
  std::string describe() const override;

  const Octree& tree() const { return tree_; }

 private:
  Visibility classify(const Frustum& frustum, const Bounds3& box) const;

  std::string name_;
  OctreeTechniqueOptions options_;
  const Scene* scene_ = nullptr;
  Octree tree_;
  std::unique_ptr<ObjectSet> visible_;
  std::vector<uint32_t> stack_;
  std::unique_ptr<Occluders> occluders_;  // null: occlusion off
  OcclusionMap occlusion_;
};

}  // namespace farfield
