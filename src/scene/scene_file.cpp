#include "farfield/scene/scene_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xxhash.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string_view>

#include "farfield/core/atomic_file.hpp"
#include "farfield/core/file_reading.hpp"

namespace farfield {

static_assert(std::endian::native == std::endian::little, "the .ffscene layout is little-endian");

namespace {

constexpr char kMagic[8] = {'F', 'F', 'S', 'C', 'E', 'N', 'E', '\0'};
constexpr uint64_t kAlignment = 64;
// Sections are read into arrays of at most this many bytes (a bound before allocating).
constexpr uint64_t kMaxSectionBytes = uint64_t(1) << 40;

uint64_t align_up(uint64_t v) {
  return (v + kAlignment - 1) / kAlignment * kAlignment;
}

// Reads `size` bytes at `offset`: from a file, or from bytes held in memory.
using ReadAt = std::function<Result<void>(void* data, uint64_t size, uint64_t offset)>;

// What a file that is not a .ffscene seems to be, from its first bytes, for the refusal.
std::string seems_to_be(const char* head, uint64_t file_size) {
  const auto starts = [&](std::string_view prefix) {
    return file_size >= prefix.size() && std::memcmp(head, prefix.data(), prefix.size()) == 0;
  };
  const char first = file_size > 0 ? head[0] : 0;
  if (starts("SQLite format 3")) return "it is an SQLite file: a .ffpack store?";
  if (starts("glTF")) return "it is a glTF binary: import it first (farfield import)";
  if (first == '{' || first == '[') return "it is JSON: a camera path, or a glTF to import?";
  return "it does not start with the .ffscene magic";
}

Error truncated(const std::string& name, uint64_t have, uint64_t want) {
  return make_error(name, ": truncated .ffscene file (", std::to_string(have), " of ",
                    std::to_string(want), " bytes)");
}

Error corrupted(const std::string& name, const std::string& what) {
  return make_error(name, ": corrupted .ffscene file (", what, ")");
}

// ---- Versions 2 and 3: a header, a table of tagged sections, the sections (3 adds cells)
// ------------------------

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

constexpr uint32_t kRequired = 1;  // a reader that does not know the section must refuse

struct SectionEntryV2 {
  char tag[16];  // the section's name, zero-padded
  uint64_t offset;
  uint64_t bytes;
  uint64_t checksum;      // XXH3-64 of the section's bytes
  uint32_t element_size;  // bytes per element (1 for byte strings)
  uint32_t flags;         // kRequired
};
static_assert(sizeof(SectionEntryV2) == 48);
constexpr uint32_t kMaxSections = 64;

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
  kTagCount
};
constexpr const char* kTagNames[kTagCount] = {
    "objects",       "materials", "vertices", "indices",      "names",   "uvs",          "textures",
    "texture_names", "images",    "cells",    "cell_objects", "portals", "portal_points"};
constexpr uint32_t kTagElementSize[kTagCount] = {sizeof(Object),
                                                 sizeof(Material),
                                                 sizeof(Vertex),
                                                 sizeof(uint32_t),
                                                 1,
                                                 sizeof(glm::vec2),
                                                 sizeof(TextureEntry),
                                                 1,
                                                 1,
                                                 sizeof(Cell),
                                                 sizeof(uint32_t),
                                                 sizeof(Portal),
                                                 sizeof(glm::vec3)};

std::string tag_text(const SectionEntryV2& e) {
  return std::string(e.tag, strnlen(e.tag, sizeof e.tag));
}

uint64_t header_checksum(const HeaderV2& h, std::span<const SectionEntryV2> table) {
  XXH3_state_t* state = XXH3_createState();
  XXH3_64bits_reset(state);
  XXH3_64bits_update(state, &h, offsetof(HeaderV2, header_checksum));
  XXH3_64bits_update(state, table.data(), table.size_bytes());
  const uint64_t hash = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  return hash;
}

// The scene's sections as they are written (textures only when it has some).
struct SectionsToWrite {
  std::vector<std::pair<Tag, std::span<const std::byte>>> list;
  std::vector<TextureEntry> textures;
  std::string texture_names;
  std::vector<std::span<const std::byte>> images;  // the "images" section, in pieces
};

SectionsToWrite sections_of(const Scene& s) {
  SectionsToWrite out;
  out.list = {{kObjects, std::as_bytes(std::span(s.objects))},
              {kMaterials, std::as_bytes(std::span(s.materials))},
              {kVertices, std::as_bytes(std::span(s.vertices))},
              {kIndices, std::as_bytes(std::span(s.indices))},
              {kNames, std::as_bytes(std::span(s.names.data(), s.names.size()))}};
  if (!s.uvs.empty()) out.list.push_back({kUvs, std::as_bytes(std::span(s.uvs))});
  if (!s.cells.empty()) {
    out.list.push_back({kCells, std::as_bytes(std::span(s.cells))});
    out.list.push_back({kCellObjects, std::as_bytes(std::span(s.cell_objects))});
    out.list.push_back({kPortals, std::as_bytes(std::span(s.portals))});
    out.list.push_back({kPortalPoints, std::as_bytes(std::span(s.portal_points))});
  }
  if (s.textures.empty()) return out;
  uint64_t image_offset = 0;
  for (const Texture& t : s.textures) {
    TextureEntry e{};
    e.image_offset = image_offset;
    e.image_bytes = t.encoded.size();
    e.width = t.width;
    e.height = t.height;
    e.name_offset = uint32_t(out.texture_names.size());
    e.name_size = uint32_t(t.name.size());
    e.codec = uint8_t(t.codec);
    e.has_alpha = t.has_alpha ? 1 : 0;
    out.textures.push_back(e);
    out.texture_names += t.name;
    out.images.push_back(std::as_bytes(std::span(t.encoded)));
    image_offset += t.encoded.size();
  }
  out.list.push_back({kTextures, std::as_bytes(std::span(out.textures))});
  out.list.push_back({kTextureNames, std::as_bytes(std::span(out.texture_names.data(),
                                                             out.texture_names.size()))});
  out.list.push_back({kImages, {}});  // written from `images`
  return out;
}

uint64_t images_checksum(const std::vector<std::span<const std::byte>>& pieces, uint64_t* bytes) {
  XXH3_state_t* state = XXH3_createState();
  XXH3_64bits_reset(state);
  *bytes = 0;
  for (auto piece : pieces) {
    XXH3_64bits_update(state, piece.data(), piece.size());
    *bytes += piece.size();
  }
  const uint64_t hash = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  return hash;
}

template <class T>
Result<void> read_array(std::vector<T>& out, const SectionEntryV2& e, const ReadAt& read) {
  out.resize(e.bytes / sizeof(T));
  return e.bytes ? read(out.data(), e.bytes, e.offset) : Result<void>{};
}

Result<Scene> read_v2(const char* head, uint64_t file_size, const std::string& name, bool verify,
                      const ReadAt& read) {
  HeaderV2 h{};
  std::memcpy(&h, head, sizeof h);
  if (h.header_size != sizeof(HeaderV2) || h.section_count > kMaxSections)
    return make_error(name, ": corrupted .ffscene header");
  const uint64_t table_end = sizeof(HeaderV2) + uint64_t(h.section_count) * sizeof(SectionEntryV2);
  if (file_size < table_end) return truncated(name, file_size, table_end);
  std::vector<SectionEntryV2> table(h.section_count);
  if (auto ok = read(table.data(), table.size() * sizeof(SectionEntryV2), sizeof(HeaderV2)); !ok)
    return ok.error();
  if (header_checksum(h, table) != h.header_checksum)
    return make_error(name, ": corrupted .ffscene header (checksum mismatch)");
  if (h.file_size != file_size) {
    if (file_size < h.file_size) return truncated(name, file_size, h.file_size);
    return make_error(name, ": .ffscene file has ", std::to_string(file_size - h.file_size),
                      " unexpected trailing bytes");
  }

  // Find the known sections; check every one's place in the file.
  std::array<const SectionEntryV2*, kTagCount> found{};
  for (const SectionEntryV2& e : table) {
    const std::string tag = tag_text(e);
    if (e.offset < table_end || e.offset > file_size || e.bytes > file_size - e.offset ||
        e.bytes > kMaxSectionBytes)
      return corrupted(name, tag + " section out of bounds");
    const auto* known = std::find(std::begin(kTagNames), std::end(kTagNames), tag);
    if (known == std::end(kTagNames)) {
      if (e.flags & kRequired)
        return make_error(name, ": needs a newer farfield (it holds a '", tag,
                          "' section this build does not know)");
      continue;
    }
    const int t = int(known - std::begin(kTagNames));
    if (found[t]) return corrupted(name, "two " + tag + " sections");
    if (e.element_size != kTagElementSize[t] || e.bytes % kTagElementSize[t] != 0)
      return corrupted(name, tag + " section of the wrong element size");
    found[t] = &e;
  }
  for (int t : {kObjects, kMaterials, kVertices, kIndices, kNames})
    if (!found[t]) return corrupted(name, std::string("no ") + kTagNames[t] + " section");
  if (found[kVertices]->bytes / sizeof(Vertex) > UINT32_MAX ||
      found[kIndices]->bytes / sizeof(uint32_t) > UINT32_MAX || found[kNames]->bytes > UINT32_MAX ||
      (found[kUvs] && found[kUvs]->bytes / 8 > UINT32_MAX))
    return corrupted(name, "counts beyond 32-bit ranges");
  const bool any_texture = found[kTextures] || found[kTextureNames] || found[kImages];
  if (any_texture && !(found[kTextures] && found[kTextureNames] && found[kImages]))
    return corrupted(name, "texture sections incomplete");
  const bool any_cell =
      found[kCells] || found[kCellObjects] || found[kPortals] || found[kPortalPoints];
  if (any_cell &&
      !(found[kCells] && found[kCellObjects] && found[kPortals] && found[kPortalPoints]))
    return corrupted(name, "cell and portal sections incomplete");

  Scene scene;
  std::string texture_names;
  std::vector<TextureEntry> textures;
  std::vector<std::byte> images;
  auto verify_section = [&](int t, const void* data) -> Result<void> {
    if (verify && XXH3_64bits(data, found[t]->bytes) != found[t]->checksum)
      return corrupted(name, std::string(kTagNames[t]) + " section checksum mismatch");
    return {};
  };
  Result<void> ok = read_array(scene.objects, *found[kObjects], read);
  if (ok) ok = verify_section(kObjects, scene.objects.data());
  if (ok) ok = read_array(scene.materials, *found[kMaterials], read);
  if (ok) ok = verify_section(kMaterials, scene.materials.data());
  if (ok) ok = read_array(scene.vertices, *found[kVertices], read);
  if (ok) ok = verify_section(kVertices, scene.vertices.data());
  if (ok) ok = read_array(scene.indices, *found[kIndices], read);
  if (ok) ok = verify_section(kIndices, scene.indices.data());
  if (ok) {
    scene.names.resize(found[kNames]->bytes);
    if (found[kNames]->bytes)
      ok = read(scene.names.data(), found[kNames]->bytes, found[kNames]->offset);
  }
  if (ok) ok = verify_section(kNames, scene.names.data());
  if (ok && found[kUvs]) ok = read_array(scene.uvs, *found[kUvs], read);
  if (ok && found[kUvs]) ok = verify_section(kUvs, scene.uvs.data());
  if (ok && any_cell) {
    ok = read_array(scene.cells, *found[kCells], read);
    if (ok) ok = verify_section(kCells, scene.cells.data());
    if (ok) ok = read_array(scene.cell_objects, *found[kCellObjects], read);
    if (ok) ok = verify_section(kCellObjects, scene.cell_objects.data());
    if (ok) ok = read_array(scene.portals, *found[kPortals], read);
    if (ok) ok = verify_section(kPortals, scene.portals.data());
    if (ok) ok = read_array(scene.portal_points, *found[kPortalPoints], read);
    if (ok) ok = verify_section(kPortalPoints, scene.portal_points.data());
  }
  if (ok && any_texture) {
    ok = read_array(textures, *found[kTextures], read);
    if (ok) ok = verify_section(kTextures, textures.data());
    if (ok) {
      texture_names.resize(found[kTextureNames]->bytes);
      if (!texture_names.empty())
        ok = read(texture_names.data(), texture_names.size(), found[kTextureNames]->offset);
    }
    if (ok) ok = verify_section(kTextureNames, texture_names.data());
    if (ok) ok = read_array(images, *found[kImages], read);
    if (ok) ok = verify_section(kImages, images.data());
  }
  if (!ok) return ok.error();

  for (size_t i = 0; i < textures.size(); ++i) {
    const TextureEntry& e = textures[i];
    if (e.image_offset > images.size() || e.image_bytes > images.size() - e.image_offset ||
        uint64_t(e.name_offset) + e.name_size > texture_names.size())
      return corrupted(name, "texture " + std::to_string(i) + " out of range");
    Texture t;
    t.name = texture_names.substr(e.name_offset, e.name_size);
    t.codec = TextureCodec(e.codec);
    t.width = e.width;
    t.height = e.height;
    t.has_alpha = e.has_alpha != 0;
    t.encoded.assign(images.begin() + ptrdiff_t(e.image_offset),
                     images.begin() + ptrdiff_t(e.image_offset + e.image_bytes));
    scene.textures.push_back(std::move(t));
  }
  scene.bounds.min = {h.bounds_min[0], h.bounds_min[1], h.bounds_min[2]};
  scene.bounds.max = {h.bounds_max[0], h.bounds_max[1], h.bounds_max[2]};
  return scene;
}

// ---- Version 1: five fixed sections (docs/ffscene.md, "Version 1") --------------------------

enum SectionV1 { kV1Objects, kV1Materials, kV1Vertices, kV1Indices, kV1Names, kV1Count };
constexpr uint64_t kV1ElementSize[kV1Count] = {sizeof(Object), 16, sizeof(Vertex), sizeof(uint32_t),
                                               1};

struct SectionEntryV1 {
  uint64_t offset;
  uint64_t count;  // elements
  uint64_t checksum;
};

struct HeaderV1 {
  char magic[8];
  uint32_t version;
  uint32_t header_size;
  float bounds_min[3];
  float bounds_max[3];
  SectionEntryV1 sections[kV1Count];
  uint64_t file_size;
  uint64_t header_checksum;  // XXH3-64 of every byte above
};
static_assert(sizeof(HeaderV1) == 176);

Result<Scene> read_v1(uint64_t file_size, const std::string& name, bool verify,
                      const ReadAt& read) {
  if (file_size < sizeof(HeaderV1))
    return make_error(name, ": truncated .ffscene file (", std::to_string(file_size),
                      " bytes, shorter than its header)");
  HeaderV1 h{};
  if (auto ok = read(&h, sizeof h, 0); !ok) return ok.error();
  if (h.header_size != sizeof(HeaderV1) ||
      XXH3_64bits(&h, offsetof(HeaderV1, header_checksum)) != h.header_checksum)
    return make_error(name, ": corrupted .ffscene header (checksum mismatch)");
  if (h.file_size != file_size) {
    if (file_size < h.file_size) return truncated(name, file_size, h.file_size);
    return make_error(name, ": .ffscene file has ", std::to_string(file_size - h.file_size),
                      " unexpected trailing bytes");
  }
  static constexpr const char* kNamesV1[kV1Count] = {"objects", "materials", "vertices", "indices",
                                                     "names"};
  uint64_t end = sizeof(HeaderV1);
  for (int s = 0; s < kV1Count; ++s) {
    const SectionEntryV1& e = h.sections[s];
    if (e.count > kMaxSectionBytes / kV1ElementSize[s] || e.offset < end || e.offset > file_size ||
        e.count * kV1ElementSize[s] > file_size - e.offset)
      return corrupted(name, std::string(kNamesV1[s]) + " section out of bounds");
    end = e.offset + e.count * kV1ElementSize[s];
  }
  if (h.sections[kV1Indices].count > UINT32_MAX || h.sections[kV1Vertices].count > UINT32_MAX ||
      h.sections[kV1Names].count > UINT32_MAX)
    return corrupted(name, "counts beyond 32-bit ranges");

  Scene scene;
  std::vector<glm::vec4> colors(h.sections[kV1Materials].count);
  scene.objects.resize(h.sections[kV1Objects].count);
  scene.vertices.resize(h.sections[kV1Vertices].count);
  scene.indices.resize(h.sections[kV1Indices].count);
  scene.names.resize(h.sections[kV1Names].count);
  void* targets[kV1Count] = {scene.objects.data(), colors.data(), scene.vertices.data(),
                             scene.indices.data(), scene.names.data()};
  for (int s = 0; s < kV1Count; ++s) {
    const SectionEntryV1& e = h.sections[s];
    const uint64_t bytes = e.count * kV1ElementSize[s];
    if (bytes == 0) continue;
    if (auto ok = read(targets[s], bytes, e.offset); !ok) return ok.error();
    if (verify && XXH3_64bits(targets[s], bytes) != e.checksum)
      return corrupted(name, std::string(kNamesV1[s]) + " section checksum mismatch");
  }
  // Version 1 materials are a base colour; its objects' last eight bytes were reserved zeros.
  for (const glm::vec4& c : colors) scene.materials.push_back(Material{.base_color = c});
  scene.bounds.min = {h.bounds_min[0], h.bounds_min[1], h.bounds_min[2]};
  scene.bounds.max = {h.bounds_max[0], h.bounds_max[1], h.bounds_max[2]};
  return scene;
}

// Either version, from its first bytes on.
Result<Scene> read_any(uint64_t file_size, const std::string& name, bool verify, const ReadAt& read,
                       SceneFileInfo* info) {
  if (file_size == 0) return make_error(name, ": file is empty");
  char head[sizeof(HeaderV2)] = {};
  const uint64_t head_size = std::min<uint64_t>(file_size, sizeof head);
  if (auto ok = read(head, head_size, 0); !ok) return ok.error();
  if (file_size < sizeof(kMagic) || std::memcmp(head, kMagic, sizeof(kMagic)) != 0)
    return make_error(name, ": not a .ffscene file (", seems_to_be(head, file_size), ")");
  if (file_size < 12)
    return make_error(name, ": truncated .ffscene file (", std::to_string(file_size),
                      " bytes, shorter than its header)");
  uint32_t version = 0;
  std::memcpy(&version, head + 8, sizeof version);
  Result<Scene> scene = make_error("");
  if (version == 1) {
    scene = read_v1(file_size, name, verify, read);
  } else if (version == 2 || version == kSceneFileVersion) {
    if (file_size < sizeof(HeaderV2))
      return make_error(name, ": truncated .ffscene file (", std::to_string(file_size),
                        " bytes, shorter than its header)");
    scene = read_v2(head, file_size, name, verify, read);
  } else {
    return make_error(name, ": unsupported .ffscene version ", std::to_string(version),
                      " (this build reads versions 1 to ", std::to_string(kSceneFileVersion), ")");
  }
  if (!scene) return scene;
  if (std::string problem = validate_scene(*scene); !problem.empty())
    return make_error(name, ": invalid .ffscene contents (", problem, ")");
  if (info) *info = {version, file_size};
  return scene;
}

}  // namespace

Result<void> write_scene(const Scene& scene, const std::string& path) {
  if (std::string problem = validate_scene(scene); !problem.empty())
    return make_error(path, ": refusing to write an invalid scene (", problem, ")");

  const SectionsToWrite sections = sections_of(scene);
  std::vector<SectionEntryV2> table(sections.list.size());
  HeaderV2 h{};
  std::memcpy(h.magic, kMagic, sizeof(kMagic));
  h.version = kSceneFileVersion;
  h.header_size = sizeof(HeaderV2);
  h.section_count = uint32_t(table.size());
  for (int a = 0; a < 3; ++a) {
    h.bounds_min[a] = scene.bounds.min[a];
    h.bounds_max[a] = scene.bounds.max[a];
  }
  uint64_t offset = align_up(sizeof(HeaderV2) + table.size() * sizeof(SectionEntryV2));
  for (size_t i = 0; i < table.size(); ++i) {
    const auto& [tag, bytes] = sections.list[i];
    SectionEntryV2& e = table[i];
    std::memcpy(e.tag, kTagNames[tag], std::strlen(kTagNames[tag]));  // the rest stays zero
    e.offset = offset;
    e.element_size = kTagElementSize[tag];
    e.flags = kRequired;
    if (tag == kImages) {
      e.checksum = images_checksum(sections.images, &e.bytes);
    } else {
      e.bytes = bytes.size();
      e.checksum = XXH3_64bits(bytes.data(), bytes.size());
    }
    offset = align_up(offset + e.bytes);
  }
  h.file_size = offset;
  h.header_checksum = header_checksum(h, table);

  return write_file_atomically(path, [&](int fd) {
    static constexpr std::array<char, kAlignment> kZeros{};
    uint64_t written = 0;
    auto put = [&](const void* data, uint64_t n) {
      written += n;
      return n == 0 || write_all(fd, data, n);
    };
    auto pad_to = [&](uint64_t position) {
      for (uint64_t n; written < position;)
        if (n = std::min<uint64_t>(position - written, kAlignment); !put(kZeros.data(), n))
          return false;
      return true;
    };
    if (!put(&h, sizeof h) || !put(table.data(), table.size() * sizeof(SectionEntryV2)))
      return false;
    for (size_t i = 0; i < table.size(); ++i) {
      if (!pad_to(table[i].offset)) return false;
      if (sections.list[i].first == kImages) {
        for (auto piece : sections.images)
          if (!put(piece.data(), piece.size())) return false;
      } else if (!put(sections.list[i].second.data(), sections.list[i].second.size())) {
        return false;
      }
    }
    return pad_to(h.file_size);
  });
}

Result<Scene> read_scene(const std::string& path, SceneFileInfo* info) {
  auto file = ReadableFile::open(path);
  if (!file) return file.error();
  ::posix_fadvise(file->fd(), 0, 0, POSIX_FADV_SEQUENTIAL);
  // Each section is read straight into its array, of any size.
  return read_any(
      file->size(), path, true,
      [&](void* data, uint64_t size, uint64_t offset) { return file->read_at(data, size, offset); },
      info);
}

Result<Scene> parse_scene(std::span<const std::byte> bytes, const std::string& name,
                          bool verify_checksums, SceneFileInfo* info) {
  return read_any(
      bytes.size(), name, verify_checksums,
      [&](void* data, uint64_t size, uint64_t offset) -> Result<void> {
        if (offset > bytes.size() || size > bytes.size() - offset)
          return make_error(name, ": truncated .ffscene file");
        if (size > 0) std::memcpy(data, bytes.data() + offset, size);
        return {};
      },
      info);
}

bool is_scene_file(const std::string& path) {
  auto file = ReadableFile::open(path);
  char magic[sizeof(kMagic)] = {};
  return file && file->size() >= sizeof(magic) && file->read_at(magic, sizeof(magic), 0) &&
         std::memcmp(magic, kMagic, sizeof(kMagic)) == 0;
}

}  // namespace farfield
