#include "farfield/techniques/chunk_stream.hpp"

#include <algorithm>

namespace farfield {

Result<std::shared_ptr<const SceneMeshData>> read_chunk_mesh(const ChunkedScene& scene,
                                                             uint32_t chunk) {
  ChunkGeometry g;
  if (auto ok = scene.read_chunk(chunk, g); !ok) return ok.error();
  auto mesh = std::make_shared<SceneMeshData>();
  mesh->vertices = std::move(g.vertices);
  mesh->indices = std::move(g.indices);
  const SceneChunk& k = scene.chunks()[chunk];
  if (!g.uvs.empty()) {
    mesh->uvs.assign(mesh->vertices.size(), glm::vec2(0.0f));
    const Scene& index = scene.index();
    for (uint32_t o = k.first_object; o < k.first_object + k.object_count; ++o) {
      const Object& object = index.objects[o];
      if (!index.textured(object)) continue;
      std::copy_n(g.uvs.begin() + (object.first_uv - k.first_uv), object.vertex_count,
                  mesh->uvs.begin() + (object.first_vertex - k.first_vertex));
    }
  }
  return std::shared_ptr<const SceneMeshData>(std::move(mesh));
}

void add_chunk_ranges(const ChunkedScene& scene, uint32_t chunk, uint32_t first_object,
                      uint32_t end_object, MeshHandle mesh, std::vector<DrawRange>* opaque,
                      std::vector<DrawRange>* transparent) {
  const Scene& index = scene.index();
  const SceneChunk& k = scene.chunks()[chunk];
  for (uint32_t o = first_object; o < end_object; ++o) {
    const Object& object = index.objects[o];
    auto* ranges = index.materials[object.material].transparent() ? transparent : opaque;
    if (!ranges || object.index_count == 0) continue;
    const uint32_t first = object.first_index - k.first_index;
    if (!ranges->empty() && ranges->back().mesh == mesh &&
        ranges->back().material == object.material &&
        ranges->back().first_index + ranges->back().index_count == first)
      ranges->back().index_count += object.index_count;
    else
      ranges->push_back({first, object.index_count, object.material, mesh});
  }
}

Result<std::unique_ptr<ChunkStream>> ChunkStream::create(const ChunkedScene& scene,
                                                         gpu::Device& device,
                                                         uint64_t budget_bytes) {
  std::unique_ptr<ChunkStream> stream(new ChunkStream(scene));
  uint64_t smallest = UINT64_MAX;
  for (const SceneChunk& k : scene.chunks())
    smallest = std::min(smallest, std::max<uint64_t>(k.byte_size(), 1));
  // As many meshes as chunks could be resident at once, within reason.
  const uint64_t meshes = std::clamp<uint64_t>(
      smallest == UINT64_MAX ? 1 : budget_bytes / smallest + 1, 1,
      std::min<uint64_t>(std::max<size_t>(scene.chunks().size(), 1), 8192));
  auto pool = gpu::MeshPool::create(
      device, {budget_bytes, uint32_t(meshes)},
      [&scene](uint64_t key) { return read_chunk_mesh(scene, uint32_t(key)); });
  if (!pool) return pool.error();
  stream->pool_ = std::move(*pool);
  return stream;
}

bool ChunkStream::draw_chunk(uint32_t chunk, float priority, DrawList& out) {
  const auto mesh = pool_->want(chunk, priority);
  if (!mesh) return false;
  const SceneChunk& k = scene_.chunks()[chunk];
  add_chunk_ranges(scene_, chunk, k.first_object, k.first_object + k.object_count, *mesh,
                   &out.opaque, &out.transparent);
  return true;
}

bool ChunkStream::draw_object(uint32_t object, float priority, DrawList& out) {
  const uint32_t chunk = scene_.chunk_of(object);
  const auto mesh = pool_->want(chunk, priority);
  if (!mesh) return false;
  add_chunk_ranges(scene_, chunk, object, object + 1, *mesh, &out.opaque, &out.transparent);
  return true;
}

}  // namespace farfield
