// portal: rendering through cells and portals (paper 004, "Plan to implement portals", which
// the paper planned and never built; Luebke and Georges, 1995). The eye's cell is drawn, its
// objects through an octree culled by the view volume, and every portal in view narrows the
// volume and leads to the cell behind it (spatial/portal_walk.hpp): `portal` clips the view
// by each portal polygon, `portal-paper` intersects the portals' screen rectangles (the
// paper's plan). An eye outside every cell (and every eye, in a scene without cells)
// falls back to frustum culling of the whole scene (counted in fallback_frames), and so does
// a chain past the walk's limits, for the part of the view it reaches: both keep the image
// brute force draws.
#pragma once

#include <vector>

#include "farfield/core/convex_volume.hpp"
#include "farfield/spatial/octree.hpp"
#include "farfield/spatial/portal_walk.hpp"
#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

extern const TechniqueDescriptor portal_descriptor;
extern const TechniqueDescriptor portal_paper_descriptor;

struct PortalTechniqueOptions {
  PortalWalkOptions walk;
  uint32_t objects_per_leaf = 8;  // of each cell's octree
};

class PortalTechnique final : public Technique {
 public:
  PortalTechnique(std::string name, const PortalTechniqueOptions& options)
      : name_(std::move(name)), options_(options) {}
  std::string_view name() const override { return name_; }
  Result<void> load(const LoadContext& context) override;
  void select(const FrameInput& input, DrawList& out) override;
  uint64_t fallback_frames() const override { return fallback_frames_; }
  std::string describe() const override;
  std::vector<std::pair<std::string, double>> figures() const override;
  void annotate(const View& eye, DrawList& list) const override;

  // The last frame's visits (empty after a fallback frame).
  const std::vector<CellVisit>& visits() const { return visits_; }

 private:
  // Inserts the objects of `tree` (numbered through `objects`) that `volume` may see.
  void collect(const Octree& tree, std::span<const uint32_t> objects, const ConvexVolume& volume,
               const Bounds3* near_box);

  std::string name_;
  PortalTechniqueOptions options_;
  const Scene* scene_ = nullptr;
  std::vector<Octree> cell_trees_;  // per cell, over its objects
  Octree scene_tree_;               // every object, for the fallbacks
  std::vector<uint32_t> all_objects_;
  std::unique_ptr<PortalWalk> walk_;
  std::unique_ptr<ObjectSet> visible_;
  std::vector<CellVisit> visits_;
  std::vector<uint32_t> stack_;
  uint64_t frames_ = 0, fallback_frames_ = 0, visits_total_ = 0, limit_frames_ = 0;
};

}  // namespace farfield
