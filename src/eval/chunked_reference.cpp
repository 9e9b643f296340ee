#include "farfield/eval/chunked_reference.hpp"

#include <algorithm>
#include <vector>

#include "farfield/core/frustum.hpp"
#include "farfield/techniques/chunk_stream.hpp"

namespace farfield {

namespace {

bool has_transparent(const ChunkedScene& scene, uint32_t c) {
  const Scene& index = scene.index();
  const SceneChunk& k = scene.chunks()[c];
  for (uint32_t o = k.first_object; o < k.first_object + k.object_count; ++o)
    if (index.materials[index.objects[o].material].transparent()) return true;
  return false;
}

}  // namespace

Result<void> draw_chunked_reference(gpu::Renderer& renderer, const ChunkedScene& scene,
                                    const View& view, uint64_t budget_bytes) {
  const Frustum frustum(view);
  std::vector<uint32_t> visible;
  for (uint32_t c = 0; c < scene.chunks().size(); ++c)
    if (frustum.classify(scene.chunk_bounds(c)) != Visibility::none) visible.push_back(c);
  DrawList list;
  bool drawn = false;
  // One pass over the chunks for the opaque objects, one for the semi-transparent ones.
  for (const bool transparent : {false, true}) {
    for (size_t first = 0; first < visible.size();) {
      std::vector<MeshHandle> meshes;
      list.clear();
      list.draw_over = drawn;
      uint64_t bytes = 0;
      size_t end = first;
      Result<void> ok;
      for (; end < visible.size(); ++end) {
        const uint32_t c = visible[end];
        if (end > first && bytes + scene.chunks()[c].byte_size() > budget_bytes) break;
        if (transparent && !has_transparent(scene, c)) continue;
        auto data = read_chunk_mesh(scene, c);
        if (!data) {
          ok = data.error();
          break;
        }
        auto mesh = renderer.create_scene_mesh((*data)->vertices, (*data)->uvs, (*data)->indices);
        if (!mesh) {
          ok = mesh.error();
          break;
        }
        meshes.push_back(*mesh);
        bytes += (*data)->byte_size();
        const SceneChunk& k = scene.chunks()[c];
        add_chunk_ranges(scene, c, k.first_object, k.first_object + k.object_count, *mesh,
                         transparent ? nullptr : &list.opaque,
                         transparent ? &list.transparent : nullptr);
      }
      if (ok) renderer.draw(view, list);
      for (MeshHandle m : meshes) renderer.free(m);
      if (!ok) return ok;
      drawn = true;
      first = end;
    }
  }
  if (!drawn) {
    list.clear();
    renderer.draw(view, list);  // the sky alone
  }
  return {};
}

}  // namespace farfield
