#include "brute_technique.hpp"

namespace farfield {

const TechniqueDescriptor brute_descriptor{
    .name = "brute",
    .summary = "every object every frame (the reference)",
    .make = [](const SettingValues&,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      return std::unique_ptr<Technique>(std::make_unique<BruteTechnique>());
    },
};

Result<void> BruteTechnique::load(const LoadContext& context) {
  scene_ = &context.scene;
  near_ = std::make_unique<ObjectSet>(context.scene);
  near_->insert_all();
  everything_.clear();
  near_->emit(everything_);
  return {};
}

void BruteTechnique::select(const FrameInput& input, DrawList& out) {
  if (input.region.kind == Region::Kind::near) {
    near_->clear();
    near_->insert_meeting(input.region.box);
    near_->emit(out);
    return;
  }
  if (input.region.kind == Region::Kind::far_field) return;  // brute has no far field
  out.opaque.insert(out.opaque.end(), everything_.opaque.begin(), everything_.opaque.end());
  out.transparent.insert(out.transparent.end(), everything_.transparent.begin(),
                         everything_.transparent.end());
}

}  // namespace farfield
