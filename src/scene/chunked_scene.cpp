#include "farfield/scene/chunked_scene.hpp"

#include <xxhash.h>

#include <algorithm>
#include <cstring>

#include "farfield/scene/instances.hpp"
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
  std::string problem = validate_scene_index(scene.index_, scene.vertex_count_,
                                             scene.index_count_, scene.uv_count_);
  if (problem.empty()) problem = validate_instances(scene.index_, InstanceForm::stored, false);
  if (!problem.empty()) return make_error(path, ": invalid .ffscene contents (", problem, ")");
  auto chunks = read_chunk_table(*table, scene.index_, path, true, read);
  if (!chunks) return chunks.error();
  if (!scene.index_.instances.empty()) {
    // Keep the stored form for reading; show the held one (every object its own ranges).
    scene.stored_.objects = scene.index_.objects;
    scene.stored_.instances = scene.index_.instances;
    scene.stored_.materials = scene.index_.materials;
    scene.stored_chunks_ = *chunks;
    uint64_t vertex = 0, index = 0, uv = 0;
    for (Object& o : scene.index_.objects) {
      o.first_vertex = uint32_t(vertex);
      o.first_index = uint32_t(index);
      o.first_uv = scene.index_.textured(o) ? uint32_t(uv) : 0;
      vertex += o.vertex_count;
      index += o.index_count;
      if (scene.index_.textured(o)) uv += o.vertex_count;
    }
    uint64_t chunk_uv = 0;
    for (SceneChunk& k : *chunks) {
      const Object& first = scene.index_.objects[k.first_object];
      const Object& last = scene.index_.objects[k.first_object + k.object_count - 1];
      k.first_vertex = first.first_vertex;
      k.vertex_count = last.first_vertex + last.vertex_count - first.first_vertex;
      k.first_index = first.first_index;
      k.index_count = last.first_index + last.index_count - first.first_index;
      k.first_uv = uint32_t(chunk_uv);
      k.uv_count = 0;
      for (uint32_t n = k.first_object; n < k.first_object + k.object_count; ++n)
        if (scene.index_.textured(scene.index_.objects[n]))
          k.uv_count += scene.index_.objects[n].vertex_count;
      chunk_uv += k.uv_count;
    }
    scene.vertex_count_ = vertex;
    scene.index_count_ = index;
    scene.uv_count_ = uv;
  }
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

Result<void> ChunkedScene::read_stored(size_t c, ChunkGeometry& out) const {
  const bool instanced = !stored_chunks_.empty();
  const SceneChunk& k = instanced ? stored_chunks_.at(c) : chunks_.at(c);
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
          instanced ? stored_ : index_, k.first_object, k.object_count,
          {.vertices = out.vertices, .indices = out.indices, .uvs = out.uvs,
           .vertex_base = k.first_vertex, .index_base = k.first_index, .uv_base = k.first_uv,
           .stored = instanced});
      !problem.empty())
    return named("invalid contents (" + problem + ")");
  return {};
}

Result<void> ChunkedScene::read_chunk(size_t c, ChunkGeometry& out) const {
  const SceneChunk& k = chunks_.at(c);
  if (stored_chunks_.empty()) {
    if (auto ok = read_stored(c, out); !ok) return ok;
    for (uint32_t& index : out.indices) index -= k.first_vertex;
    return {};
  }
  // Stored chunks, this one's and those of prototypes that lie elsewhere, read once each.
  std::vector<std::pair<size_t, ChunkGeometry>> read;
  auto stored_chunk = [&](size_t chunk) -> Result<const ChunkGeometry*> {
    for (const auto& [n, g] : read)
      if (n == chunk) return &g;
    auto& [n, g] = read.emplace_back(chunk, ChunkGeometry{});
    if (auto ok = read_stored(chunk, g); !ok) return ok.error();
    return &g;
  };
  if (auto own = stored_chunk(c); !own) return own.error();
  out.vertices.resize(k.vertex_count);
  out.indices.resize(k.index_count);
  out.uvs.resize(k.uv_count);
  for (uint32_t n = k.first_object; n < k.first_object + k.object_count; ++n) {
    const Object& to = index_.objects[n];
    const Instance* instance = instance_of(stored_, n);
    const uint32_t source = instance ? instance->prototype : n;
    const Object& from = stored_.objects[source];
    const size_t from_chunk = instance ? chunk_of(source) : c;
    auto geometry = stored_chunk(from_chunk);
    if (!geometry) return geometry.error();
    const ChunkGeometry& g = **geometry;
    const SceneChunk& s = stored_chunks_[from_chunk];
    const Vertex* vertices = g.vertices.data() + (from.first_vertex - s.first_vertex);
    Vertex* vertices_to = out.vertices.data() + (to.first_vertex - k.first_vertex);
    if (instance) {
      const InstanceTransform move(*instance);
      for (uint32_t v = 0; v < to.vertex_count; ++v) vertices_to[v] = move(vertices[v]);
    } else {
      std::copy_n(vertices, to.vertex_count, vertices_to);
    }
    const uint32_t* indices = g.indices.data() + (from.first_index - s.first_index);
    uint32_t* indices_to = out.indices.data() + (to.first_index - k.first_index);
    for (uint32_t i = 0; i < to.index_count; ++i)
      indices_to[i] = indices[i] - from.first_vertex + (to.first_vertex - k.first_vertex);
    if (index_.textured(to))
      std::copy_n(g.uvs.data() + (from.first_uv - s.first_uv), to.vertex_count,
                  out.uvs.data() + (to.first_uv - k.first_uv));
  }
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
