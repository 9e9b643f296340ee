// hybrid: paper 003's hybrid renderer (Sec. 3). The bake finds, for each viewpoint on a sphere
// around the model (core/view_sphere.hpp, the same as ibr's), the triangles its frame shows
// (gpu::Renderer::visible_triangles, at the walk's resolution and field of view) and stores
// them as a compressed occupancy bit vector (core/occupancy_codec.hpp: the paper's run-length
// and Huffman coding, or zstd over the run lengths). A frame draws the visible triangles of the
// viewpoint nearest the eye as real geometry, lit and pickable like the scene; beyond the paper,
// by default the union of the four viewpoints around the eye, so that between viewpoints
// fewer visible triangles are missing.
#pragma once

#include <memory>
#include <vector>

#include "farfield/core/codec.hpp"
#include "farfield/core/view_sphere.hpp"
#include "farfield/techniques/sphere_settings.hpp"
#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

extern const TechniqueDescriptor hybrid_descriptor;

struct HybridOptions {
  SphereSettings sphere;
  int width = 1024, height = 768;
  float hfov_deg = 90.0f;
  int scale = 3;       // also found at this odd multiple of width x height (003, Sec. 3.2)
  bool zstd = false;   // the codec stored: zstd over the run lengths; else the paper's
  bool around = true;  // the union of the four viewpoints around the eye; else the nearest
};

// Paper 003, Table 3 over a pack's viewpoints: the mean share of visible triangles and the
// bytes at each stage, both codecs.
struct HybridStorage {
  uint32_t views = 0;
  uint64_t triangles = 0;  // of the scene
  double mean_visible_share = 0.0;
  uint64_t bit_vector = 0, run_length = 0, paper = 0, zstd = 0;  // summed over the views
  uint64_t stored = 0;                                           // the codec kept
};
Result<HybridStorage> hybrid_storage(const Store& store);

class HybridTechnique final : public Technique {
 public:
  explicit HybridTechnique(const HybridOptions& options) : options_(options) {}
  std::string_view name() const override { return "hybrid"; }
  Result<void> bake(const BakeContext& context) override;
  Result<void> load(const LoadContext& context) override;
  void select(const FrameInput& input, DrawList& out) override;
  uint64_t fallback_frames() const override { return fallback_frames_; }
  std::optional<CameraPose> start_pose() const override;
  std::string describe() const override;
  std::vector<std::pair<std::string, double>> figures() const override;
  std::string failure() const override { return failure_; }

 private:
  const std::vector<uint32_t>* decoded(uint32_t view);
  void build_ranges();

  HybridOptions options_;
  const Scene* scene_ = nullptr;
  ViewSphere sphere_;
  std::vector<Bytes> sets_;  // per view, compressed
  HybridStorage storage_;
  std::vector<uint32_t> object_end_;  // per object, the triangle after its last
  // The last viewpoints decoded, most recent last.
  struct Decoded {
    uint32_t view;
    std::vector<uint32_t> visible;
  };
  std::vector<Decoded> cache_;
  std::array<uint32_t, 4> views_{};  // the viewpoints of ranges_
  size_t view_count_ = 0;
  std::vector<uint32_t> merged_, scratch_;
  DrawList ranges_;  // the union's triangles as scene ranges
  std::unique_ptr<ObjectSet> objects_;
  std::string failure_;
  // figures()
  uint64_t frames_ = 0, fallback_frames_ = 0, decodes_ = 0, visible_drawn_ = 0, ranges_drawn_ = 0;
  double decode_ms_ = 0.0;
};

}  // namespace farfield
