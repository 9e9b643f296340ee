#include "farfield/scene/cells.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "farfield/core/text.hpp"
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

Result<std::vector<glm::vec3>> portal_polygon_of_mesh(std::span<const glm::vec3> positions,
                                                      std::span<const uint32_t> triangles) {
  glm::dvec3 normal(0.0);
  double area = 0.0;
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const glm::dvec3 a(positions[triangles[t]]), b(positions[triangles[t + 1]]),
        c(positions[triangles[t + 2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    normal += n;
    area += 0.5 * glm::length(n);
  }
  const double length = glm::length(normal);
  if (!(length > 1e-12) || positions.empty()) return make_error("has no area");
  normal /= length;
  // A basis of the plane, and the hull of the points in it (Andrew's monotone chain).
  const glm::dvec3 u = glm::normalize(std::abs(normal.x) < 0.9 ? glm::cross(normal, {1, 0, 0})
                                                               : glm::cross(normal, {0, 1, 0}));
  const glm::dvec3 v = glm::cross(normal, u);
  std::vector<std::pair<glm::dvec2, size_t>> flat;
  for (size_t i = 0; i < positions.size(); ++i)
    flat.push_back(
        {{glm::dot(glm::dvec3(positions[i]), u), glm::dot(glm::dvec3(positions[i]), v)}, i});
  std::sort(flat.begin(), flat.end(), [](const auto& a, const auto& b) {
    return a.first.x < b.first.x || (a.first.x == b.first.x && a.first.y < b.first.y);
  });
  auto turn = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  std::vector<size_t> hull;
  std::vector<glm::dvec2> at;
  for (int pass = 0; pass < 2; ++pass) {
    const size_t start = at.size();
    for (size_t k = 0; k < flat.size(); ++k) {
      const auto& [p, i] = pass == 0 ? flat[k] : flat[flat.size() - 1 - k];
      while (at.size() >= start + 2 && turn(at[at.size() - 2], at.back(), p) <= 1e-12) {
        at.pop_back();
        hull.pop_back();
      }
      at.push_back(p);
      hull.push_back(i);
    }
    at.pop_back();  // each chain's last point starts the other
    hull.pop_back();
  }
  double hull_area = 0.0;
  for (size_t k = 0; k < at.size(); ++k) {
    const glm::dvec2& a = at[k];
    const glm::dvec2& b = at[(k + 1) % at.size()];
    hull_area += 0.5 * (a.x * b.y - a.y * b.x);
  }
  std::vector<glm::vec3> polygon;
  for (size_t i : hull) polygon.push_back(positions[i]);
  if (const std::string problem = portal_polygon_problem(polygon); !problem.empty())
    return make_error(problem);
  // Every vertex on the plane; the triangles fill the hull.
  const auto plane = portal_plane(polygon);
  const float tolerance = std::max(1e-3f, 1e-3f * float(std::sqrt(hull_area)));
  for (const glm::vec3& p : positions)
    if (std::abs(plane->signed_distance(p)) > tolerance)
      return make_error("is not planar: a vertex lies ",
                        number_text(std::abs(plane->signed_distance(p))), " m off its plane");
  if (area < 0.99 * hull_area)
    return make_error("is not convex: its triangles cover ", number_text(100.0 * area / hull_area),
                      "% of their hull");
  return polygon;
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
