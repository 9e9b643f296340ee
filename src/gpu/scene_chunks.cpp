#include "farfield/gpu/scene_chunks.hpp"

#include <algorithm>
#include <numeric>

#include "farfield/core/text.hpp"

namespace farfield::gpu {

Result<std::vector<SceneChunk>> plan_scene_chunks(const Scene& scene, uint64_t max_bytes) {
  std::vector<uint32_t> order(scene.objects.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return scene.objects[a].first_index < scene.objects[b].first_index;
  });
  std::vector<SceneChunk> chunks;
  uint64_t index_begin = 0, index_end = 0, vertex_begin = 0, vertex_end = 0;
  const auto flush = [&] {
    if (index_end > index_begin)
      chunks.push_back({uint32_t(index_begin), uint32_t(index_end - index_begin),
                        uint32_t(vertex_begin), uint32_t(vertex_end - vertex_begin)});
  };
  const auto fits = [&](uint64_t indices, uint64_t vertices) {
    return indices * sizeof(uint32_t) <= max_bytes && vertices * sizeof(Vertex) <= max_bytes;
  };
  for (uint32_t i : order) {
    const Object& o = scene.objects[i];
    if (o.index_count == 0) continue;
    if (!fits(o.index_count, o.vertex_count))
      return make_error("object ", std::to_string(i), " (", std::string(scene.object_name(o)),
                        ") has ", counted(o.vertex_count, "vertex", "vertices"), " and ",
                        counted(o.index_count / 3, "triangle"), ", more than one GPU buffer of ",
                        number_text(double(max_bytes) / (1 << 20)), " MiB holds; split it");
    const uint64_t lo = std::min<uint64_t>(vertex_begin, o.first_vertex);
    const uint64_t hi = std::max<uint64_t>(vertex_end, uint64_t(o.first_vertex) + o.vertex_count);
    const uint64_t end = uint64_t(o.first_index) + o.index_count;
    if (index_end > index_begin && fits(end - index_begin, hi - lo)) {
      index_end = end, vertex_begin = lo, vertex_end = hi;
      continue;
    }
    flush();
    index_begin = o.first_index, index_end = end;
    vertex_begin = o.first_vertex, vertex_end = uint64_t(o.first_vertex) + o.vertex_count;
  }
  flush();
  return chunks;
}

size_t chunk_of(const std::vector<SceneChunk>& chunks, uint32_t first_index) {
  const auto after =
      std::upper_bound(chunks.begin(), chunks.end(), first_index,
                       [](uint32_t i, const SceneChunk& c) { return i < c.first_index; });
  return after == chunks.begin() ? 0 : size_t(after - chunks.begin()) - 1;
}

size_t chunk_of_vertex(const std::vector<SceneChunk>& chunks, uint32_t vertex) {
  const auto after =
      std::upper_bound(chunks.begin(), chunks.end(), vertex,
                       [](uint32_t v, const SceneChunk& c) { return v < c.first_vertex; });
  return after == chunks.begin() ? 0 : size_t(after - chunks.begin()) - 1;
}

}  // namespace farfield::gpu
