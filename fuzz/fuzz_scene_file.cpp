// libFuzzer target for the .ffscene reader. Checksums are skipped on one pass so that the
// fuzzer reaches the structural checks behind them; the other pass is the reader as shipped.
#include <cstddef>
#include <cstdint>

#include "farfield/scene/scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  for (bool verify : {false, true}) {
    auto scene = farfield::parse_scene(bytes, "fuzz", verify);
    if (scene) {
      // An accepted scene must be safe to walk: touch every index's vertex.
      float sum = 0.0f;
      for (uint32_t index : scene->indices) sum += scene->vertices[index].position.x;
      for (const auto& object : scene->objects) {
        sum += float(scene->object_name(object).size());
        if (scene->textured(object) && object.vertex_count > 0) {  // an empty object has none
          sum += scene->uvs[object.first_uv + object.vertex_count - 1].x;
          sum += float(scene->textures[scene->materials[object.material].texture].encoded.size());
        }
      }
      volatile float sink = sum;
      (void)sink;
    }
  }
  return 0;
}
