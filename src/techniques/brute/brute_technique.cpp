#include "brute_technique.hpp"

#include <algorithm>

#include "farfield/core/frustum.hpp"

namespace farfield {

namespace {

constexpr SettingSpec kSettings[] = {
    {.key = "wait",
     .type = SettingType::flag,
     .default_value = "0",
     .help = "with the scene left on disk (--cache-mb): wait until every chunk the frame "
             "needs is loaded, so that the frame is complete (a reference; as long as the "
             "chunks in view fit the cache); 0: draw what is loaded, never wait"},
};

}  // namespace

const TechniqueDescriptor brute_descriptor{
    .name = "brute",
    .summary = "every object every frame (the reference)",
    .settings = kSettings,
    .streams = true,
    .make = [](const SettingValues& v,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      return std::unique_ptr<Technique>(std::make_unique<BruteTechnique>(v.flag("wait")));
    },
};

Result<void> BruteTechnique::load(const LoadContext& context) {
  scene_ = &context.scene;
  frames_ = incomplete_frames_ = 0;
  if (context.on_disk) {
    auto stream = ChunkStream::create(*context.on_disk, context.device, context.cache_bytes);
    if (!stream) return make_error("brute: ", stream.error().message);
    stream_ = std::move(*stream);
    return {};
  }
  near_ = std::make_unique<ObjectSet>(context.scene);
  near_->insert_all();
  everything_.clear();
  near_->emit(everything_);
  return {};
}

void BruteTechnique::select(const FrameInput& input, DrawList& out) {
  if (stream_) return select_streamed(input, out);
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

// Every chunk that meets the view (and the near box), in scene order so that the frame is
// brute force's; the nearest load first.
void BruteTechnique::select_streamed(const FrameInput& input, DrawList& out) {
  if (input.region.kind == Region::Kind::far_field) return;
  ++frames_;
  const Frustum frustum(input.view);
  const glm::vec3 eye = input.view.pose.position;
  const size_t first_opaque = out.opaque.size(), first_transparent = out.transparent.size();
  uint64_t fewest = UINT64_MAX;
  for (int stalled = 0;;) {
    const ChunkedScene& scene = stream_->scene();
    for (uint32_t c = 0; c < scene.chunks().size(); ++c) {
      const Bounds3& b = scene.chunk_bounds(c);
      if (input.region.kind == Region::Kind::near && !meet(b, input.region.box)) continue;
      if (frustum.classify(b) == Visibility::none) continue;
      stream_->draw_chunk(c, -distance_to(b, eye), out);
    }
    const uint64_t missed = stream_->end_frame(out);
    if (missed == 0) return;
    // Waiting: once the loads asked for are in, the frame is selected again (the uploads
    // already in the list stay: the last one of a mesh wins).
    // Given up when three rounds in a row load nothing more (the view needs more chunks
    // than the cache holds) or a chunk cannot be read.
    stalled = missed < fewest ? 0 : stalled + 1;
    fewest = std::min(fewest, missed);
    if (!wait_ || stalled >= 3 || !stream_->failure().empty()) {
      ++incomplete_frames_;
      return;
    }
    out.opaque.resize(first_opaque);
    out.transparent.resize(first_transparent);
    stream_->wait_for_loads();
  }
}

std::vector<std::pair<std::string, double>> BruteTechnique::figures() const {
  if (!stream_) return {};
  const gpu::MeshPoolCounters& c = stream_->counters();
  return {{"cache_hits", double(c.hits)},
          {"cache_misses", double(c.misses)},
          {"bytes_read", double(c.bytes_read)},
          {"cache_evictions", double(c.evictions)},
          {"cache_peak_mb", double(c.peak_resident_bytes) / 1e6},
          {"incomplete_frames", double(incomplete_frames_)}};
}

std::string BruteTechnique::failure() const {
  return stream_ ? stream_->failure() : std::string();
}

}  // namespace farfield
