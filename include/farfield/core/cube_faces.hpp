// The six faces of an axis-aligned box in the one order every technique uses (colour-cube
// faces, far-field box sides, textured cluster boxes): named by the side a viewer stands on,
// 0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z. Face 0 is what a viewer at +X, looking towards -X, sees;
// for a box around a viewpoint, face 0 is the side it sees looking towards +X.
#pragma once

#include <glm/vec3.hpp>

namespace farfield {

inline constexpr int kCubeFaces = 6;

inline constexpr int face_axis(int face) {
  return face / 2;
}
inline constexpr int face_sign(int face) {
  return face % 2 == 0 ? 1 : -1;
}
// The outward normal of the face.
inline constexpr glm::vec3 face_normal(int face) {
  glm::vec3 n(0.0f);
  n[face_axis(face)] = float(face_sign(face));
  return n;
}
// Whether the face is a side (not the top or bottom) for +Y up.
inline constexpr bool vertical_face(int face) {
  return face_axis(face) != 1;
}

}  // namespace farfield
