// A Scene as glTF 2.0 binary (.glb): one node a object (named as the object), one mesh of
// one primitive each (positions, unit normals, vertex colours, texture coordinates where the
// material is textured, 32-bit indices), the scene's materials as metallic-roughness materials
// (base colour factor and texture, alpha mode and cutoff, double-sidedness) and its textures
// as embedded PNG or JPEG images. An instance (Scene::instances) whose prototype is exported too
// is a node placing the prototype's mesh with its transform as the node's matrix, so a viewer
// holds the model once. +Y up, metres, as glTF. The 3D Tiles export writes each
// tile's content through the same encoder.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

struct GlbOptions {
  // Objects whose names match this shell pattern (fnmatch: *, ?, [...]); empty: all.
  std::string objects;
  // When not empty: these objects (indices into Scene::objects), in this order, instead.
  std::vector<uint32_t> object_list;
};

struct GlbSummary {
  uint64_t objects = 0, triangles = 0, vertices = 0, materials = 0, textures = 0;
  uint64_t bytes = 0;  // of the whole .glb
};

// The .glb's bytes. Fails when no object matches, or when the file would pass the GLB
// container's 4 GiB limit (the message says how large and suggests --objects to split).
Result<std::string> encode_glb(const Scene& scene, const GlbOptions& options,
                               GlbSummary* summary = nullptr);

// encode_glb written to `path` atomically (the old file or the new one, never a part).
Result<GlbSummary> write_glb(const Scene& scene, const std::string& path,
                             const GlbOptions& options = {});

}  // namespace farfield
