// The random city of paper 000, Appendix A: a rectangular grid of blocks separated by streets,
// each block a building block (rows and columns of lots holding parks, buildings, fountains)
// or a park block (one big park with a fountain in the middle), some blocks lined with trees.
//
// Deterministic: the same options give the same scene, byte for byte, on every run; each
// block draws from its own random stream (seed, block row, block column), so growing the grid
// keeps the existing blocks unchanged.
#pragma once

#include <cstdint>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

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
  // detail) until the city has at least this many triangles.
  uint64_t target_triangles = 0;
};

// Checks the options; the message names the option and the problem.
Result<void> validate_city_options(const CityOptions& options);

// Generates the city into a new scene. Reports progress per block.
Result<Scene> generate_city(const CityOptions& options, Progress& progress);

}  // namespace farfield
