// composite: the near field from one technique, the far field from another (DESIGN.md). Each
// frame the far technique draws only its far field (Region::far_field) and names the box
// beyond which it stands in for the scene; the near technique then draws the objects that
// meet that box (Region::near). Where the far technique has no far field (outside its bake),
// the near technique draws the whole scene and the frame counts as a fallback. The budget is
// split between the two by `near_share`.
#pragma once

#include <memory>

#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

extern const TechniqueDescriptor composite_descriptor;

class CompositeTechnique final : public Technique {
 public:
  CompositeTechnique(std::unique_ptr<Technique> near, std::unique_ptr<Technique> far,
                     double near_share)
      : near_(std::move(near)), far_(std::move(far)), near_share_(near_share) {}
  std::string_view name() const override { return "composite"; }
  Result<void> load(const LoadContext& context) override;
  void select(const FrameInput& input, DrawList& out) override;
  void frame_done(uint64_t frame) override;
  std::optional<Bounds3> far_field_box() const override { return far_->far_field_box(); }
  uint64_t fallback_frames() const override { return fallback_frames_; }
  std::string describe() const override;
  std::vector<std::pair<std::string, double>> figures() const override;
  void annotate(const View& eye, DrawList& list) const override;
  std::string failure() const override;

 private:
  std::unique_ptr<Technique> near_, far_;
  double near_share_;
  uint64_t frames_ = 0, fallback_frames_ = 0;
};

}  // namespace farfield
