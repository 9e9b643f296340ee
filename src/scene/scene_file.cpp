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
#include "farfield/scene/instances.hpp"
#include "farfield/scene/scene_file_writer.hpp"
#include "scene_file_layout.hpp"

namespace farfield {

static_assert(std::endian::native == std::endian::little, "the .ffscene layout is little-endian");

using namespace scene_file;

namespace {

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

template <class T>
Result<void> read_geometry_array(std::vector<T>& out, const SectionEntryV2* e, Tag tag,
                                 const std::string& name, bool verify, const ReadAt& read) {
  if (!e) return {};
  out.resize(e->bytes / sizeof(T));
  if (e->bytes == 0) return {};
  if (auto ok = read(out.data(), e->bytes, e->offset); !ok) return ok;
  if (verify && XXH3_64bits(out.data(), e->bytes) != e->checksum)
    return corrupted(name, std::string(kTagNames[tag]) + " section checksum mismatch");
  return {};
}

// ---- Versions 2 and 3: a header, a table of tagged sections, the sections
// (scene_file_layout.hpp) -----------------------------------------------------------------------

Result<Scene> read_v2(const char* head, uint64_t file_size, const std::string& name, bool verify,
                      const ReadAt& read, uint64_t* chunks) {
  auto table = read_section_table(head, file_size, name, read);
  if (!table) return table.error();
  Scene scene;
  if (auto ok = read_index_sections(*table, scene, name, verify, read); !ok) return ok.error();
  const auto& found = table->found;
  if (auto ok = read_geometry_array(scene.vertices, found[kVertices], kVertices, name, verify, read);
      !ok)
    return ok.error();
  if (auto ok = read_geometry_array(scene.indices, found[kIndices], kIndices, name, verify, read);
      !ok)
    return ok.error();
  if (auto ok = read_geometry_array(scene.uvs, found[kUvs], kUvs, name, verify, read); !ok)
    return ok.error();
  // The chunk table is checked here too, so that a file whose chunks lie is refused whole
  // (read_any checks the rest of the scene).
  auto chunk_table = read_chunk_table(*table, scene, name, verify, read);
  if (!chunk_table) return chunk_table.error();
  *chunks = chunk_table->size();
  // Instances are stored with their prototypes' ranges: checked in that form, then given
  // their own geometry (read_any checks the scene that results).
  if (!scene.instances.empty()) {
    std::string problem =
        validate_scene_index(scene, scene.vertices.size(), scene.indices.size(), scene.uvs.size());
    if (problem.empty()) problem = validate_instances(scene, InstanceForm::stored, false);
    if (problem.empty())
      problem = validate_geometry(scene, 0, uint32_t(scene.objects.size()),
                                  {.vertices = scene.vertices, .indices = scene.indices,
                                   .uvs = scene.uvs, .stored = true});
    if (!problem.empty()) return make_error(name, ": invalid .ffscene contents (", problem, ")");
    expand_instances(scene);
  }
  // The fingerprint stands for the scene where its geometry is not read (chunked_scene.hpp):
  // it must be the scene's.
  if (const SectionEntryV2* e = found[kFingerprint]; e && verify) {
    uint64_t stored = 0;
    if (auto ok = read(&stored, sizeof stored, e->offset); !ok) return ok.error();
    if (XXH3_64bits(&stored, sizeof stored) != e->checksum)
      return corrupted(name, "fingerprint section checksum mismatch");
    if (stored != scene_fingerprint(scene))
      return corrupted(name, "the fingerprint is not the scene's");
  }
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
  uint64_t chunks = 0;
  if (version == 1) {
    scene = read_v1(file_size, name, verify, read);
  } else if (version == 2 || version == kSceneFileVersion) {
    if (file_size < sizeof(HeaderV2))
      return make_error(name, ": truncated .ffscene file (", std::to_string(file_size),
                        " bytes, shorter than its header)");
    scene = read_v2(head, file_size, name, verify, read, &chunks);
  } else {
    return make_error(name, ": unsupported .ffscene version ", std::to_string(version),
                      " (this build reads versions 1 to ", std::to_string(kSceneFileVersion), ")");
  }
  if (!scene) return scene;
  if (std::string problem = validate_scene(*scene); !problem.empty())
    return make_error(name, ": invalid .ffscene contents (", problem, ")");
  if (info) *info = {version, file_size, chunks};
  return scene;
}

}  // namespace

Result<void> write_scene(const Scene& scene, const std::string& path) {
  const StoredGeometry stored = stored_geometry(scene);
  auto writer = SceneFileWriter::create(path, {stored.vertices, stored.indices});
  if (!writer) return writer.error();
  if (auto ok = writer->append(scene); !ok) return ok;
  auto written = writer->finish(scene, scene_fingerprint(scene));
  if (!written) return written.error();
  return {};
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
