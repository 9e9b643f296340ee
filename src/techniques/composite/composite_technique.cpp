#include "composite_technique.hpp"

namespace farfield {

namespace {

constexpr SettingSpec kSettings[] = {
    {.key = "near",
     .type = SettingType::choice,
     .default_value = "octree",
     .help = "the technique of the near field (its own settings apply)",
     .choices = "octree|octree-paper|brute"},
    {.key = "far",
     .type = SettingType::choice,
     .default_value = "stratified",
     .help = "the technique of the far field (its own settings and bake apply)",
     .choices = "stratified"},
    {.key = "near_share",
     .type = SettingType::number,
     .default_value = "0.5",
     .help = "the part of the frame budget given to the near field",
     .min = 0,
     .max = 1,
     .min_open = true,
     .max_open = true},
};

}  // namespace

const TechniqueDescriptor composite_descriptor{
    .name = "composite",
    .summary = "the near field from one technique, the far field from another",
    .settings = kSettings,
    .make = [](const SettingValues& v,
               const TechniqueSettings& all) -> Result<std::unique_ptr<Technique>> {
      auto near = make_technique(v.text("near"), all);
      if (!near) return near.error();
      auto far = make_technique(v.text("far"), all);
      if (!far) return far.error();
      return std::unique_ptr<Technique>(std::make_unique<CompositeTechnique>(
          std::move(*near), std::move(*far), v.number("near_share")));
    },
    .parts =
        [](const SettingValues& v) {
          return std::vector<std::string>{v.text("near"), v.text("far")};
        },
};

Result<void> CompositeTechnique::load(const LoadContext& context) {
  if (auto ok = far_->load(context); !ok) return make_error("composite: ", ok.error().message);
  if (auto ok = near_->load(context); !ok) return make_error("composite: ", ok.error().message);
  frames_ = fallback_frames_ = 0;
  return {};
}

void CompositeTechnique::select(const FrameInput& input, DrawList& out) {
  ++frames_;
  FrameInput far = input, near = input;
  far.budget.target_ms = input.budget.target_ms * (1.0 - near_share_);
  near.budget.target_ms = input.budget.target_ms * near_share_;
  far.region = Region::far_field();
  far_->select(far, out);
  const std::optional<Bounds3> box = far_->far_field_box();
  if (box) {
    near.region = Region::near_box(*box);
  } else {
    ++fallback_frames_;  // no far field here: the near technique draws everything
    near.region = Region::everything();
  }
  near_->select(near, out);
}

void CompositeTechnique::frame_done(uint64_t frame) {
  far_->frame_done(frame);
  near_->frame_done(frame);
}

std::string CompositeTechnique::describe() const {
  return std::string(near_->name()) + " near (" + near_->describe() + "), " +
         std::string(far_->name()) + " far (" + far_->describe() + ")";
}

std::vector<std::pair<std::string, double>> CompositeTechnique::figures() const {
  std::vector<std::pair<std::string, double>> f;
  for (const Technique* part : {near_.get(), far_.get()})
    for (auto& [key, value] : part->figures())
      f.emplace_back(std::string(part->name()) + "." + key, value);
  return f;
}

void CompositeTechnique::annotate(const View& eye, DrawList& list) const {
  far_->annotate(eye, list);
  near_->annotate(eye, list);
}

std::string CompositeTechnique::failure() const {
  if (std::string f = far_->failure(); !f.empty()) return f;
  return near_->failure();
}

}  // namespace farfield
