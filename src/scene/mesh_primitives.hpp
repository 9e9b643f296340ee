// Simple solids appended to the open object of a SceneBuilder: the building blocks of the
// generated city (paper 000, App. A). Private to src/scene.
//
// Conventions: metres, +Y up, counter-clockwise front faces seen from outside. Flat faces get
// their own vertices with the face normal (4 per quad, 3 per triangle); round sides share one
// ring of vertices per height with smooth normals. Every vertex gets the given packed colour.
// A "c" argument is the centre of a round shape in the XZ plane (x, z).
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "farfield/scene/scene.hpp"

namespace farfield::mesh {

// Faces of an axis-aligned box, to leave out the ones that can never be seen.
enum BoxFace : uint32_t {
  kNegX = 1u << 0,
  kPosX = 1u << 1,
  kNegY = 1u << 2,
  kPosY = 1u << 3,
  kNegZ = 1u << 4,
  kPosZ = 1u << 5,
  kSides = kNegX | kPosX | kNegZ | kPosZ,
  kNoBottom = kSides | kPosY,
  kAllFaces = kSides | kPosY | kNegY,
};

// The `sides` corners of the regular polygon of radius r about c, by increasing angle from +X
// towards +Z: the vertex positions of round_side, disk and annulus.
void circle_points(const glm::vec2& c, float r, int sides, std::vector<glm::vec2>& out);

// One flat quad o, o+u, o+u+v, o+v; it faces along cross(u, v). 2 triangles.
void quad(SceneBuilder& b, const glm::vec3& o, const glm::vec3& u, const glm::vec3& v,
          uint32_t color);

// One flat triangle, front face counter-clockwise.
void triangle(SceneBuilder& b, const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
              uint32_t color);

// A quad like `quad` set `inward` into a wall: the pane colour at the back of a hole whose
// four sides (sill, head, jambs) take the wall colour. 10 triangles.
void recessed_quad(SceneBuilder& b, const glm::vec3& o, const glm::vec3& u, const glm::vec3& v,
                   const glm::vec3& inward, uint32_t pane, uint32_t wall);

// Storeys of windows: in each floor a band of wall `sill` high under a row of windows set
// into the wall between piers, one window per `bay` metres of wall or part of it.
struct WindowRows {
  float floor_h;  // metres
  float sill;     // height of the wall band under the windows, metres
  float bay;      // wall length per window, metres
  float glazed;   // share of the wall length that is window, in (0, 1)
  float recess;   // depth of the windows in the wall, metres
  uint32_t wall, pane;
};

// The walls of a vertical prism over `corners` (XZ, by increasing angle from +X towards +Z,
// like circle_points) from y0 up, `floors` storeys of `rows`, flat-shaded per wall.
// Per wall and floor: 4 + 12 * windows triangles.
void window_walls(SceneBuilder& b, std::span<const glm::vec2> corners, float y0, int floors,
                  const WindowRows& rows);

// Axis-aligned box, `faces` a mask of BoxFace. 2 triangles per face.
void box(SceneBuilder& b, const glm::vec3& min, const glm::vec3& max, uint32_t color,
         uint32_t faces = kAllFaces);

// Side of a (truncated) cone about the vertical axis through c: radius r0 at y0, r1 at y1
// (r1 = 0: a cone with a pointed top). Smooth normals, facing out, or in when `inward`.
// 2 * sides triangles (sides for a cone).
void round_side(SceneBuilder& b, const glm::vec2& c, float r0, float y0, float r1, float y1,
                int sides, uint32_t color, bool inward = false);

// Flat disk at height y, facing up or down. sides - 2 triangles.
void disk(SceneBuilder& b, const glm::vec2& c, float r, float y, int sides, uint32_t color,
          bool up);

// Flat ring between r_in and r_out at height y, facing up or down. 2 * sides triangles.
void annulus(SceneBuilder& b, const glm::vec2& c, float r_in, float r_out, float y, int sides,
             uint32_t color, bool up);

// Closed-top cylinder (no bottom): side plus top disk. 3 * sides - 2 triangles.
void cylinder(SceneBuilder& b, const glm::vec2& c, float r, float y0, float y1, int sides,
              uint32_t color);

// Cone standing on a disk: side plus, when `base`, a downward base disk.
void cone(SceneBuilder& b, const glm::vec2& c, float r, float y0, float y1, int sides,
          uint32_t color, bool base);

// Pyramid over the rectangle [min.x, max.x] x [min.y, max.y] (XZ) at height y0, apex at y1.
// 4 triangles (6 with the base).
void pyramid(SceneBuilder& b, const glm::vec2& min, const glm::vec2& max, float y0, float y1,
             uint32_t color, bool base);

// Ellipsoid of radii (rx, ry, rz) about `center`: `slices` around, `stacks` from pole to pole,
// smooth normals. 2 * slices * (stacks - 1) triangles.
void ellipsoid(SceneBuilder& b, const glm::vec3& center, const glm::vec3& radii, int slices,
               int stacks, uint32_t color);

// Vertical prism over a simple polygon in XZ (either winding) from y0 to y1: flat sides and top,
// no bottom. The top is a fan from polygon[fan]; the caller picks a vertex that sees all others.
// 2 * n + n - 2 triangles.
void prism(SceneBuilder& b, std::span<const glm::vec2> polygon, float y0, float y1, uint32_t color,
           size_t fan = 0);

// L-shaped prism in the corner of the rectangle [min, max] (XZ) given by `corner` (bit 0: max
// x side, bit 1: max z side), arms `arm` thick along the two rectangle edges through it.
// 16 triangles.
void l_shape(SceneBuilder& b, const glm::vec2& min, const glm::vec2& max, float arm, int corner,
             float y0, float y1, uint32_t color);

// Side of a truncated cone along an arbitrary axis (a branch): radius r0 at p0, r1 at p1 (both
// > 0). The ring starts in direction `side` (any vector not parallel to the axis), so joined
// segments can line up their rings. Smooth normals facing out, open ends.
// 2 * sides vertices, 2 * sides triangles.
void tube(SceneBuilder& b, const glm::vec3& p0, const glm::vec3& p1, float r0, float r1,
          const glm::vec3& side, int sides, uint32_t color);

}  // namespace farfield::mesh
