// A landscape: rolling hills with groves of trees, the kind of open, unoccluded scene paper 002
// tested (Sec. 5, Table 1, "Landscape (F)": grassy hills with trees, 2.4M polygons).
//
// The ground is a height field of fractal value noise (octaves of smoothly interpolated random
// lattice values, each twice the frequency and half the amplitude of the last), rescaled so
// that its lowest point is at y = 0 and its highest at y = relief, sampled on a square grid of
// resolution x resolution cells. The same seed gives the same hills at any --resolution and
// --size; the resolution only decides the finest octave (2 cells a wavelength).
// Colours by height and slope: lush grass in the valleys, drier grass higher up, rock on steep
// slopes and near the top.
//
// Trees: `trees` L-system trees (tree_generator.hpp, 4 or 5 iterations, 7 to 15 m, each its own
// seed, angles and size) in groves of about 16, each grove a disk about 28 m across round a
// random centre. A tree (or a grove centre) stands on a slope under about 30 degrees and below
// 3/4 of the relief; where 64 tries find no such place it takes the gentlest. Each trunk stands
// on the triangulated ground below it, sunk 0.2 m so that it does not float on a slope.
//
// Layout: +Y up, the terrain spans [-size/2, size/2] in X and Z. Objects:
//   terrain_I_J   kind terrain: tile (I, J), tile x tile cells from cell (I * tile, J * tile)
//   tree_K        kind tree: one object per tree
// One opaque white material; colours are in the vertices.
//
// Deterministic: the same options give the same scene, byte for byte.
//
// Cost: the default landscape (1 km, 256 x 256 cells in 256 tiles, 200 trees) has about 2.7M
// triangles and takes about 0.7 s on one core, writing the 100 MB file included.
#pragma once

#include <cstdint>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

struct LandscapeOptions {
  double size = 1000.0;       // side of the square terrain, metres
  uint32_t resolution = 256;  // grid cells per side, 1 to 8192
  uint32_t tile_cells = 16;   // grid cells per side of a tile (object), 1 to 4096
  double relief = 80.0;       // highest minus lowest ground, metres; 0: flat
  uint32_t trees = 200;       // 0 to 50000
  uint64_t seed = 1;
};

// Checks the options; the message names the option as on the command line.
Result<void> validate_landscape_options(const LandscapeOptions& options);

// Generates the landscape into a new scene, with progress per tile and per tree.
Result<Scene> generate_landscape(const LandscapeOptions& options, Progress& progress);

}  // namespace farfield
