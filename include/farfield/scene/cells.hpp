// Cells (rooms) and the portals that join them (paper 004, "Plan to implement portals";
// Luebke and Georges, 1995; docs/portals.md). A scene may hold cells: boxes the eye can
// stand in, each with the objects that can be seen from inside it (a wall between two rooms
// belongs to both), and portals: convex planar polygons (doors, windows, stairwell openings)
// through which two cells see each other. Everything else a cell's occupant sees is hidden
// by the cell's own objects: `portal` rendering draws the eye's cell and recurses through
// the portals in view.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "farfield/core/bounds.hpp"
#include "farfield/core/result.hpp"

namespace farfield {

struct Scene;

struct Cell {
  Bounds3 bounds;  // the eye is in this cell inside this box (the smallest box, where they nest)
  uint32_t first_object = 0;  // into Scene::cell_objects
  uint32_t object_count = 0;
  uint32_t name_offset = 0;  // into Scene::names
  uint32_t name_size = 0;
};
static_assert(sizeof(Cell) == 40);

// The polygon's points wind counter-clockwise seen from cells[0]: its normal (right-hand
// rule) points into cells[0], so an eye in cells[0] sees the portal's front.
struct Portal {
  uint32_t cells[2] = {0, 0};
  uint32_t first_point = 0;  // into Scene::portal_points
  uint32_t point_count = 0;
};
static_assert(sizeof(Portal) == 16);

inline constexpr uint32_t kMaxPortalPoints = 64;

// The plane of a portal's points (Newell's method): unit normal towards cells[0] and offset,
// dot(normal, p) + offset = 0 on the plane. Nullopt for a polygon of no area.
struct PortalPlane {
  glm::vec3 normal;
  float offset;
  float signed_distance(const glm::vec3& p) const;
};
std::optional<PortalPlane> portal_plane(std::span<const glm::vec3> points);

// What is wrong with a polygon as a portal ("not planar: point 3 lies 0.2 m off its plane",
// "not convex at point 2", "of no area"), or an empty string.
std::string portal_polygon_problem(std::span<const glm::vec3> points);

// The portal polygon a mesh stands for (an imported "-portal" node): its vertices' convex hull
// in the plane of its triangles, counter-clockwise about the triangles' summed normal. An
// error where the mesh has no area, is not planar, or does not fill its hull (not convex).
Result<std::vector<glm::vec3>> portal_polygon_of_mesh(std::span<const glm::vec3> positions,
                                                      std::span<const uint32_t> triangles);

// Checks cells and portals against the scene (ranges, names, finite boxes, portal polygons,
// cells joined); returns a message naming the first problem, or an empty string.
std::string validate_cells(const Scene& scene);

// The cell the eye stands in: the smallest box holding `eye`; nullopt outside every cell.
std::optional<uint32_t> cell_containing(const Scene& scene, const glm::vec3& eye);

}  // namespace farfield
