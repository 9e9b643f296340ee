#include "farfield/scene/scene_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string_view>

#include <xxhash.h>

#include "farfield/core/atomic_file.hpp"
#include "farfield/core/file_reading.hpp"

namespace farfield {

static_assert(std::endian::native == std::endian::little, "the .ffscene layout is little-endian");

namespace {

constexpr char kMagic[8] = {'F', 'F', 'S', 'C', 'E', 'N', 'E', '\0'};
constexpr uint64_t kAlignment = 64;
enum Section { kObjects, kMaterials, kVertices, kIndices, kNames, kSectionCount };
constexpr const char* kSectionNames[kSectionCount] = {"objects", "materials", "vertices", "indices",
                                                      "names"};
constexpr uint64_t kElementSize[kSectionCount] = {sizeof(Object), sizeof(Material), sizeof(Vertex),
                                                  sizeof(uint32_t), 1};

struct SectionEntry {
  uint64_t offset;
  uint64_t count;  // elements
  uint64_t checksum;
};

struct Header {
  char magic[8];
  uint32_t version;
  uint32_t header_size;
  float bounds_min[3];
  float bounds_max[3];
  SectionEntry sections[kSectionCount];
  uint64_t file_size;
  uint64_t header_checksum;  // XXH3-64 of every byte above
};
static_assert(sizeof(Header) == 176);

uint64_t align_up(uint64_t v) {
  return (v + kAlignment - 1) / kAlignment * kAlignment;
}

std::span<const std::byte> section_bytes(const Scene& s, int section) {
  switch (section) {
    case kObjects:
      return std::as_bytes(std::span(s.objects));
    case kMaterials:
      return std::as_bytes(std::span(s.materials));
    case kVertices:
      return std::as_bytes(std::span(s.vertices));
    case kIndices:
      return std::as_bytes(std::span(s.indices));
    default:
      return std::as_bytes(std::span(s.names.data(), s.names.size()));
  }
}

uint64_t header_checksum(const Header& h) {
  return XXH3_64bits(&h, offsetof(Header, header_checksum));
}

// What a file that is not a .ffscene seems to be, from its first bytes, for the refusal.
std::string seems_to_be(const Header& h, uint64_t file_size) {
  const auto starts = [&](std::string_view prefix) {
    return file_size >= prefix.size() && std::memcmp(&h, prefix.data(), prefix.size()) == 0;
  };
  const char first = file_size > 0 ? reinterpret_cast<const char*>(&h)[0] : 0;
  if (starts("SQLite format 3")) return "it is an SQLite file: a .ffpack store?";
  if (starts("glTF")) return "it is a glTF binary: import it first (farfield import)";
  if (first == '{' || first == '[') return "it is JSON: a camera path, or a glTF to import?";
  return "it does not start with the .ffscene magic";
}

// Checks the header alone: magic, version, checksum, section layout against the file size.
Result<void> check_header(const Header& h, uint64_t file_size, const std::string& name) {
  if (file_size < sizeof(Header)) {
    if (file_size >= sizeof(kMagic) && std::memcmp(h.magic, kMagic, sizeof(kMagic)) == 0)
      return make_error(name, ": truncated .ffscene file (", std::to_string(file_size),
                        " bytes, shorter than its header)");
    return make_error(name, ": not a .ffscene file (", seems_to_be(h, file_size), ")");
  }
  if (std::memcmp(h.magic, kMagic, sizeof(kMagic)) != 0)
    return make_error(name, ": not a .ffscene file (", seems_to_be(h, file_size), ")");
  if (h.version != kSceneFileVersion)
    return make_error(name, ": unsupported .ffscene version ", std::to_string(h.version),
                      " (this build reads version ", std::to_string(kSceneFileVersion), ")");
  if (h.header_size != sizeof(Header) || header_checksum(h) != h.header_checksum)
    return make_error(name, ": corrupted .ffscene header (checksum mismatch)");
  if (h.file_size != file_size) {
    if (file_size < h.file_size)
      return make_error(name, ": truncated .ffscene file (", std::to_string(file_size), " of ",
                        std::to_string(h.file_size), " bytes)");
    return make_error(name, ": .ffscene file has ", std::to_string(file_size - h.file_size),
                      " unexpected trailing bytes");
  }
  uint64_t end = sizeof(Header);
  for (int s = 0; s < kSectionCount; ++s) {
    const SectionEntry& e = h.sections[s];
    if (e.count > (uint64_t(1) << 40) / kElementSize[s] || e.offset < end || e.offset > file_size ||
        e.count * kElementSize[s] > file_size - e.offset)
      return make_error(name, ": corrupted .ffscene file (", kSectionNames[s],
                        " section out of bounds)");
    end = e.offset + e.count * kElementSize[s];
  }
  if (h.sections[kIndices].count > UINT32_MAX || h.sections[kVertices].count > UINT32_MAX ||
      h.sections[kNames].count > UINT32_MAX)
    return make_error(name, ": corrupted .ffscene file (counts beyond 32-bit ranges)");
  return {};
}

template <class T>
void copy_section(std::vector<T>& out, const std::byte* base, const SectionEntry& e) {
  out.resize(e.count);
  if (e.count) std::memcpy(out.data(), base + e.offset, e.count * sizeof(T));
}

// Checksums and scene invariants of a fully loaded scene.
Result<Scene> finish(Scene scene, const Header& h, const std::string& name, bool verify) {
  if (verify) {
    for (int s = 0; s < kSectionCount; ++s) {
      const auto bytes = section_bytes(scene, s);
      if (XXH3_64bits(bytes.data(), bytes.size()) != h.sections[s].checksum)
        return make_error(name, ": corrupted .ffscene file (", kSectionNames[s],
                          " section checksum mismatch)");
    }
  }
  if (std::string problem = validate_scene(scene); !problem.empty())
    return make_error(name, ": invalid .ffscene contents (", problem, ")");
  scene.bounds.min = {h.bounds_min[0], h.bounds_min[1], h.bounds_min[2]};
  scene.bounds.max = {h.bounds_max[0], h.bounds_max[1], h.bounds_max[2]};
  return scene;
}

}  // namespace

Result<void> write_scene(const Scene& scene, const std::string& path) {
  if (std::string problem = validate_scene(scene); !problem.empty())
    return make_error(path, ": refusing to write an invalid scene (", problem, ")");

  Header h{};
  std::memcpy(h.magic, kMagic, sizeof(kMagic));
  h.version = kSceneFileVersion;
  h.header_size = sizeof(Header);
  for (int a = 0; a < 3; ++a) {
    h.bounds_min[a] = scene.bounds.min[a];
    h.bounds_max[a] = scene.bounds.max[a];
  }
  uint64_t offset = align_up(sizeof(Header));
  for (int s = 0; s < kSectionCount; ++s) {
    const auto bytes = section_bytes(scene, s);
    h.sections[s] = {offset, bytes.size() / kElementSize[s],
                     XXH3_64bits(bytes.data(), bytes.size())};
    offset = align_up(offset + bytes.size());
  }
  h.file_size = offset;
  h.header_checksum = header_checksum(h);

  return write_file_atomically(path, [&](int fd) {
    static constexpr std::array<char, kAlignment> kZeros{};
    uint64_t written = sizeof(h);
    auto pad_to = [&](uint64_t position) {
      const uint64_t n = position - written;
      written = position;
      return n == 0 || write_all(fd, kZeros.data(), n);
    };
    if (!write_all(fd, &h, sizeof(h))) return false;
    for (int s = 0; s < kSectionCount; ++s) {
      const auto bytes = section_bytes(scene, s);
      if (!pad_to(h.sections[s].offset) || !write_all(fd, bytes.data(), bytes.size())) return false;
      written += bytes.size();
    }
    return pad_to(h.file_size);
  });
}

Result<Scene> read_scene(const std::string& path, SceneFileInfo* info) {
  auto file = ReadableFile::open(path);
  if (!file) return file.error();
  const uint64_t file_size = file->size();
  if (file_size == 0) return make_error(path, ": file is empty");

  Header h{};
  const size_t head = static_cast<size_t>(std::min<uint64_t>(file_size, sizeof(Header)));
  if (auto ok = file->read_at(&h, head, 0); !ok) return ok.error();
  if (auto ok = check_header(h, file_size, path); !ok) return ok.error();
  ::posix_fadvise(file->fd(), 0, 0, POSIX_FADV_SEQUENTIAL);

  // Read each section straight into its array, of any size.
  Scene scene;
  scene.objects.resize(h.sections[kObjects].count);
  scene.materials.resize(h.sections[kMaterials].count);
  scene.vertices.resize(h.sections[kVertices].count);
  scene.indices.resize(h.sections[kIndices].count);
  scene.names.resize(h.sections[kNames].count);
  void* targets[kSectionCount] = {scene.objects.data(), scene.materials.data(),
                                  scene.vertices.data(), scene.indices.data(), scene.names.data()};
  for (int s = 0; s < kSectionCount; ++s) {
    const SectionEntry& e = h.sections[s];
    if (auto ok = file->read_at(targets[s], e.count * kElementSize[s], e.offset); !ok)
      return ok.error();
  }
  if (info) *info = {h.version, file_size};
  return finish(std::move(scene), h, path, true);
}

Result<Scene> parse_scene(std::span<const std::byte> bytes, const std::string& name,
                          bool verify_checksums, SceneFileInfo* info) {
  if (bytes.empty()) return make_error(name, ": file is empty");
  Header h{};
  std::memcpy(&h, bytes.data(), std::min(bytes.size(), sizeof(Header)));
  if (auto ok = check_header(h, bytes.size(), name); !ok) return ok.error();
  Scene scene;
  copy_section(scene.objects, bytes.data(), h.sections[kObjects]);
  copy_section(scene.materials, bytes.data(), h.sections[kMaterials]);
  copy_section(scene.vertices, bytes.data(), h.sections[kVertices]);
  copy_section(scene.indices, bytes.data(), h.sections[kIndices]);
  const SectionEntry& names = h.sections[kNames];
  scene.names.assign(reinterpret_cast<const char*>(bytes.data()) + names.offset, names.count);
  if (info) *info = {h.version, bytes.size()};
  return finish(std::move(scene), h, name, verify_checksums);
}

bool is_scene_file(const std::string& path) {
  auto file = ReadableFile::open(path);
  char magic[sizeof(kMagic)] = {};
  return file && file->size() >= sizeof(magic) && file->read_at(magic, sizeof(magic), 0) &&
         std::memcmp(magic, kMagic, sizeof(kMagic)) == 0;
}

}  // namespace farfield
