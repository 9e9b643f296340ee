// The .ffscene file: a Scene on disk (docs/ffscene.md gives the layout).
//
// Little-endian. A header (magic, version, bounds, the file's size, a checksum over it and the
// section table), a table of tagged sections (name, offset, bytes, element size, XXH3-64
// checksum, whether a reader must know it), then the sections, each 64-byte aligned: objects,
// materials, vertices, indices, names, and for textured scenes uvs, textures, texture_names,
// images, and for scenes with rooms cells, cell_objects, portals, portal_points; then chunks (runs
// of objects to read on their own, SceneChunk) and the scene's fingerprint, optional sections
// that older readers skip. Later versions add sections; a reader skips those it does not know
// unless they are marked required. Version 1 files
// (five fixed sections) are still read. Written atomically: a temporary file in the destination's
// folder, flushed, then renamed over the destination. Reading checks size, checksums and every
// scene invariant, so a truncated, corrupted or hand-crafted file is refused with a message rather
// than trusted.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

// Written; 1 to 3 are read. Version 3 added cells and portals (sections cells, cell_objects,
// portals, portal_points, written only by scenes that have cells).
inline constexpr uint32_t kSceneFileVersion = 3;

// A run of consecutive objects whose vertices, indices and texture coordinates follow each
// other in the file, so that it is read with three reads and checked on its own: what a walk
// too large for memory reads on demand (chunked_scene.hpp). The writer closes a chunk before
// the object that would take it past kChunkTriangles (one larger object is a chunk alone);
// generators and importers emit objects near each other one after the other, so chunks are
// compact in space. Version 3 files written before chunks have none.
struct SceneChunk {
  uint32_t first_object = 0, object_count = 0;
  uint32_t first_vertex = 0, vertex_count = 0;
  uint32_t first_index = 0, index_count = 0;
  uint32_t first_uv = 0, uv_count = 0;
  uint64_t checksum = 0;  // XXH3-64 of the XXH3-64s of its vertex, index and uv bytes
  uint64_t triangle_count() const { return index_count / 3; }
  uint64_t byte_size() const {
    return uint64_t(vertex_count) * sizeof(Vertex) + uint64_t(index_count) * sizeof(uint32_t) +
           uint64_t(uv_count) * sizeof(glm::vec2);
  }
};
static_assert(sizeof(SceneChunk) == 40);
inline constexpr uint32_t kChunkTriangles = 1u << 16;

struct SceneFileInfo {
  uint32_t version = 0;
  uint64_t file_bytes = 0;
  uint64_t chunks = 0;  // 0: written before chunks
};

Result<void> write_scene(const Scene& scene, const std::string& path);

Result<Scene> read_scene(const std::string& path, SceneFileInfo* info = nullptr);

// Parses a whole file held in memory; `name` is used in messages. `verify_checksums` false
// skips only the checksum comparison (for fuzzing the structural checks behind it).
Result<Scene> parse_scene(std::span<const std::byte> bytes, const std::string& name,
                          bool verify_checksums = true, SceneFileInfo* info = nullptr);

// True when the file starts with the .ffscene magic.
bool is_scene_file(const std::string& path);

}  // namespace farfield
