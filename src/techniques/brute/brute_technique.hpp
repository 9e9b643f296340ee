// brute: every object, every frame, in scene order. The reference for speed and pixels.
// With the scene left on disk (--cache-mb), every chunk that meets the view is drawn through
// the cache (chunk_stream.hpp), nearest first: a chunk not yet loaded leaves its objects out
// of the frame (counted in incomplete frames), unless brute.wait asks to wait for it.
#pragma once

#include "farfield/techniques/chunk_stream.hpp"
#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

extern const TechniqueDescriptor brute_descriptor;

class BruteTechnique final : public Technique {
 public:
  explicit BruteTechnique(bool wait = false) : wait_(wait) {}
  std::string_view name() const override { return "brute"; }
  Result<void> load(const LoadContext& context) override;
  void select(const FrameInput& input, DrawList& out) override;
  std::vector<std::pair<std::string, double>> figures() const override;
  std::string failure() const override;

 private:
  void select_streamed(const FrameInput& input, DrawList& out);

  const Scene* scene_ = nullptr;
  DrawList everything_;
  std::unique_ptr<ObjectSet> near_;  // Region::near
  // The scene left on disk.
  bool wait_ = false;
  std::unique_ptr<ChunkStream> stream_;
  uint64_t frames_ = 0, incomplete_frames_ = 0;
};

}  // namespace farfield
