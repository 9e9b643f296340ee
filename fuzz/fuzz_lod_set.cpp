// libFuzzer target for the clusters bake reader (load_lod_set): a pack holding fuzzed LOD
// vertices, texture coordinates, indices and records. An accepted set must be safe to draw:
// every level's indices are followed to their vertices, every object's levels to the records.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "farfield/techniques/clusters/lod_set.hpp"
#include "fuzz_pack.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  const std::string path = fuzz::scratch_pack("lod-set");
  fuzz::remove_pack(path);
  {
    auto store = farfield::Store::open(path, farfield::Store::Mode::kReadWrite);
    if (!store) std::abort();
    {
      auto transaction = store->begin();
      if (!transaction) std::abort();
      fuzz::put(*store, "clusters/lod_vertices", fuzz::records(in, sizeof(farfield::Vertex)));
      fuzz::put(*store, "clusters/lod_uvs", fuzz::records(in, sizeof(glm::vec2)));
      fuzz::put(*store, "clusters/lod_indices", fuzz::records(in, sizeof(uint32_t)));
      fuzz::put(*store, "clusters/lods", fuzz::records(in, sizeof(farfield::Lod)));
      (void)transaction->commit();
    }
    const farfield::Scene& scene = fuzz::small_scene();
    auto set = farfield::load_lod_set(*store, scene);
    if (set) {
      if (set->first_lod.size() != scene.objects.size() + 1) std::abort();
      uint64_t sum = 0;
      for (size_t o = 0; o < scene.objects.size(); ++o)
        for (uint32_t k = set->first_lod[o]; k < set->first_lod[o + 1]; ++k) {
          const farfield::Lod& lod = set->lods[k];
          if (lod.object != o) std::abort();
          for (uint32_t i = lod.first_index; i < lod.first_index + lod.index_count; ++i)
            sum += set->vertices[set->indices[i]].color;
        }
      volatile uint64_t sink = sum;
      (void)sink;
    }
  }
  fuzz::remove_pack(path);
  return 0;
}
