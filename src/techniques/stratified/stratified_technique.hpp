// stratified: Stratified Rendering of paper 000. The bake cuts the navigable region into
// viewcells (a k-d tree, Sec. 3.1.1) and renders, from each viewcell's centre, the far objects
// (those wholly outside the viewcell's bounding box) onto the box's sides (Sec. 3.1.3), into
// the pack. The walk finds the viewpoint's viewcell, draws its near objects culled to the
// frustum in front of the textured box, and prefetches the viewcells ahead on a background
// thread (Sec. 3.2). Shells of boxes (Ch. 4) nest further far fields around the first.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cell_loader.hpp"
#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/stratified/stratified_options.hpp"
#include "farfield/techniques/stratified/stratified_pack.hpp"
#include "farfield/spatial/viewcell_tree.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

extern const TechniqueDescriptor stratified_descriptor;

class StratifiedTechnique final : public Technique {
 public:
  explicit StratifiedTechnique(const stratified::StratifiedOptions& options) : options_(options) {}
  ~StratifiedTechnique() override;
  std::string_view name() const override { return "stratified"; }
  Result<void> bake(const BakeContext& context) override;
  Result<void> load(const LoadContext& context) override;
  void select(const FrameInput& input, DrawList& out) override;
  std::optional<Bounds3> far_field_box() const override { return far_box_; }
  uint64_t fallback_frames() const override {
    return unbaked_frames_ + outside_frames_ + damaged_frames_;
  }
  std::optional<CameraPose> start_pose() const override;
  std::string describe() const override;
  std::vector<std::pair<std::string, double>> figures() const override;
  void annotate(const View& eye, DrawList& list) const override;
  std::string failure() const override;

 private:
  struct Shell {
    ViewcellTree tree;
    std::vector<uint64_t> baked;  // packed keys, sorted
  };
  // A viewcell's sides in one of the sets of six textures.
  struct Resident {
    stratified::CellId id;
    uint8_t faces = 0;  // bit F: side F has an image
    uint64_t last_used = 0;
  };
  bool baked(int shell, const CellKey& key) const;
  // The texture set holding `id`, uploading it (into `out`) if it is not resident.
  int make_resident(const stratified::CellId& id,
                    const std::shared_ptr<const stratified::CellRecord>& record, DrawList& out);
  void add_box(int shell, const CellKey& key, int set, float opacity, DrawList& out) const;
  void prefetch_ahead(const glm::vec3& position);

  stratified::StratifiedOptions options_;
  const Scene* scene_ = nullptr;
  stratified::BakeParams params_;
  std::vector<Shell> shells_;
  std::unique_ptr<stratified::CellLoader> loader_;
  std::unique_ptr<ObjectSet> selected_;
  gpu::OwnedResources resources_;
  std::vector<TextureHandle> textures_;  // set i: textures_[6i .. 6i+5], one per box side
  std::vector<Resident> resident_;       // set i
  std::optional<Bounds3> far_box_;       // this frame's, for far_field_box()
  uint64_t frame_ = 0;
  std::optional<glm::vec3> last_position_;
  glm::vec3 velocity_{0.0f};  // metres per frame
  // The frame's viewcells (shell order) and, during a blend, shell 0's previous one.
  std::vector<std::optional<CellKey>> current_;
  std::optional<CellKey> previous_;
  uint64_t crossed_at_ = 0;
  // Figures.
  uint64_t crossings_ = 0, stalls_ = 0, unbaked_frames_ = 0, outside_frames_ = 0,
           damaged_frames_ = 0;
  double bake_s_ = 0.0;
  std::string bake_summary_;  // describe() after a bake
};

}  // namespace farfield
