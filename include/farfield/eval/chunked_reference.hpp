// Brute force's frame of a scene left on disk (a chunked .ffscene) whatever its size: the
// chunks that meet the view, drawn in parts of at most `budget_bytes` of GPU meshes each over
// one frame (DrawList::draw_over), the opaque objects of every chunk first, then the
// semi-transparent ones in scene order, as brute force draws them in memory: the same pixels
// (ChunkStreamGL.PartsMakeBruteForcesFrame). The reference of bench --cache-mb, where the
// chunks in view can outgrow the walk's cache (the 100M-triangle city's street: 2.4 GB of
// them). Reads every chunk in view for each frame, on the calling thread (the GL one).
#pragma once

#include <cstdint>

#include "farfield/core/image.hpp"
#include "farfield/core/result.hpp"
#include "farfield/core/view.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/chunked_scene.hpp"

namespace farfield {

// Draws the frame into the renderer's target (capture() reads it). Fails, naming the chunk,
// where one cannot be read.
Result<void> draw_chunked_reference(gpu::Renderer& renderer, const ChunkedScene& scene,
                                    const View& view, uint64_t budget_bytes);

}  // namespace farfield
