#include "farfield/scene/scene_file_writer.hpp"

#include <sys/statvfs.h>
#include <unistd.h>
#include <xxhash.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "farfield/core/assert.hpp"
#include "farfield/core/atomic_file.hpp"
#include "farfield/core/text.hpp"
#include "farfield/scene/instances.hpp"
#include "scene_file_layout.hpp"

namespace farfield {

using namespace scene_file;

namespace {

// The three arrays a chunk holds, in the order of its checksum.
enum Stream { kVertexStream, kIndexStream, kUvStream, kStreamCount };
constexpr uint64_t kElementBytes[kStreamCount] = {sizeof(Vertex), sizeof(uint32_t),
                                                  sizeof(glm::vec2)};

struct Hasher {
  XXH3_state_t* state = XXH3_createState();
  Hasher() { XXH3_64bits_reset(state); }
  Hasher(const Hasher&) = delete;
  ~Hasher() { XXH3_freeState(state); }
  void update(const void* data, size_t n) { XXH3_64bits_update(state, data, n); }
  uint64_t take() {  // the digest, and a fresh start
    const uint64_t h = XXH3_64bits_digest(state);
    XXH3_64bits_reset(state);
    return h;
  }
};

uint32_t first_of(const SceneChunk& c, int stream) {
  return stream == kVertexStream ? c.first_vertex : stream == kIndexStream ? c.first_index
                                                                           : c.first_uv;
}

}  // namespace

struct SceneFileWriter::State {
  explicit State(AtomicFile f) : file(std::move(f)) {}
  AtomicFile file;
  SceneFileSizes sizes;
  uint32_t chunk_triangles = kChunkTriangles;
  std::array<uint64_t, kStreamCount> offset{};   // of each array's section in the file
  std::array<uint64_t, kStreamCount> written{};  // elements
  std::vector<Object> objects;  // in the stored form (instances.hpp)
  std::vector<Instance> instances;
  std::string names;
  // Chunks: their starts as objects come; per stream, the chunk its bytes now go to.
  std::vector<SceneChunk> chunks;
  std::vector<std::array<uint64_t, kStreamCount>> chunk_hashes;
  std::array<size_t, kStreamCount> stream_chunk{};
  std::array<Hasher, kStreamCount> chunk_hasher, section_hasher;
  uint64_t chunk_triangles_now = 0;
  std::array<uint64_t, kStreamCount> end{};  // the furthest any object's range reaches
  bool in_order = true;  // every object's ranges start inside its chunk (else: one chunk)

  // The bytes of `stream` from element `at` on, to the section's checksum and to the chunks
  // they fall in.
  void hash(int stream, uint64_t at, const void* data, uint64_t count) {
    const auto* bytes = static_cast<const std::byte*>(data);
    section_hasher[stream].update(bytes, count * kElementBytes[stream]);
    while (count > 0) {
      size_t& k = stream_chunk[stream];
      const uint64_t next = k + 1 < chunks.size() ? first_of(chunks[k + 1], stream) : UINT64_MAX;
      if (at >= next) {
        chunk_hashes[k][stream] = chunk_hasher[stream].take();
        ++k;
        continue;
      }
      const uint64_t n = std::min(count, next - at);
      chunk_hasher[stream].update(bytes, n * kElementBytes[stream]);
      bytes += n * kElementBytes[stream];
      at += n;
      count -= n;
    }
  }

  Result<void> put(int stream, const void* data, uint64_t count) {
    const uint64_t at = written[stream];
    if (count && !write_all_at(file.fd(), data, count * kElementBytes[stream],
                               offset[stream] + at * kElementBytes[stream]))
      return file.failure("write failed");
    hash(stream, at, data, count);
    written[stream] += count;
    return {};
  }

  // A chunk starts before object `o` (numbered in the whole scene) when the last one is full
  // and nothing before `o` reaches past where `o` starts. An instance stores no geometry: a
  // chunk may start before it, where the stored geometry has come to, and its triangles count
  // towards its chunk's as they are read.
  void place(const Object& o, bool textured, bool instance) {
    const std::array<uint64_t, kStreamCount> start =
        instance ? end
                 : std::array<uint64_t, kStreamCount>{o.first_vertex, o.first_index,
                                                      textured ? o.first_uv : end[kUvStream]};
    const bool clean = start[0] >= end[0] && start[1] >= end[1] && start[2] >= end[2];
    const uint64_t triangles = o.triangle_count();
    if (chunks.empty() ||
        (clean && chunk_triangles_now > 0 && chunk_triangles_now + triangles > chunk_triangles)) {
      SceneChunk c;
      c.first_object = uint32_t(objects.size());
      if (!chunks.empty()) {
        c.first_vertex = uint32_t(start[0]);
        c.first_index = uint32_t(start[1]);
        c.first_uv = uint32_t(start[2]);
      }
      chunks.push_back(c);
      chunk_hashes.push_back({});
      chunk_triangles_now = 0;
    }
    chunk_triangles_now += triangles;
    if (instance) return;
    const SceneChunk& c = chunks.back();
    if (start[0] < c.first_vertex || start[1] < c.first_index || start[2] < c.first_uv)
      in_order = false;
    end[0] = std::max<uint64_t>(end[0], uint64_t(o.first_vertex) + o.vertex_count);
    end[1] = std::max<uint64_t>(end[1], uint64_t(o.first_index) + o.index_count);
    if (textured) end[2] = std::max<uint64_t>(end[2], uint64_t(o.first_uv) + o.vertex_count);
  }

  // The chunks' counts and checksums, once every byte has come.
  void close_chunks(uint64_t object_count,
                    const std::array<uint64_t, kStreamCount>& section_checksums) {
    for (int s = 0; s < kStreamCount; ++s) {
      for (; stream_chunk[s] < chunks.size(); ++stream_chunk[s])
        chunk_hashes[stream_chunk[s]][s] = chunk_hasher[s].take();
    }
    if (!in_order && !chunks.empty()) {  // one chunk of everything
      chunks.resize(1);
      chunk_hashes[0] = section_checksums;
    }
    for (size_t k = 0; k < chunks.size(); ++k) {
      SceneChunk& c = chunks[k];
      const bool last = k + 1 == chunks.size();
      c.object_count = uint32_t((last ? object_count : chunks[k + 1].first_object) -
                                c.first_object);
      c.vertex_count =
          uint32_t((last ? written[0] : chunks[k + 1].first_vertex) - c.first_vertex);
      c.index_count = uint32_t((last ? written[1] : chunks[k + 1].first_index) - c.first_index);
      c.uv_count = uint32_t((last ? written[2] : chunks[k + 1].first_uv) - c.first_uv);
      c.checksum = XXH3_64bits(chunk_hashes[k].data(), sizeof(chunk_hashes[k]));
    }
  }
};

SceneFileWriter::SceneFileWriter(std::unique_ptr<State> state) : s_(std::move(state)) {}
SceneFileWriter::SceneFileWriter(SceneFileWriter&&) noexcept = default;
SceneFileWriter& SceneFileWriter::operator=(SceneFileWriter&&) noexcept = default;
SceneFileWriter::~SceneFileWriter() = default;

uint64_t SceneFileWriter::vertices_written() const { return s_->written[kVertexStream]; }
uint64_t SceneFileWriter::indices_written() const { return s_->written[kIndexStream]; }

Result<SceneFileWriter> SceneFileWriter::create(const std::string& path, SceneFileSizes sizes,
                                                uint32_t chunk_triangles) {
  if (sizes.vertices > UINT32_MAX || sizes.indices > UINT32_MAX || sizes.indices % 3 != 0)
    return make_error(path, ": a scene of ", std::to_string(sizes.vertices), " vertices and ",
                      std::to_string(sizes.indices),
                      " indices cannot be written (at most 2^32 - 1 of each, whole triangles)");
  // Refuse before the work what the disk cannot hold (the geometry's bytes; the rest is small).
  const uint64_t geometry = sizes.vertices * sizeof(Vertex) + sizes.indices * sizeof(uint32_t);
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  struct statvfs fs {};
  if (::statvfs(folder.empty() ? "." : folder.c_str(), &fs) == 0 &&
      uint64_t(fs.f_bavail) * fs.f_frsize < geometry)
    return make_error(path, ": the scene needs ", number_text(double(geometry) / 1e9),
                      " GB and its folder's file system has ",
                      number_text(double(fs.f_bavail) * double(fs.f_frsize) / 1e9), " GB free");
  auto file = AtomicFile::create(path);
  if (!file) return file.error();
  auto s = std::make_unique<State>(std::move(*file));
  s->sizes = sizes;
  s->chunk_triangles = std::max<uint32_t>(chunk_triangles, 1);
  s->offset[kVertexStream] = kFirstSection;
  s->offset[kIndexStream] = align_up(kFirstSection + sizes.vertices * sizeof(Vertex));
  s->offset[kUvStream] = align_up(s->offset[kIndexStream] + sizes.indices * sizeof(uint32_t));
  return SceneFileWriter(std::move(s));
}

Result<void> SceneFileWriter::append(const Scene& part) {
  State& s = *s_;
  const std::string& path = s.file.path();
  if (std::string problem = validate_scene(part); !problem.empty())
    return make_error(path, ": refusing to write an invalid scene (", problem, ")");
  const uint64_t base_v = s.written[kVertexStream], base_i = s.written[kIndexStream],
                 base_u = s.written[kUvStream];
  const StoredGeometry part_size = stored_geometry(part);
  if (base_v + part_size.vertices > s.sizes.vertices ||
      base_i + part_size.indices > s.sizes.indices)
    return make_error(path, ": the scene's parts hold more than the ",
                      std::to_string(s.sizes.vertices), " vertices and ",
                      std::to_string(s.sizes.indices), " indices it was to have");
  if (s.names.size() + part.names.size() > UINT32_MAX || s.objects.size() + part.objects.size() > UINT32_MAX)
    return make_error(path, ": the scene's names or objects pass 2^32");
  // Instances' geometry is left out (their prototypes lie in the part: validate_scene).
  std::optional<StoredForm> stored;
  if (!part.instances.empty()) stored = stored_form(part);
  const std::span<const Object> objects = stored ? stored->objects : part.objects;
  const std::span<const Vertex> vertices = stored ? stored->vertices : part.vertices;
  const std::span<const uint32_t> part_indices = stored ? stored->indices : part.indices;
  const std::span<const glm::vec2> uvs = stored ? stored->uvs : part.uvs;
  const uint32_t base_object = uint32_t(s.objects.size());
  for (Instance i : part.instances) {
    i.object += base_object;
    i.prototype += base_object;
    s.instances.push_back(i);
  }
  for (uint32_t n = 0; n < objects.size(); ++n) {
    Object o = objects[n];
    const bool textured = part.textured(o);
    o.first_vertex += uint32_t(base_v);
    o.first_index += uint32_t(base_i);
    o.first_uv = textured ? o.first_uv + uint32_t(base_u) : 0;
    o.name_offset += uint32_t(s.names.size());
    s.place(o, textured, stored && instance_of(part, n));
    s.objects.push_back(o);
  }
  s.names += part.names;
  if (auto ok = s.put(kVertexStream, vertices.data(), vertices.size()); !ok) return ok;
  std::vector<uint32_t> rebased;
  constexpr size_t kSlice = size_t(1) << 18;
  for (size_t i = 0; i < part_indices.size(); i += kSlice) {
    const size_t n = std::min(kSlice, part_indices.size() - i);
    rebased.assign(part_indices.begin() + ptrdiff_t(i), part_indices.begin() + ptrdiff_t(i + n));
    for (uint32_t& index : rebased) index += uint32_t(base_v);
    if (auto ok = s.put(kIndexStream, rebased.data(), n); !ok) return ok;
  }
  return s.put(kUvStream, uvs.data(), uvs.size());
}

Result<SceneFileInfo> SceneFileWriter::finish(const Scene& rest,
                                              std::optional<uint64_t> fingerprint) {
  State& s = *s_;
  const std::string& path = s.file.path();
  const uint64_t vertices = s.written[kVertexStream], indices = s.written[kIndexStream],
                 uvs = s.written[kUvStream];
  if (vertices != s.sizes.vertices || indices != s.sizes.indices)
    return make_error(path, ": the scene's parts held ", std::to_string(vertices),
                      " vertices and ", std::to_string(indices), " indices, not the ",
                      std::to_string(s.sizes.vertices), " and ", std::to_string(s.sizes.indices),
                      " it was to have");
  // Everything but the geometry, which is in the file already.
  Scene index;
  index.objects = std::move(s.objects);
  index.names = std::move(s.names);
  index.materials = rest.materials;
  index.textures = rest.textures;
  index.cells = rest.cells;
  index.cell_objects = rest.cell_objects;
  index.portals = rest.portals;
  index.portal_points = rest.portal_points;
  index.instances = std::move(s.instances);
  index.bounds = rest.bounds;
  std::string problem = validate_scene_index(index, vertices, indices, uvs);
  if (problem.empty()) problem = validate_instances(index, InstanceForm::stored, false);
  if (!problem.empty())
    return make_error(path, ": refusing to write an invalid scene (", problem, ")");
  // The fingerprint is of the scene held, instances expanded: it cannot be read back.
  if (!fingerprint && !index.instances.empty())
    return make_error(path, ": a scene with instances is written with its fingerprint given");
  std::array<uint64_t, kStreamCount> section_checksums;
  for (int k = 0; k < kStreamCount; ++k) section_checksums[k] = s.section_hasher[k].take();
  s.close_chunks(index.objects.size(), section_checksums);

  // Read back from the file what the fingerprint needs, where the caller does not hold it.
  if (!fingerprint) {
    Result<void> read_ok;
    std::vector<std::byte> buffer(size_t(4) << 20);
    fingerprint = scene_fingerprint(index, uvs, [&](GeometryArray array, const ByteSink& feed) {
      const int stream = int(array);
      const uint64_t bytes = s.written[stream] * kElementBytes[stream];
      for (uint64_t at = 0; at < bytes && read_ok;) {
        const size_t n = size_t(std::min<uint64_t>(buffer.size(), bytes - at));
        const ssize_t got = ::pread(s.file.fd(), buffer.data(), n, off_t(s.offset[stream] + at));
        if (got <= 0) {
          if (got < 0 && errno == EINTR) continue;
          read_ok = s.file.failure("cannot read back what was written");
          break;
        }
        feed(std::span(buffer.data(), size_t(got)));
        at += uint64_t(got);
      }
    });
    if (!read_ok) return read_ok.error();
  }

  // The sections that follow the geometry, in the order written.
  std::vector<TextureEntry> textures;
  std::string texture_names;
  std::vector<std::byte> images;
  for (const Texture& t : index.textures) {
    TextureEntry e{};
    e.image_offset = images.size();
    e.image_bytes = t.encoded.size();
    e.width = t.width;
    e.height = t.height;
    e.name_offset = uint32_t(texture_names.size());
    e.name_size = uint32_t(t.name.size());
    e.codec = uint8_t(t.codec);
    e.has_alpha = t.has_alpha ? 1 : 0;
    textures.push_back(e);
    texture_names += t.name;
    images.insert(images.end(), t.encoded.begin(), t.encoded.end());
  }
  std::vector<std::pair<Tag, std::span<const std::byte>>> tail = {
      {kObjects, std::as_bytes(std::span(index.objects))},
      {kMaterials, std::as_bytes(std::span(index.materials))},
      {kNames, std::as_bytes(std::span(index.names.data(), index.names.size()))}};
  if (!index.cells.empty()) {
    tail.push_back({kCells, std::as_bytes(std::span(index.cells))});
    tail.push_back({kCellObjects, std::as_bytes(std::span(index.cell_objects))});
    tail.push_back({kPortals, std::as_bytes(std::span(index.portals))});
    tail.push_back({kPortalPoints, std::as_bytes(std::span(index.portal_points))});
  }
  if (!index.instances.empty())
    tail.push_back({kInstances, std::as_bytes(std::span(index.instances))});
  if (!textures.empty()) {
    tail.push_back({kTextures, std::as_bytes(std::span(textures))});
    tail.push_back(
        {kTextureNames, std::as_bytes(std::span(texture_names.data(), texture_names.size()))});
    tail.push_back({kImages, std::span<const std::byte>(images)});
  }
  tail.push_back({kChunks, std::as_bytes(std::span(s.chunks))});
  const uint64_t print = *fingerprint;
  tail.push_back({kFingerprint, std::as_bytes(std::span(&print, 1))});

  std::vector<SectionEntryV2> table;
  auto entry = [&](Tag tag, uint64_t offset, uint64_t bytes, uint64_t checksum) {
    SectionEntryV2 e{};
    std::memcpy(e.tag, kTagNames[tag], std::strlen(kTagNames[tag]));  // the rest stays zero
    e.offset = offset;
    e.bytes = bytes;
    e.checksum = checksum;
    e.element_size = kTagElementSize[tag];
    e.flags = optional_section(tag) ? 0 : kRequired;
    table.push_back(e);
  };
  entry(kVertices, s.offset[kVertexStream], vertices * sizeof(Vertex),
        section_checksums[kVertexStream]);
  entry(kIndices, s.offset[kIndexStream], indices * sizeof(uint32_t),
        section_checksums[kIndexStream]);
  if (uvs > 0)
    entry(kUvs, s.offset[kUvStream], uvs * sizeof(glm::vec2), section_checksums[kUvStream]);
  uint64_t offset = align_up(s.offset[kUvStream] + uvs * sizeof(glm::vec2));
  for (const auto& [tag, bytes] : tail) {
    entry(tag, offset, bytes.size(), XXH3_64bits(bytes.data(), bytes.size()));
    if (!bytes.empty() && !write_all_at(s.file.fd(), bytes.data(), bytes.size(), offset))
      return s.file.failure("write failed");
    offset = align_up(offset + bytes.size());
  }
  FF_ASSERT(table.size() <= kMostSectionsWritten, "%zu sections", table.size());

  HeaderV2 h{};
  std::memcpy(h.magic, kMagic, sizeof(kMagic));
  h.version = kSceneFileVersion;
  h.header_size = sizeof(HeaderV2);
  h.section_count = uint32_t(table.size());
  for (int a = 0; a < 3; ++a) {
    h.bounds_min[a] = index.bounds.min[a];
    h.bounds_max[a] = index.bounds.max[a];
  }
  h.file_size = offset;
  h.header_checksum = header_checksum(h, table);
  // The gaps between sections are holes, read as zeros: the same scene gives the same bytes.
  if (!write_all_at(s.file.fd(), &h, sizeof h, 0) ||
      !write_all_at(s.file.fd(), table.data(), table.size() * sizeof(SectionEntryV2), sizeof h) ||
      ::ftruncate(s.file.fd(), off_t(h.file_size)) != 0)
    return s.file.failure("write failed");
  if (auto ok = s.file.commit(); !ok) return ok.error();
  return SceneFileInfo{kSceneFileVersion, h.file_size, s.chunks.size()};
}

}  // namespace farfield
