// A scene whose geometry stays in its .ffscene file and is read a chunk at a time (SceneChunk:
// a run of objects whose vertices, indices and texture coordinates lie together), for scenes
// larger than memory: `info` describes one without reading its geometry, and a walk reads what
// it draws. Opening reads and checks everything else (objects, materials, names, textures,
// cells, the chunk table, the fingerprint): about 70 bytes an object.
//
// read_chunk may be called from several threads at once (pread on one descriptor).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "farfield/core/file_reading.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/scene/scene_file.hpp"

namespace farfield {

// One chunk's geometry, its indices counted from its first vertex.
struct ChunkGeometry {
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;
  std::vector<glm::vec2> uvs;
};

class ChunkedScene {
 public:
  // Fails, naming the file and the problem, as read_scene does; a file written before chunks
  // (they came with farfield's out-of-core walk) is refused with how to rewrite it.
  static Result<ChunkedScene> open(const std::string& path);

  // Everything but vertices, indices and texture coordinates (those arrays are empty). Objects
  // and chunks are as a scene read whole holds them: an instance (Scene::instances) has ranges
  // of its own, and a chunk of instances the geometry they expand to.
  const Scene& index() const { return index_; }
  std::span<const SceneChunk> chunks() const { return chunks_; }
  const SceneFileInfo& file() const { return file_; }
  const std::string& path() const { return path_; }
  uint64_t vertex_count() const { return vertex_count_; }
  uint64_t index_count() const { return index_count_; }
  uint64_t uv_count() const { return uv_count_; }
  uint64_t triangle_count() const { return index_count_ / 3; }
  // The scene's fingerprint (scene_fingerprint of the whole scene), as written.
  uint64_t fingerprint() const { return fingerprint_; }
  // The chunk that holds `object`.
  uint32_t chunk_of(uint32_t object) const;
  // The bounds of chunk `c`'s objects.
  const Bounds3& chunk_bounds(size_t c) const { return chunk_bounds_[c]; }

  // Reads chunk `c`, checks it against its checksum and the scene's invariants, and counts its
  // indices from its first vertex. Its instances are expanded from their prototypes, read from
  // their own chunks where they lie in another. An error names the file and the chunk (its
  // objects).
  Result<void> read_chunk(size_t c, ChunkGeometry& out) const;

 private:
  // Chunk `c` as stored: without its instances' geometry, its indices absolute in the stored
  // arrays.
  Result<void> read_stored(size_t c, ChunkGeometry& out) const;
  ChunkedScene(std::string path, ReadableFile file) : path_(std::move(path)), file_handle_(std::move(file)) {}
  std::string path_;
  ReadableFile file_handle_;
  SceneFileInfo file_;
  Scene index_;
  std::vector<SceneChunk> chunks_;
  // With instances: the objects and chunks as the file stores them (instances.hpp).
  Scene stored_;
  std::vector<SceneChunk> stored_chunks_;
  std::vector<Bounds3> chunk_bounds_;
  uint64_t vertex_count_ = 0, index_count_ = 0, uv_count_ = 0;
  uint64_t offset_[3] = {0, 0, 0};  // of the vertices, indices and uvs sections
  uint64_t fingerprint_ = 0;
};

// The median of the longest edges of triangles sampled from up to `chunks` chunks spread over
// the scene (each chunk's median, then the median of those): the scene's detail without
// reading all of it.
Result<float> sampled_triangle_edge(const ChunkedScene& scene, size_t chunks = 16);

}  // namespace farfield
