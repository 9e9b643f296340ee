#include "farfield/scene/chunked_scene.hpp"

#include <xxhash.h>

#include <algorithm>
#include <cstring>

#include "scene_file_layout.hpp"

namespace farfield {

using namespace scene_file;

Result<ChunkedScene> ChunkedScene::open(const std::string& path) {
  auto file = ReadableFile::open(path);
  if (!file) return file.error();
  ChunkedScene scene(path, std::move(*file));
  const ReadableFile& f = scene.file_handle_;
  const ReadAt read = [&](void* data, uint64_t size, uint64_t offset) {
    return f.read_at(data, size, offset);
  };
  char head[sizeof(HeaderV2)] = {};
  if (f.size() < sizeof(HeaderV2) || !f.read_at(head, sizeof head, 0) ||
      std::memcmp(head, kMagic, sizeof(kMagic)) != 0) {
    // Not a version 2 or 3 file: the whole-file reader says what it is.
    SceneFileInfo info;
    if (auto whole = read_scene(path, &info); !whole) return whole.error();
    return make_error(path, ": a version ", std::to_string(info.version),
                      " .ffscene file, written before chunks: rewrite it (farfield import ", path,
                      " --out NEW.ffscene) to read it in parts");
  }
  uint32_t version = 0;
  std::memcpy(&version, head + 8, sizeof version);
  if (version != 2 && version != kSceneFileVersion) {
    if (auto whole = read_scene(path); !whole) return whole.error();
    return make_error(path, ": a version ", std::to_string(version),
                      " .ffscene file, written before chunks: rewrite it (farfield import ", path,
                      " --out NEW.ffscene) to read it in parts");
  }
  auto table = read_section_table(head, f.size(), path, read);
  if (!table) return table.error();
  if (auto ok = read_index_sections(*table, scene.index_, path, true, read); !ok)
    return ok.error();
  scene.vertex_count_ = table->count(kVertices);
  scene.index_count_ = table->count(kIndices);
  scene.uv_count_ = table->count(kUvs);
  if (std::string problem = validate_scene_index(scene.index_, scene.vertex_count_,
                                                 scene.index_count_, scene.uv_count_);
      !problem.empty())
    return make_error(path, ": invalid .ffscene contents (", problem, ")");
  auto chunks = read_chunk_table(*table, scene.index_, path, true, read);
  if (!chunks) return chunks.error();
  if (chunks->empty() && !scene.index_.objects.empty())
    return make_error(path, ": written before chunks: rewrite it (farfield import ", path,
                      " --out NEW.ffscene) to read it in parts");
  if (!table->found[kFingerprint])
    return corrupted(path, "chunks without the scene's fingerprint");
  if (auto ok = read(&scene.fingerprint_, sizeof(uint64_t), table->found[kFingerprint]->offset);
      !ok)
    return ok.error();
  if (XXH3_64bits(&scene.fingerprint_, sizeof(uint64_t)) != table->found[kFingerprint]->checksum)
    return corrupted(path, "fingerprint section checksum mismatch");
  scene.chunks_ = std::move(*chunks);
  for (const SceneChunk& k : scene.chunks_) {
    Bounds3& b = scene.chunk_bounds_.emplace_back();
    for (uint32_t o = k.first_object; o < k.first_object + k.object_count; ++o)
      b.expand(scene.index_.objects[o].bounds);
  }
  scene.offset_[0] = table->found[kVertices]->offset;
  scene.offset_[1] = table->found[kIndices]->offset;
  scene.offset_[2] = table->found[kUvs] ? table->found[kUvs]->offset : 0;
  scene.file_ = {version, f.size(), scene.chunks_.size()};
  return scene;
}

uint32_t ChunkedScene::chunk_of(uint32_t object) const {
  const auto it = std::upper_bound(
      chunks_.begin(), chunks_.end(), object,
      [](uint32_t o, const SceneChunk& c) { return o < c.first_object; });
  return uint32_t(it - chunks_.begin()) - 1;
}

Result<void> ChunkedScene::read_chunk(size_t c, ChunkGeometry& out) const {
  const SceneChunk& k = chunks_.at(c);
  auto named = [&](const std::string& problem) {
    const Object& first = index_.objects[k.first_object];
    return make_error(path_, ": chunk ", std::to_string(c), " (objects ",
                      std::to_string(k.first_object), " to ",
                      std::to_string(k.first_object + k.object_count - 1), ", from '",
                      std::string(index_.object_name(first)), "'): ", problem);
  };
  out.vertices.resize(k.vertex_count);
  out.indices.resize(k.index_count);
  out.uvs.resize(k.uv_count);
  const uint64_t bytes[3] = {uint64_t(k.vertex_count) * sizeof(Vertex),
                             uint64_t(k.index_count) * sizeof(uint32_t),
                             uint64_t(k.uv_count) * sizeof(glm::vec2)};
  const uint64_t at[3] = {offset_[0] + uint64_t(k.first_vertex) * sizeof(Vertex),
                          offset_[1] + uint64_t(k.first_index) * sizeof(uint32_t),
                          offset_[2] + uint64_t(k.first_uv) * sizeof(glm::vec2)};
  void* data[3] = {out.vertices.data(), out.indices.data(), out.uvs.data()};
  uint64_t hashes[3];
  for (int s = 0; s < 3; ++s) {
    // The file may have changed since it was opened: a read past its end is "truncated".
    if (bytes[s] > 0)
      if (auto ok = file_handle_.read_at(data[s], bytes[s], at[s]); !ok) {
        std::string problem = ok.error().message;
        if (problem.starts_with(path_ + ": ")) problem.erase(0, path_.size() + 2);
        return named(problem);
      }
    hashes[s] = XXH3_64bits(data[s], bytes[s]);
  }
  if (XXH3_64bits(hashes, sizeof hashes) != k.checksum)
    return named("checksum mismatch (corrupted .ffscene file)");
  if (std::string problem = validate_geometry(
          index_, k.first_object, k.object_count,
          {.vertices = out.vertices, .indices = out.indices, .uvs = out.uvs,
           .vertex_base = k.first_vertex, .index_base = k.first_index, .uv_base = k.first_uv});
      !problem.empty())
    return named("invalid contents (" + problem + ")");
  for (uint32_t& index : out.indices) index -= k.first_vertex;
  return {};
}

Result<float> sampled_triangle_edge(const ChunkedScene& scene, size_t chunks) {
  const size_t n = scene.chunks().size();
  if (n == 0 || chunks == 0) return 0.0f;
  const size_t count = std::min(n, chunks);
  std::vector<float> medians;
  ChunkGeometry geometry;
  for (size_t i = 0; i < count; ++i) {
    if (auto ok = scene.read_chunk(i * n / count, geometry); !ok) return ok.error();
    if (!geometry.indices.empty())
      medians.push_back(median_triangle_edge(geometry.vertices, geometry.indices, 1u << 16));
  }
  if (medians.empty()) return 0.0f;
  std::nth_element(medians.begin(), medians.begin() + medians.size() / 2, medians.end());
  return medians[medians.size() / 2];
}

}  // namespace farfield
