// Average-colour boxes (paper 001, Sec. 4.1.2 and 5.1): per side of a textured box
// (box_set.hpp) the mean colour of what its image shows and the share of the side it covers,
// drawn as the box's front sides shrunk to that share (about the centre of what they show),
// flat, untextured. The coarsest representation: the paper draws it where an object is "less
// than a few pixels" on screen (Sec. 4.2), and a walk from disk draws it where a box's tile has
// not arrived yet, since it needs none (36 bytes a box, always in memory).
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/gpu/draw_list.hpp"
#include "farfield/techniques/clusters/box_set.hpp"

namespace farfield {

class Store;

// A side: colour (the image's, alpha-weighted), the share of the side its image covers (255:
// all), and the centre of what it covers along the side's right and up directions (-127 and
// 127: the side's edges). coverage 0: nothing to draw.
struct AverageSide {
  uint8_t r = 0, g = 0, b = 0, coverage = 0;
  int8_t u = 0, v = 0;
};
struct AverageBox {
  AverageSide sides[6];  // as TexturedBox::sides
};
static_assert(sizeof(AverageBox) == 36);

// From the box's side images in `page` (RGBA8, page_px square, rows from the top).
AverageBox average_box(const TexturedBox& box, std::span<const uint8_t> page, int page_px);
// Every box of `set`, from its pages (held in memory).
std::vector<AverageBox> average_boxes(const BoxSet& set);

// The sides of `average` that face `eye` (those of `box`), as quads of its colours
// (texture coordinates (0.5, 0.5): drawn with a white texture).
void append_average_box(const TexturedBox& box, const AverageBox& average, const glm::vec3& eye,
                        TexturedMesh& out);

// Blob "clusters/box_averages": saved after the boxes (save_box_set erases it with them, so
// that a pack never holds the averages of other boxes). A pack without it: none (empty).
// Refused: not one per box.
Result<void> save_average_boxes(std::span<const AverageBox> averages, Store& store);
Result<std::vector<AverageBox>> load_average_boxes(const Store& store, const BoxSet& set);

}  // namespace farfield
