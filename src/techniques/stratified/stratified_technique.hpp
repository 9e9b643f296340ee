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
#include "farfield/techniques/stratified/viewcell_tree.hpp"
#include "farfield/techniques/technique.hpp"

namespace farfield {

class StratifiedTechnique final : public Technique {
 public:
  explicit StratifiedTechnique(const stratified::StratifiedOptions& options)
      : options_(options) {}
  ~StratifiedTechnique() override;
  std::string_view name() const override { return "stratified"; }
  Result<void> load(const Scene& scene) override;
  Result<void> bake(const Scene& scene, Store& store, Progress& progress) override;
  Result<void> load_baked(const Scene& scene, const Store& store) override;
  void select(const View& view, const FrameBudget& budget, DrawList& out) override;
  std::string describe() const override;
  std::vector<std::pair<std::string, double>> figures() const override;
  void annotate(const View& eye, DrawList& list) const override;
  std::string failure() const override;

 private:
  struct Shell {
    stratified::ViewcellTree tree;
    std::vector<uint64_t> baked;  // packed keys, sorted
  };
  // A viewcell's sides in renderer texture slots.
  struct Resident {
    stratified::CellId id;
    uint8_t faces = 0;  // bit F: side F has an image
    uint64_t last_used = 0;
  };
  bool baked(int shell, const stratified::CellKey& key) const;
  // The texture-slot set holding `id`, uploading it (into `out`) if it is not resident.
  int make_resident(const stratified::CellId& id,
                    const std::shared_ptr<const stratified::CellRecord>& record, DrawList& out);
  void add_box(int shell, const stratified::CellKey& key, int set, float opacity,
               DrawList& out) const;
  void prefetch_ahead(const glm::vec3& position);

  stratified::StratifiedOptions options_;
  const Scene* scene_ = nullptr;
  stratified::BakeParams params_;
  std::vector<Shell> shells_;
  std::unique_ptr<stratified::CellLoader> loader_;
  std::unique_ptr<ObjectSet> selected_;
  std::vector<Resident> resident_;  // slot set i: slots 6i .. 6i+5
  // The viewcells this frame's uploads point into: kept until the next select().
  std::vector<std::shared_ptr<const stratified::CellRecord>> uploading_;
  uint64_t frame_ = 0;
  std::optional<glm::vec3> last_position_;
  glm::vec3 velocity_{0.0f};  // metres per frame
  // The frame's viewcells (shell order) and, during a blend, shell 0's previous one.
  std::vector<std::optional<stratified::CellKey>> current_;
  std::optional<stratified::CellKey> previous_;
  uint64_t crossed_at_ = 0;
  // Figures.
  uint64_t crossings_ = 0, stalls_ = 0, unbaked_frames_ = 0, outside_frames_ = 0;
  double bake_s_ = 0.0;
  std::string bake_summary_;  // describe() after a bake
};

}  // namespace farfield
