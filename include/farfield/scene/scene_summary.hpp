// A human-readable summary of a scene for `farfield info`: counts, bounds, bytes, objects and
// triangles by kind, file version.
#pragma once

#include <string>

#include "farfield/scene/chunked_scene.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/scene/scene_file.hpp"

namespace farfield {

struct SceneSummaryInput {
  const Scene& scene;  // without geometry where `on_disk` is given (its index())
  std::string path;
  SceneFileInfo file;
  double load_seconds = 0.0;
  const ChunkedScene* on_disk = nullptr;  // the geometry left in the file
  float detail_m = -1.0f;                 // < 0: the scene's median_triangle_edge
};

std::string summarize_scene(const SceneSummaryInput& input);

}  // namespace farfield
