// A human-readable summary of a scene for `farfield info`: counts, bounds, bytes, objects and
// triangles by kind, file version.
#pragma once

#include <string>

#include "farfield/scene/scene.hpp"
#include "farfield/scene/scene_file.hpp"

namespace farfield {

struct SceneSummaryInput {
  const Scene& scene;
  std::string path;
  SceneFileInfo file;
  double load_seconds = 0.0;
};

std::string summarize_scene(const SceneSummaryInput& input);

}  // namespace farfield
