// Colour-cubes (paper 002, Sec. 3.3.2): a cube with one RGB value and one coverage value per
// face, standing for the appearance of an octree cell's contents seen orthographically through
// that face. Faces in the order of core/cube_faces.hpp (0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z).
#pragma once

#include <array>
#include <span>

#include <glm/vec3.hpp>

#include "farfield/core/cube_faces.hpp"

namespace farfield {

struct FaceColor {
  glm::vec3 rgb{0.0f};    // linear, lit (as the renderer would draw it)
  float coverage = 0.0f;  // 0: the face is transparent; 1: fully covered
};

struct ColorCube {
  std::array<FaceColor, 6> faces{};
};

// paper 002, Sec. 4.1: the "modified over" of a front face over a back face. It assumes the
// two coverages overlap as little as possible, so two half-covered faces make a covered one
// and large opaque surfaces stay opaque at coarser levels (plain over would give 0.75).
FaceColor composite(const FaceColor& front, const FaceColor& back);

// Coverage-weighted average of the colours; the coverage is the mean coverage.
FaceColor average(std::span<const FaceColor> faces);

// A parent cube from its eight children, child index bit 0 = upper X half, bit 1 = upper Y,
// bit 2 = upper Z (paper 002, Fig. 5): per face, the children are composited pairwise along
// the face's axis, front over back, then the four results averaged. An empty child is a cube
// with zero coverage.
ColorCube combine(const std::array<ColorCube, 8>& children);

}  // namespace farfield
