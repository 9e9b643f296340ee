// ibr: paper 003's multi-level image-based rendering of a model seen from outside. The bake
// renders the model from viewpoints on a sphere around it (core/view_sphere.hpp) at W x W,
// builds each viewpoint's pyramid and stores its coarsest level and the differences of the
// finer ones as JPEG (core/image_pyramid.hpp, Sec. 2.2: the paper's min rule, or by default
// the mean with signed differences), each difference taken from the coarser level as it will
// be decoded, so that JPEG's errors do not add up from level to level. A frame decodes the levels
// its speed asks for (Sec. 2.3: the faster the viewer, the coarser) and adds them up on the
// GPU: each level a quad at the model's centre, facing the viewpoint, that covers exactly what
// the viewpoint's camera saw (so that from the viewpoint it is the image itself), the
// coarsest drawn over what is there and the differences added. Between viewpoints the paper
// shows the nearest; by default the four around the eye are blended by their bilinear weights
// in longitude and latitude (ibr.blend).
#pragma once

#include <memory>
#include <vector>

#include "farfield/core/codec.hpp"
#include "farfield/core/image_pyramid.hpp"
#include "farfield/core/view_sphere.hpp"
#include "farfield/techniques/sphere_settings.hpp"
#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

extern const TechniqueDescriptor ibr_descriptor;

struct IbrOptions {
  SphereSettings sphere;
  float fov_deg = 0.0f;   // 0: the model's bounding sphere seen from the radius, 5% around
  int resolution = 512;   // W
  int levels = 3;
  int quality = 80;     // JPEG, of the coarsest level and of each level alone (Table 1)
  int difference_quality = 75;  // JPEG, of the differences (the highest, under max_storage)
  // > 0: a viewpoint's stored levels take at most this many times its level-0 image as JPEG
  // alone: its differences at the highest quality, from difference_quality down to
  // kLowestDifferenceQuality, that fits. 0: every difference at difference_quality.
  double max_storage = 1.18;
  PyramidRule rule = PyramidRule::mean;
  int level = -1;       // the finest level drawn; -1: by the viewer's speed
  bool blend = true;    // the four viewpoints around the eye blended; false: the nearest
  float fast_deg = 0;   // speed (degrees of the sphere a frame) from which the coarsest level
                        // is drawn; 0: one step of longitude
};

inline constexpr int kLowestDifferenceQuality = 40;

// What the pack's views take, by level (paper 003, Table 1): the stored coarsest image and
// differences, and each level's full image as it would be stored on its own.
struct IbrStorage {
  uint32_t views = 0;
  std::vector<uint64_t> stored;  // per level: D_i (i < levels - 1), I_{levels - 1}
  std::vector<uint64_t> full;    // per level: I_i as JPEG alone
};
Result<IbrStorage> ibr_storage(const Store& store);

class IbrTechnique final : public Technique {
 public:
  explicit IbrTechnique(const IbrOptions& options) : options_(options) {}
  std::string_view name() const override { return "ibr"; }
  Result<void> bake(const BakeContext& context) override;
  Result<void> load(const LoadContext& context) override;
  void select(const FrameInput& input, DrawList& out) override;
  uint64_t fallback_frames() const override { return fallback_frames_; }
  std::optional<CameraPose> start_pose() const override;
  std::string describe() const override;
  std::vector<std::pair<std::string, double>> figures() const override;
  std::string failure() const override { return failure_; }

 private:
  // A decoded level of a viewpoint on the GPU.
  struct Slot {
    uint32_t view = UINT32_MAX, level = 0;
    TextureHandle texture;
    uint64_t used = 0;  // frame
  };
  TextureHandle resident(uint32_t view, uint32_t level, uint64_t frame, DrawList& out);

  IbrOptions options_;
  const Scene* scene_ = nullptr;
  ViewSphere sphere_;
  float fov_deg_ = 0.0f;
  std::vector<std::vector<Bytes>> jpegs_;  // per view, per level
  IbrStorage storage_;
  gpu::OwnedResources resources_;
  std::vector<Slot> slots_;
  std::unique_ptr<ObjectSet> objects_;  // near regions and frames far off the sphere
  glm::vec3 last_eye_{0.0f};
  std::string failure_;
  // figures()
  uint64_t frames_ = 0, fallback_frames_ = 0, decodes_ = 0, levels_drawn_ = 0;
  double decode_ms_ = 0.0;
};

}  // namespace farfield
