#include "farfield/techniques/stratified/box_faces.hpp"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "farfield/core/assert.hpp"

namespace farfield::stratified {

namespace {

// Camera up of each face's view; the top and bottom look along Y, so their up is -Z / +Z.
constexpr glm::vec3 kUps[kFaces] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1},
                                    {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};

}  // namespace

FaceFrame face_frame(int face) {
  FF_ASSERT(face >= 0 && face < kFaces, "face %d", face);
  const glm::vec3 n = face_normal(face), up = kUps[face];
  return {n, glm::cross(n, up), up};
}

glm::vec3 face_point(const glm::vec3& centre, float box, int face, const glm::vec2& uv) {
  const FaceFrame f = face_frame(face);
  const float h = 0.5f * box;
  return centre + h * (f.normal + (2.0f * uv.x - 1.0f) * f.right + (1.0f - 2.0f * uv.y) * f.up);
}

std::array<glm::vec3, 4> face_corners(const glm::vec3& centre, float box, int face) {
  return {face_point(centre, box, face, {0, 0}), face_point(centre, box, face, {1, 0}),
          face_point(centre, box, face, {1, 1}), face_point(centre, box, face, {0, 1})};
}

glm::mat4 face_view_projection(const glm::vec3& centre, float box, int face) {
  const FaceFrame f = face_frame(face);
  const glm::mat4 view = glm::lookAt(centre, centre + f.normal, f.up);
  // Reversed-Z infinite perspective as View's, 90 degrees both ways (scale 1). Far objects lie
  // wholly outside the box (those touching it are near), so a near plane a hair inside the
  // face clips none of them.
  glm::mat4 projection(0.0f);
  projection[0][0] = 1.0f;
  projection[1][1] = 1.0f;
  projection[2][3] = -1.0f;
  projection[3][2] = 0.5f * box * 0.999f;
  return projection * view;
}

FaceHit project_to_box(const glm::vec3& direction) {
  const glm::vec3 a = glm::abs(direction);
  int face;
  if (a.x >= a.y && a.x >= a.z)
    face = direction.x > 0 ? 0 : 1;
  else if (a.z >= a.y)
    face = direction.z > 0 ? 4 : 5;
  else
    face = direction.y > 0 ? 2 : 3;
  const FaceFrame f = face_frame(face);
  const glm::vec3 on_plane = direction / glm::dot(direction, f.normal);  // normal component 1
  return {face,
          {0.5f * (glm::dot(on_plane, f.right) + 1.0f), 0.5f * (1.0f - glm::dot(on_plane, f.up))}};
}

}  // namespace farfield::stratified
