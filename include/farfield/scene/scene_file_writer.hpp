// Writing a .ffscene in parts, so that a scene larger than memory can be written while it is
// made (generate city --target-triangles 100000000): the geometry of each part goes to the file
// as it comes, and only the objects' table (64 bytes an object), their names and the chunk
// table stay in memory until finish(). write_scene is one part and finish.
//
// The file is the one write_scene writes for the same scene, byte for byte, whatever the parts
// (SceneFileWriter.PartsMakeTheSameFile): chunks are cut at objects, never at parts. It is
// written beside the destination and renamed over it by finish(); a writer destroyed before
// then removes it, so a failed or interrupted write leaves the old file (or none).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/scene/scene_file.hpp"

namespace farfield {

// What the parts will hold together, said up front so that each section's place is known.
struct SceneFileSizes {
  uint64_t vertices = 0;
  uint64_t indices = 0;
};

class SceneFileWriter {
 public:
  static Result<SceneFileWriter> create(const std::string& path, SceneFileSizes sizes,
                                        uint32_t chunk_triangles = kChunkTriangles);
  SceneFileWriter(SceneFileWriter&&) noexcept;
  SceneFileWriter& operator=(SceneFileWriter&&) noexcept;
  ~SceneFileWriter();

  // Appends the objects of `part` with their geometry. The part is a scene of its own (its
  // objects' vertex, index, texture coordinate and name offsets count from its arrays' start,
  // its indices from its first vertex) whose materials are the scene's: those of the last part
  // and of finish()'s `rest` must agree. Fails when the parts outgrow the sizes given.
  Result<void> append(const Scene& part);

  // Writes what is not geometry (objects, materials, names, textures, cells and portals from
  // `rest`, whose objects, vertices and indices are ignored), the chunk table, the header, and
  // renames the file into place. `fingerprint`: the scene's (scene_fingerprint), where the
  // caller holds it; otherwise it is computed by reading the geometry back from the file.
  // Fails when the parts fell short of the sizes given, or the whole breaks a scene invariant.
  Result<SceneFileInfo> finish(const Scene& rest, std::optional<uint64_t> fingerprint = {});

  uint64_t vertices_written() const;
  uint64_t indices_written() const;

 private:
  struct State;
  explicit SceneFileWriter(std::unique_ptr<State> state);
  std::unique_ptr<State> s_;
};

}  // namespace farfield
