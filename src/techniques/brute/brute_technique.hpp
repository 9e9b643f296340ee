// brute: every object, every frame, in scene order. The reference for speed and pixels.
#pragma once

#include "farfield/techniques/technique.hpp"

namespace farfield {

class BruteTechnique final : public Technique {
 public:
  std::string_view name() const override { return "brute"; }
  Result<void> load(const Scene& scene) override;
  void select(const View& view, const FrameBudget& budget, DrawList& out) override;

 private:
  DrawList everything_;
};

}  // namespace farfield
