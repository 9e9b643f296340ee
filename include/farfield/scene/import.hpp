// Import of model files through assimp (OBJ, PLY, OFF, glTF/GLB, STL, DAE, 3DS, IFC and the
// other formats assimp reads) into one Scene.
//
// Node transforms are applied to positions and normals; each (node, mesh) pair becomes one
// object named after the node and the mesh; a material's diffuse colour and opacity become the
// object's Material; vertex colours are kept when the mesh has them. Models are converted to
// +Y up where the format says otherwise (assimp's convention is already +Y up).
#pragma once

#include <span>
#include <string>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

// What the file does not say, or says wrongly: its up axis and its unit (a GLB in millimetres
// has scale 0.001). Applied after the file's own transforms and the unit the file states
// (FBX's UnitScaleFactor): rotated to +Y up, then scaled.
struct ImportOptions {
  char up = 'y';       // 'y' or 'z': the axis that points up in the file
  double scale = 1.0;  // metres per file unit, > 0
};

// Appends the model in `path` to `scene`. On error the scene is left as it was and the message
// names the file and the problem (missing, empty, not a model, truncated, no triangles).
Result<void> import_model(const std::string& path, Scene& scene, const ImportOptions& options = {});

// Imports several files into one new scene, in order.
Result<Scene> import_models(std::span<const std::string> paths, Progress& progress,
                            const ImportOptions& options = {});

}  // namespace farfield
