#include "farfield/scene/cells.hpp"

#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>

#include "farfield/scene/scene.hpp"

namespace farfield {

float PortalPlane::signed_distance(const glm::vec3& p) const {
  return glm::dot(normal, p) + offset;
}

std::optional<PortalPlane> portal_plane(std::span<const glm::vec3> points) {
  if (points.size() < 3) return std::nullopt;
  // Newell's method: robust for nearly collinear neighbours, exact for planar polygons.
  glm::dvec3 n(0.0), centre(0.0);
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::dvec3 a(points[i]), b(points[(i + 1) % points.size()]);
    n +=
        glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    centre += a;
  }
  const double length = glm::length(n);
  if (!(length > 1e-12)) return std::nullopt;
  n /= length;
  centre /= double(points.size());
  return PortalPlane{glm::vec3(n), float(-glm::dot(n, centre))};
}

std::string portal_polygon_problem(std::span<const glm::vec3> points) {
  char text[160];
  if (points.size() < 3 || points.size() > kMaxPortalPoints) {
    std::snprintf(text, sizeof text, "has %zu points (3 to %u)", points.size(), kMaxPortalPoints);
    return text;
  }
  float extent = 0.0f;
  for (const glm::vec3& p : points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return "has a point that is not finite";
    extent = std::max(extent, glm::length(p - points[0]));
  }
  const auto plane = portal_plane(points);
  if (!plane || extent <= 0.0f) return "has no area";
  // Planar within a thousandth of its size (and 1 mm): a door frame modelled slightly off.
  const float tolerance = std::max(1e-3f, 1e-3f * extent);
  for (size_t i = 0; i < points.size(); ++i) {
    const float d = plane->signed_distance(points[i]);
    if (std::abs(d) > tolerance) {
      std::snprintf(text, sizeof text, "is not planar: point %zu lies %.3g m off its plane", i,
                    double(std::abs(d)));
      return text;
    }
  }
  // Convex: every corner turns the same way as the whole polygon (collinear corners allowed).
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::vec3& a = points[(i + points.size() - 1) % points.size()];
    const glm::vec3& b = points[i];
    const glm::vec3& c = points[(i + 1) % points.size()];
    const float turn = glm::dot(glm::cross(b - a, c - b), plane->normal);
    if (turn < -1e-6f * extent * extent) {
      std::snprintf(text, sizeof text, "is not convex: it turns back at point %zu", i);
      return text;
    }
  }
  return {};
}

std::string validate_cells(const Scene& s) {
  for (size_t i = 0; i < s.cells.size(); ++i) {
    const Cell& c = s.cells[i];
    const std::string at = "cell " + std::to_string(i) + ": ";
    if (uint64_t(c.name_offset) + c.name_size > s.names.size()) return at + "name out of range";
    if (c.bounds.empty()) return at + "empty box";
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(c.bounds.min[a]) || !std::isfinite(c.bounds.max[a]))
        return at + "box not finite";
    if (uint64_t(c.first_object) + c.object_count > s.cell_objects.size())
      return at + "object list out of range";
    for (uint32_t k = 0; k < c.object_count; ++k)
      if (s.cell_objects[c.first_object + k] >= s.objects.size())
        return at + "names object " + std::to_string(s.cell_objects[c.first_object + k]) +
               ", but the scene has " + std::to_string(s.objects.size()) + " objects";
  }
  for (size_t i = 0; i < s.portals.size(); ++i) {
    const Portal& p = s.portals[i];
    const std::string at = "portal " + std::to_string(i) + ": ";
    for (uint32_t cell : p.cells)
      if (cell >= s.cells.size())
        return at + "names cell " + std::to_string(cell) + ", but the scene has " +
               std::to_string(s.cells.size()) + " cells";
    if (p.cells[0] == p.cells[1])
      return at + "joins cell " + std::to_string(p.cells[0]) + " to itself";
    if (uint64_t(p.first_point) + p.point_count > s.portal_points.size())
      return at + "points out of range";
    const std::string problem =
        portal_polygon_problem(std::span(s.portal_points).subspan(p.first_point, p.point_count));
    if (!problem.empty()) return at + problem;
  }
  if (s.cells.empty() && !s.portals.empty()) return "portals without cells";
  return {};
}

std::optional<uint32_t> cell_containing(const Scene& scene, const glm::vec3& eye) {
  std::optional<uint32_t> best;
  float best_volume = INFINITY;
  for (uint32_t i = 0; i < scene.cells.size(); ++i) {
    const Bounds3& b = scene.cells[i].bounds;
    if (!b.contains(eye)) continue;
    const glm::vec3 s = b.size();
    if (const float volume = s.x * s.y * s.z; volume < best_volume) {
      best_volume = volume;
      best = i;
    }
  }
  return best;
}

}  // namespace farfield
