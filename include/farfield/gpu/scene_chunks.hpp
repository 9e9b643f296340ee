// The scene split into chunks for the GPU: runs of whole objects (in index order) whose
// vertices and indices each fit in `max_bytes`, so that no buffer nears 2^31 bytes, past which
// drivers address vertices with 32-bit offsets (Mesa's llvmpipe crashes on a 3.6 GB vertex
// buffer: the 100M-triangle city). A chunk's index buffer keeps the scene's indices as they
// are; its vertex buffer starts at `first_vertex`, and draws add -first_vertex (base vertex).
#pragma once

#include <cstdint>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield::gpu {

inline constexpr uint64_t kSceneChunkBytes = uint64_t(1) << 30;

struct SceneChunk {
  uint32_t first_index = 0, index_count = 0;    // of Scene::indices
  uint32_t first_vertex = 0, vertex_count = 0;  // of Scene::vertices
};

// Chunks in index order, covering every object; refused when one object alone is larger.
Result<std::vector<SceneChunk>> plan_scene_chunks(const Scene& scene, uint64_t max_bytes);

// The chunk holding scene index `first_index` (chunks from plan_scene_chunks).
size_t chunk_of(const std::vector<SceneChunk>& chunks, uint32_t first_index);
// The chunk holding scene vertex `vertex`.
size_t chunk_of_vertex(const std::vector<SceneChunk>& chunks, uint32_t vertex);

}  // namespace farfield::gpu
