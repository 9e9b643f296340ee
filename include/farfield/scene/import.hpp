// Import of model files through assimp (OBJ, PLY, OFF, glTF/GLB, STL, DAE, 3DS, IFC and the
// other formats assimp reads) into one Scene.
//
// Node transforms are applied to positions and normals; each (node, mesh) pair becomes one
// object named after the node and the mesh; a material's diffuse colour and opacity become the
// object's Material; vertex colours are kept when the mesh has them. Models are converted to
// +Y up where the format says otherwise (assimp's convention is already +Y up).
//
// Base-colour textures (glTF baseColorTexture, OBJ map_Kd, the diffuse map of Collada, FBX,
// AC3D, 3DS and the rest): embedded in the file or its .bin, or an image file beside the
// model (paths relative to it; Windows separators and %20 accepted). Their first texture
// coordinates are kept, flipped to glTF's top-left origin; wrap modes and glTF's alpha mode
// and cutoff too (other formats: a texture with transparent texels is a mask at 0.5). A
// texture that cannot be found or decoded refuses the import, naming it, unless
// ImportOptions::drop_bad_textures (then the material keeps its colour, and the report names
// what was dropped). A textured material on a mesh without texture coordinates is drawn
// with its colour alone.
//
// Cells and portals by node names (docs/techniques/portal.md): "NAME-cell" (or "-room") is a
// cell whose meshes are its objects, "OTHER-portal" inside it a portal to cell OTHER (its mesh
// the polygon, not drawn), "ANY-bound" inside it the cell's box; objects outside every cell
// are seen from all of them. A broken portal refuses the import, naming the node.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

// What the file does not say, or says wrongly: its up axis and its unit (a GLB in millimetres
// has scale 0.001). Applied after the file's own transforms and the unit the file states
// (FBX's UnitScaleFactor): rotated to +Y up, then scaled.
struct ImportOptions {
  char up = 'y';                   // 'y' or 'z': the axis that points up in the file
  double scale = 1.0;              // metres per file unit, > 0
  bool drop_bad_textures = false;  // keep the base colour where a texture fails
  // A mesh that several nodes place: its later placements kept as instances of its first
  // (Scene::instances, stored once), where neither or both mirror. False: each expanded apart.
  bool instances = true;
};

// What an import left out.
struct ImportReport {
  std::vector<std::string> dropped_textures;  // "FILE: why", with drop_bad_textures
};

// Appends the model in `path` to `scene`. On error the scene is left as it was and the message
// names the file and the problem (missing, empty, not a model, truncated, no triangles).
Result<void> import_model(const std::string& path, Scene& scene, const ImportOptions& options = {},
                          ImportReport* report = nullptr);

// Imports several files into one new scene, in order.
Result<Scene> import_models(std::span<const std::string> paths, Progress& progress,
                            const ImportOptions& options = {}, ImportReport* report = nullptr);

}  // namespace farfield
