#include "farfield/techniques/colorcube/color_cube.hpp"

#include <algorithm>

namespace farfield {

FaceColor composite(const FaceColor& front, const FaceColor& back) {
  // The back shows only where the front leaves room: min(a_back, 1 - a_front).
  const float back_visible = std::min(back.coverage, 1.0f - front.coverage);
  FaceColor out;
  out.coverage = front.coverage + back_visible;
  if (out.coverage > 0.0f)
    out.rgb = (front.rgb * front.coverage + back.rgb * back_visible) / out.coverage;
  return out;
}

FaceColor average(std::span<const FaceColor> faces) {
  FaceColor out;
  if (faces.empty()) return out;
  float weight = 0.0f;
  for (const FaceColor& f : faces) {
    out.rgb += f.rgb * f.coverage;
    weight += f.coverage;
  }
  if (weight > 0.0f) out.rgb /= weight;
  out.coverage = weight / float(faces.size());
  return out;
}

ColorCube combine(const std::array<ColorCube, 8>& children) {
  ColorCube parent;
  for (int face = 0; face < 6; ++face) {
    const int axis = face_axis(face);
    const int axis_bit = 1 << axis;
    // The viewer of a + face stands on the upper side: the upper child is in front.
    const bool upper_in_front = face_sign(face) > 0;
    std::array<FaceColor, 4> columns;
    int n = 0;
    for (int child = 0; child < 8; ++child) {
      if (child & axis_bit) continue;  // visit each column once, from its lower child
      const FaceColor& lower = children[child].faces[face];
      const FaceColor& upper = children[child | axis_bit].faces[face];
      columns[n++] = upper_in_front ? composite(upper, lower) : composite(lower, upper);
    }
    parent.faces[face] = average(columns);
  }
  return parent;
}

}  // namespace farfield
