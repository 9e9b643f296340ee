// Leaf colour-cubes (paper 002, Sec. 4.1): a leaf cell's triangles rendered orthographically
// through each of its six faces at k x k pixels per cube, and the non-background pixels
// averaged into the face colour. With clustering (Sec. 4.2) the cell holds c x c x c cubes:
// each direction is rendered at (c k) x (c k) pixels into c depth slabs at once (every slab
// keeps its own nearest fragment, as if drawn with clip planes at the slab boundaries), so a
// cube behind another still gets its own colour.
//
// Rendering is a small CPU rasterizer sampling pixel centres, with the renderer's lighting
// (gpu/lighting.hpp), culling (back faces of opaque materials dropped) and textures (sampled
// from the mip level of the pixel's footprint, mask materials cut out below their cutoff), so
// baked colours match drawn ones. Pure CPU: bakes run on every core without a GL context.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "farfield/core/bounds.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/scene/texture_sampler.hpp"
#include "farfield/techniques/colorcube/color_cube.hpp"

namespace farfield {

enum class CoverageMode {
  binary,    // paper 002: 1 when any pixel is covered, else 0
  fraction,  // the fraction of covered pixels (the paper's suggested alternative)
};

struct LeafBakeOptions {
  int oversampling = 1;  // k: pixels per cube side, 1..5 (paper 002, Sec. 4.1)
  int cluster = 1;       // c: cubes per cell side (paper 002, Sec. 4.2)
  CoverageMode coverage = CoverageMode::binary;
};

// The material of every triangle of the scene, for bake_leaf (4 bytes per triangle).
std::vector<uint32_t> triangle_materials(const Scene& scene);

// What bake_leaf needs of a textured scene: its textures decoded, and each vertex's texture
// coordinate (an index into Scene::uvs, kNoTexture where it has none). Empty for a scene
// without textures; refused naming a texture that does not decode.
struct LeafTextures {
  std::vector<TextureSampler> samplers;
  std::vector<uint32_t> vertex_uv;
};
Result<LeafTextures> leaf_textures(const Scene& scene);

// `triangles` are triangle numbers of `scene` (index / 3); `materials` from
// triangle_materials(). `cell` must be a cube. Returns c^3 cubes, cube (x, y, z) at
// x + c (y + c z), x along +X from cell.min. Semi-transparent materials count as opaque
// (their colour, both sides drawn, as the renderer draws them without culling).
std::vector<ColorCube> bake_leaf(const Scene& scene, std::span<const uint32_t> materials,
                                 std::span<const uint32_t> triangles, const Bounds3& cell,
                                 const LeafBakeOptions& options, const LeafTextures& textures = {});

}  // namespace farfield
