// The random city of paper 000, Appendix A: a rectangular grid of blocks separated by streets,
// each block a building block (rows and columns of lots holding parks, buildings, fountains)
// or a park block (one big park with a fountain in the middle), some blocks lined with trees.
//
// Deterministic: the same options give the same scene, byte for byte, on every run; each
// block draws from its own random stream (seed, block row, block column), so growing the grid
// keeps the existing blocks unchanged.
//
// Layout: +Y up, the city spans [0, blocks_x * (block_length + street_width) + street_width]
// along X (Z likewise), streets on the outside too. Block (i, j) starts at
// x = street_width + i * (block_length + street_width). Street tops are at street_height, curb
// and block ground tops at street_height + curb_height; building tops stay under max_height.
//
// Objects, one per thing, named for people and scripts:
//   crossing_I_J, street_x_I_J, street_z_I_J     kind street: the crossing at the -X -Z corner
//                                                of block (I, J), the streets from it along X
//                                                and along Z to the next crossings
//   block_I_J/curb_K (K < 4)                     kind curb
//   block_I_J/ground                             kind ground
//   block_I_J/building_K, /fountain_K, /tree_K   kinds building, fountain, tree
//   block_I_J/park_K_C (C < 4: its L strips)     kind park
// Semi-transparent buildings use a material of base colour (1, 1, 1, 0.5); everything else is
// opaque white and takes its colours from the vertices.
//
// Cost: the default city (8 x 8 blocks, about 1 km square) has about 1.2M triangles and is
// generated in about 0.1 s; 10M triangles take about 1.5 s and 0.5 GB, on one core.
#pragma once

#include <cstdint>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/scene/scene_file.hpp"

namespace farfield {

struct CityOptions {                 // paper 000, App. A: the generator's parameters
  double max_height = 120.0;         // maximum height of the city, metres
  double block_length = 110.0;       // block extent along X, metres (curb included)
  double block_width = 110.0;        // block extent along Z, metres (curb included)
  uint32_t rows = 5;                 // maximum rows of lots per block
  uint32_t columns = 5;              // maximum columns of lots per block
  uint32_t blocks_x = 8;             // number of blocks along X
  uint32_t blocks_z = 8;             // number of blocks along Z
  double street_width = 16.0;        // metres
  double street_height = 0.2;        // thickness of the street slab, metres (top at this height)
  double curb_width = 3.0;           // metres
  double curb_height = 0.15;         // curb top above the street top, metres
  double tree_distance = 12.0;       // distance between trees along a lined block, metres
  double park_block_fraction = 0.1;  // chance that a block is a park block
  double tree_block_fraction = 0.6;  // chance that a block is lined with trees
  uint64_t seed = 1;
  // 0: use blocks_x x blocks_z. Otherwise the grid grows (square, keeping block sizes and
  // detail, ignoring blocks_x and blocks_z) from 1 x 1 until the city has at least this many
  // triangles; at most 1e9.
  uint64_t target_triangles = 0;
  // Procedural textures (city_textures.hpp) on building walls and roofs (not glass), streets
  // and sidewalks; the geometry is the same as without.
  bool textures = false;
};

// Checks the options; the message names the option and the problem.
Result<void> validate_city_options(const CityOptions& options);

// Generates the city into a new scene: sizes it block by block ("size city"), then writes it
// ("generate city", progress per block). Fails on bad options, or when the city would not fit
// the 2^32 vertices and indices of a scene.
// Held whole in memory: refused when it would not fit.
Result<Scene> generate_city(const CityOptions& options, Progress& progress);

// The same city written to a .ffscene file a block at a time, byte for byte the file
// write_scene(generate_city(...)) writes, in bounded memory (the objects' table and a block):
// cities larger than memory. Refused when the disk cannot hold it.
Result<SceneFileInfo> write_city(const CityOptions& options, const std::string& path,
                                 Progress& progress);

}  // namespace farfield
