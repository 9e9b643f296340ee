// Pseudo-texture maps (paper 001, Sec. 4.1.2 and 5.1): a textured box whose side images are
// meshes instead of textures, "a triangular mesh onto which a texture map is pasted in such a
// way that each pixel in the image is associated to a pair of triangles", for renderers
// without texture mapping. As the paper, each image is first shrunk ("successively [...] by
// convolving it with a Gaussian filter that averages the RGB components") until it has at
// most max_px texels a side, so that a side costs at most 2 x max_px^2 triangles; a texel
// covered at least half is drawn as a quad of its colour, the others not.
#pragma once

#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "farfield/gpu/draw_list.hpp"
#include "farfield/techniques/clusters/box_set.hpp"

namespace farfield {

struct PseudoMaps {
  int max_px = 0;
  // Per box: where its sides' shrunk images start in `texels`, one side after the other, and
  // each side's width and height (0: an empty side).
  std::vector<uint32_t> first;
  std::vector<std::array<uint8_t, 12>> sizes;
  std::vector<uint32_t> texels;  // RGBA8, R in the low byte; alpha: the share covered
};

// An image (RGBA8, rows from the top) shrunk by halves, each step a [1 2 1] x [1 2 1]
// Gaussian weighted by alpha, until it is at most max_px texels a side.
std::vector<uint32_t> shrink_image(std::vector<uint32_t> texels, int& w, int& h, int max_px);

// The pseudo-texture maps of every box of `set`, from its pages (held in memory).
PseudoMaps pseudo_maps(const BoxSet& set, int max_px);

// Box `b`'s sides that face `eye` as quads of their shrunk images' colours (texture
// coordinates (0.5, 0.5): drawn with a white texture).
void append_pseudo_box(const BoxSet& set, const PseudoMaps& maps, uint32_t b, const glm::vec3& eye,
                       TexturedMesh& out);

}  // namespace farfield
