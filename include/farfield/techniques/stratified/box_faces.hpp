// The sides of a viewcell's bounding box as image planes (paper 000, Sec. 3.1.3): the far
// field is rendered from the viewcell's centre through each side, a 90 x 90 degree
// perspective whose image plane is the side itself, so a side's image maps linearly onto it.
//
// Faces in the order of core/cube_faces.hpp: +X, -X, +Y (top), -Y (bottom), +Z, -Z. Pixel
// (x, y) of a face's R x R image (rows from the top) has texture coordinates
// u = (x + 0.5) / R, v = (y + 0.5) / R, and sits at
// centre + h (normal + (2u - 1) right + (1 - 2v) up), h = box / 2.
#pragma once

#include <array>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "farfield/core/cube_faces.hpp"

namespace farfield::stratified {

inline constexpr int kFaces = kCubeFaces;

struct FaceFrame {
  glm::vec3 normal, right, up;  // unit, right = normal x up (as the camera sees it)
};
FaceFrame face_frame(int face);

// The face's corners on a box of side `box` around `centre`: the image's top-left, top-right,
// bottom-right and bottom-left (TexturedQuad's order).
std::array<glm::vec3, 4> face_corners(const glm::vec3& centre, float box, int face);

// The view-projection that renders through the face from `centre` (reversed-Z, like View),
// its near plane just inside the face so that nothing outside the box is clipped.
glm::mat4 face_view_projection(const glm::vec3& centre, float box, int face);

// The point of the face at texture coordinates `uv` (u right, v down, both in [0, 1]).
glm::vec3 face_point(const glm::vec3& centre, float box, int face, const glm::vec2& uv);

// Where the ray from `centre` along `direction` (non-zero) leaves the box: the face and the
// texture coordinates there.
struct FaceHit {
  int face;
  glm::vec2 uv;
};
FaceHit project_to_box(const glm::vec3& direction);

}  // namespace farfield::stratified
