// libFuzzer target for the colour-cube bake reader (load_cube_tree): a pack holding fuzzed
// cells, proxy vertices, proxy indices, scene ranges and statistics. An accepted tree must be
// safe to walk: every cell's ranges are followed to their vertices and scene triangles.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "farfield/techniques/colorcube/cube_tree.hpp"
#include "fuzz_pack.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  const std::string path = fuzz::scratch_pack("cube-tree");
  fuzz::remove_pack(path);
  {
    auto store = farfield::Store::open(path, farfield::Store::Mode::kReadWrite);
    if (!store) std::abort();
    {
      auto transaction = store->begin();
      if (!transaction) std::abort();
      fuzz::put(*store, "colorcube/cells", fuzz::records(in, sizeof(farfield::CubeCell)));
      fuzz::put(*store, "colorcube/proxy_vertices",
                fuzz::records(in, sizeof(farfield::ProxyVertex)));
      fuzz::put(*store, "colorcube/proxy_indices", fuzz::records(in, sizeof(uint32_t)));
      fuzz::put(*store, "colorcube/scene_ranges", fuzz::records(in, sizeof(farfield::DrawRange)));
      fuzz::put(*store, "colorcube/stats", fuzz::records(in, sizeof(farfield::CubeTreeStats)));
      (void)transaction->commit();
    }
    const farfield::Scene& scene = fuzz::small_scene();
    auto tree = farfield::load_cube_tree(*store, scene);
    if (tree) {
      uint64_t sum = 0;
      for (const farfield::CubeCell& c : tree->cells) {
        for (int f = 0; f < 6; ++f)
          for (uint32_t k = c.faces_begin[f]; k < c.faces_begin[f] + c.faces_count[f]; ++k)
            sum += tree->proxies.vertices[tree->proxies.indices[k]].color;
        for (uint32_t k = c.geometry_begin; k < c.geometry_begin + c.geometry_count; ++k)
          sum += tree->proxies.vertices[tree->proxies.indices[k]].color;
        for (uint32_t k = c.scene_ranges_begin; k < c.scene_ranges_begin + c.scene_ranges_count;
             ++k) {
          const farfield::DrawRange& r = tree->scene_ranges[k];
          for (uint32_t i = r.first_index; i < r.first_index + r.index_count; ++i)
            sum += scene.indices[i] + scene.materials[r.material].texture;
        }
        if (c.child_count > 0 && uint64_t(c.first_child) + c.child_count > tree->cells.size())
          std::abort();
      }
      volatile uint64_t sink = sum;
      (void)sink;
    }
  }
  fuzz::remove_pack(path);
  return 0;
}
