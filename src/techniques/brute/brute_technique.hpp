// brute: every object, every frame, in scene order. The reference for speed and pixels.
#pragma once

#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

extern const TechniqueDescriptor brute_descriptor;

class BruteTechnique final : public Technique {
 public:
  std::string_view name() const override { return "brute"; }
  Result<void> load(const LoadContext& context) override;
  void select(const FrameInput& input, DrawList& out) override;

 private:
  const Scene* scene_ = nullptr;
  DrawList everything_;
  std::unique_ptr<ObjectSet> near_;  // Region::near
};

}  // namespace farfield
