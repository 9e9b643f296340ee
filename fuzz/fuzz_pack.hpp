// Shared by the fuzz targets of technique bakes: a scratch .ffpack (in /dev/shm where there is
// one, so that each input costs little I/O) filled with fuzzed blobs, removed again.
#pragma once

#include <fuzzer/FuzzedDataProvider.h>
#include <unistd.h>

#include <filesystem>
#include <span>
#include <string>

#include "farfield/scene/scene.hpp"
#include "farfield/store/store.hpp"

namespace fuzz {

// A blob stored as given (uncompressed); a refusal is the reader's to meet, not the target's.
inline void put(farfield::Store& store, const std::string& name, const std::string& bytes) {
  (void)store.put(name, std::as_bytes(std::span(bytes.data(), bytes.size())),
                  farfield::Codec::kNone);
}

// Fuzzed bytes, cut to whole records of `record` bytes more often than not, so that the checks
// behind a reader's size checks are met.
inline std::string records(FuzzedDataProvider& in, size_t record) {
  std::string bytes = in.ConsumeRandomLengthString(1 << 16);
  if (in.ConsumeBool()) bytes.resize(bytes.size() / record * record);
  return bytes;
}

// The scene a fuzzed bake is read for: two objects of one triangle each, two materials.
inline const farfield::Scene& small_scene() {
  static const farfield::Scene scene = [] {
    farfield::Scene s;
    farfield::SceneBuilder b(s);
    for (int i = 0; i < 2; ++i) {
      const uint32_t m = b.add_material(farfield::Material{glm::vec4(1.0f)});
      b.begin_object("triangle", farfield::ObjectKind::mesh, m);
      for (int k = 0; k < 3; ++k)
        b.add_vertex({float(k == 1) + float(i), float(k == 2), 0.0f}, {0, 0, 1}, 0xffffffffu);
      b.add_triangle(0, 1, 2);
      b.end_object();
    }
    return s;
  }();
  return scene;
}

inline std::string scratch_pack(const char* target) {
  const std::filesystem::path dir = std::filesystem::is_directory("/dev/shm")
                                        ? "/dev/shm"
                                        : std::filesystem::temp_directory_path();
  return (dir / (std::string("farfield-") + target + "-" + std::to_string(::getpid()) + ".ffpack"))
      .string();
}

inline void remove_pack(const std::string& path) {
  for (const char* suffix : {"", "-journal", "-wal", "-shm"}) ::unlink((path + suffix).c_str());
}

}  // namespace fuzz
