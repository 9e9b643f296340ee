// The .ffscene layout of versions 2 and 3 (docs/ffscene.md), shared by the whole-file reader
// (scene_file.cpp), the writer (scene_file_writer.cpp) and the reader that leaves geometry on
// disk (chunked_scene.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/scene/scene_file.hpp"

namespace farfield::scene_file {

inline constexpr char kMagic[8] = {'F', 'F', 'S', 'C', 'E', 'N', 'E', '\0'};
inline constexpr uint64_t kAlignment = 64;
// Sections are read into arrays of at most this many bytes (a bound before allocating).
inline constexpr uint64_t kMaxSectionBytes = uint64_t(1) << 40;

constexpr uint64_t align_up(uint64_t v) {
  return (v + kAlignment - 1) / kAlignment * kAlignment;
}

struct HeaderV2 {
  char magic[8];
  uint32_t version;
  uint32_t header_size;  // 64
  float bounds_min[3];
  float bounds_max[3];
  uint32_t section_count;
  uint32_t reserved;
  uint64_t file_size;
  uint64_t header_checksum;  // XXH3-64 of the bytes above and of the section table
};
static_assert(sizeof(HeaderV2) == 64);

inline constexpr uint32_t kRequired = 1;  // a reader that does not know the section must refuse

struct SectionEntryV2 {
  char tag[16];  // the section's name, zero-padded
  uint64_t offset;
  uint64_t bytes;
  uint64_t checksum;      // XXH3-64 of the section's bytes
  uint32_t element_size;  // bytes per element (1 for byte strings)
  uint32_t flags;         // kRequired
};
static_assert(sizeof(SectionEntryV2) == 48);
inline constexpr uint32_t kMaxSections = 64;
// The writer leaves room for the most sections it writes, so that it can write them before it
// knows how many there are; the first section starts here.
inline constexpr uint32_t kMostSectionsWritten = 17;
inline constexpr uint64_t kFirstSection =
    align_up(sizeof(HeaderV2) + kMostSectionsWritten * sizeof(SectionEntryV2));

// A texture's entry in the "textures" section; its image lies in "images", its name in
// "texture_names".
struct TextureEntry {
  uint64_t image_offset, image_bytes;
  uint32_t width, height;
  uint32_t name_offset, name_size;
  uint8_t codec, has_alpha, reserved[6];
};
static_assert(sizeof(TextureEntry) == 40);

// The sections this build writes and reads. A section a reader does not know is skipped,
// unless flagged required (then the file needs a newer farfield).
enum Tag {
  kObjects,
  kMaterials,
  kVertices,
  kIndices,
  kNames,
  kUvs,
  kTextures,
  kTextureNames,
  kImages,
  kCells,
  kCellObjects,
  kPortals,
  kPortalPoints,
  kChunks,
  kFingerprint,
  kInstances,
  kTagCount
};
inline constexpr const char* kTagNames[kTagCount] = {
    "objects", "materials",    "vertices", "indices",       "names",
    "uvs",     "textures",     "texture_names", "images",   "cells",
    "cell_objects", "portals", "portal_points", "chunks",   "fingerprint",
    "instances"};
inline constexpr uint32_t kTagElementSize[kTagCount] = {
    sizeof(Object), sizeof(Material), sizeof(Vertex),    sizeof(uint32_t),   1,
    sizeof(glm::vec2), sizeof(TextureEntry), 1,          1,                  sizeof(Cell),
    sizeof(uint32_t), sizeof(Portal), sizeof(glm::vec3), sizeof(SceneChunk), sizeof(uint64_t),
    sizeof(Instance)};
// Older readers skip these: they add to a file and change nothing it held.
constexpr bool optional_section(Tag tag) { return tag == kChunks || tag == kFingerprint; }

uint64_t header_checksum(const HeaderV2& h, std::span<const SectionEntryV2> table);

// Reads `size` bytes at `offset`: from a file, or from bytes held in memory.
using ReadAt = std::function<Result<void>(void* data, uint64_t size, uint64_t offset)>;

Error truncated(const std::string& name, uint64_t have, uint64_t want);
Error corrupted(const std::string& name, const std::string& what);

// A version 2 or 3 file's header and section table, checked: the header's checksum and the
// file's size, every section inside the file, a known one of its element size and at most
// once, the five that every scene has present, texture and cell sections all or none.
struct SectionTable {
  HeaderV2 header{};
  std::vector<SectionEntryV2> entries;
  std::array<const SectionEntryV2*, kTagCount> found{};
  uint64_t count(Tag tag) const {
    return found[tag] ? found[tag]->bytes / kTagElementSize[tag] : 0;
  }
};
Result<SectionTable> read_section_table(const char* head, uint64_t file_size,
                                        const std::string& name, const ReadAt& read);

// Reads every section but vertices, indices and uvs into `scene` (bounds from the header),
// each checked against its checksum when `verify`. The objects are in the stored form
// (instances.hpp): an instance's ranges are its prototype's.
Result<void> read_index_sections(const SectionTable& table, Scene& scene, const std::string& name,
                                 bool verify, const ReadAt& read);

// Reads the chunk table (empty where the file has none) and checks it against the stored
// objects: chunks follow each other without gaps over every object and every stored vertex,
// index and coordinate, and each object's ranges, but an instance's, lie in its chunk's.
Result<std::vector<SceneChunk>> read_chunk_table(const SectionTable& table, const Scene& index,
                                                 const std::string& name, bool verify,
                                                 const ReadAt& read);

}  // namespace farfield::scene_file
