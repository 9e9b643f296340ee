// A scene left on disk (ChunkedScene) drawn through a bounded pool of GPU meshes
// (gpu/mesh_pool.hpp): the techniques that walk a scene larger than memory (bench and view
// --cache-mb) draw its objects from here instead of from the scene's own buffers. A chunk is
// read, its texture coordinates spread one per vertex, and uploaded on its first want; an
// object is drawn from its chunk's mesh once that is resident, in scene order, neighbours of
// one material one range, so that with every chunk resident the frame is brute force's.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "farfield/gpu/device.hpp"
#include "farfield/gpu/draw_list.hpp"
#include "farfield/gpu/mesh_pool.hpp"
#include "farfield/scene/chunked_scene.hpp"

namespace farfield {

class ChunkStream {
 public:
  // `budget_bytes` bounds the chunks resident on the GPU together.
  static Result<std::unique_ptr<ChunkStream>> create(const ChunkedScene& scene,
                                                     gpu::Device& device, uint64_t budget_bytes);

  const ChunkedScene& scene() const { return scene_; }

  // Wants chunk `chunk` (higher priority loads first); when it is resident, appends all its
  // objects to `out` and returns true.
  bool draw_chunk(uint32_t chunk, float priority, DrawList& out);
  // The same for one object.
  bool draw_object(uint32_t object, float priority, DrawList& out);
  // After the frame's wants (MeshPool::end_frame); returns the wants missed.
  uint64_t end_frame(DrawList& out) { return pool_->end_frame(out); }
  void wait_for_loads() { pool_->wait_for_loads(); }
  const gpu::MeshPoolCounters& counters() const { return pool_->counters(); }
  std::string failure() const { return pool_->failure(); }

 private:
  explicit ChunkStream(const ChunkedScene& scene) : scene_(scene) {}

  const ChunkedScene& scene_;
  std::unique_ptr<gpu::MeshPool> pool_;
};

// Appends the draw ranges of objects [first_object, end_object) of chunk `chunk`, drawn from
// `mesh` (the chunk's geometry, read_chunk_mesh), in scene order, neighbours of one material one
// range: the opaque ones to `opaque` and the semi-transparent ones to `transparent`, either
// left out where null.
void add_chunk_ranges(const ChunkedScene& scene, uint32_t chunk, uint32_t first_object,
                      uint32_t end_object, MeshHandle mesh, std::vector<DrawRange>* opaque,
                      std::vector<DrawRange>* transparent);

// The chunk's geometry as a scene mesh: indices from its first vertex, texture coordinates one
// per vertex (zeros for untextured objects) where it has any.
Result<std::shared_ptr<const SceneMeshData>> read_chunk_mesh(const ChunkedScene& scene,
                                                             uint32_t chunk);

}  // namespace farfield
