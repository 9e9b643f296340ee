#include "mesh_primitives.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

#include "farfield/core/assert.hpp"

namespace farfield::mesh {

namespace {

constexpr int kMaxSides = 64;

// Unit directions (cos, sin) of `sides` equal steps around the circle, starting at +X and
// turning towards +Z, plus an optional half step.
struct Circle {
  std::array<glm::vec2, kMaxSides> dir;
  explicit Circle(int sides, bool half_step = false) {
    FF_ASSERT(sides >= 3 && sides <= kMaxSides, "sides %d not in [3, %d]", sides, kMaxSides);
    const double step = 2.0 * std::numbers::pi / sides;
    for (int i = 0; i < sides; ++i) {
      const double a = step * (i + (half_step ? 0.5 : 0.0));
      dir[i] = glm::vec2(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)));
    }
  }
};

glm::vec3 at(const glm::vec2& c, const glm::vec2& dir, float r, float y) {
  return {c.x + r * dir.x, y, c.y + r * dir.y};
}

}  // namespace

void circle_points(const glm::vec2& c, float r, int sides, std::vector<glm::vec2>& out) {
  const Circle circle(sides);
  out.clear();
  for (int i = 0; i < sides; ++i) out.push_back(c + r * circle.dir[i]);
}

void quad(SceneBuilder& b, const glm::vec3& o, const glm::vec3& u, const glm::vec3& v,
          uint32_t color) {
  const glm::vec3 n = glm::normalize(glm::cross(u, v));
  const uint32_t i = b.add_vertex(o, n, color);
  b.add_vertex(o + u, n, color);
  b.add_vertex(o + u + v, n, color);
  b.add_vertex(o + v, n, color);
  b.add_triangle(i, i + 1, i + 2);
  b.add_triangle(i, i + 2, i + 3);
}

void triangle(SceneBuilder& b, const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
              uint32_t color) {
  const glm::vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
  const uint32_t i = b.add_vertex(p0, n, color);
  b.add_vertex(p1, n, color);
  b.add_vertex(p2, n, color);
  b.add_triangle(i, i + 1, i + 2);
}

void recessed_quad(SceneBuilder& b, const glm::vec3& o, const glm::vec3& u, const glm::vec3& v,
                   const glm::vec3& inward, uint32_t pane, uint32_t wall) {
  const glm::vec3 back = o + inward, out = -inward;
  quad(b, back, u, v, pane);
  quad(b, back, out, u, wall);      // sill, facing up
  quad(b, back + v, u, out, wall);  // head, facing down
  quad(b, back, v, out, wall);      // jamb at o, facing along u
  quad(b, back + u, out, v, wall);  // jamb at o + u, facing against u
}

void window_walls(SceneBuilder& b, std::span<const glm::vec2> corners, float y0, int floors,
                  const WindowRows& rows) {
  const glm::vec3 sill_up(0.0f, rows.sill, 0.0f), window_up(0.0f, rows.floor_h - rows.sill, 0.0f);
  const size_t n = corners.size();
  for (size_t i = n; i > 0; --i) {  // clockwise seen from above: cross(edge, up) points out
    const glm::vec2 a = corners[i % n], c = corners[i - 1];
    const glm::vec3 edge(c.x - a.x, 0.0f, c.y - a.y);
    const float length = glm::length(edge);
    const int windows = std::max(1, static_cast<int>(length / rows.bay));
    const float pane = rows.glazed * length / windows;
    const float pier = (length - windows * pane) / (windows + 1);
    const glm::vec3 along = edge / length;
    const glm::vec3 inward = rows.recess * glm::normalize(glm::cross(glm::vec3(0, 1, 0), edge));
    for (int k = 0; k < floors; ++k) {
      const glm::vec3 o(a.x, y0 + k * rows.floor_h, a.y);
      quad(b, o, edge, sill_up, rows.wall);
      glm::vec3 at = o + sill_up;
      for (int w = 0; w < windows; ++w) {
        quad(b, at, along * pier, window_up, rows.wall);
        recessed_quad(b, at + along * pier, along * pane, window_up, inward, rows.pane, rows.wall);
        at += along * (pier + pane);
      }
      quad(b, at, along * pier, window_up, rows.wall);
    }
  }
}

void box(SceneBuilder& b, const glm::vec3& lo, const glm::vec3& hi, uint32_t color,
         uint32_t faces) {
  const glm::vec3 dx(hi.x - lo.x, 0, 0), dy(0, hi.y - lo.y, 0), dz(0, 0, hi.z - lo.z);
  // Each (u, v) pair has cross(u, v) pointing out of the box.
  if (faces & kPosX) quad(b, {hi.x, lo.y, lo.z}, dy, dz, color);
  if (faces & kNegX) quad(b, lo, dz, dy, color);
  if (faces & kPosY) quad(b, {lo.x, hi.y, lo.z}, dz, dx, color);
  if (faces & kNegY) quad(b, lo, dx, dz, color);
  if (faces & kPosZ) quad(b, {lo.x, lo.y, hi.z}, dx, dy, color);
  if (faces & kNegZ) quad(b, lo, dy, dx, color);
}

void round_side(SceneBuilder& b, const glm::vec2& c, float r0, float y0, float r1, float y1,
                int sides, uint32_t color, bool inward) {
  FF_ASSERT(r0 > 0.0f && r1 >= 0.0f && y1 > y0, "r0 %g r1 %g y0 %g y1 %g", r0, r1, y0, y1);
  const Circle circle(sides);
  const float h = y1 - y0, s = inward ? -1.0f : 1.0f;
  auto normal = [&](const glm::vec2& d) {
    return s * glm::normalize(glm::vec3(d.x * h, r0 - r1, d.y * h));
  };
  const uint32_t n = static_cast<uint32_t>(sides);
  const uint32_t bottom = b.vertex_count();
  for (int i = 0; i < sides; ++i)
    b.add_vertex(at(c, circle.dir[i], r0, y0), normal(circle.dir[i]), color);
  if (r1 == 0.0f) {  // a cone: one apex vertex per side, its normal half way round the side
    const Circle mid(sides, true);
    for (int i = 0; i < sides; ++i) b.add_vertex({c.x, y1, c.y}, normal(mid.dir[i]), color);
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t p = bottom + i, q = bottom + n + i, p1 = bottom + (i + 1) % n;
      if (inward)
        b.add_triangle(p, p1, q);
      else
        b.add_triangle(p, q, p1);
    }
    return;
  }
  for (int i = 0; i < sides; ++i)
    b.add_vertex(at(c, circle.dir[i], r1, y1), normal(circle.dir[i]), color);
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    const uint32_t p0 = bottom + i, p1 = bottom + j, q0 = bottom + n + i, q1 = bottom + n + j;
    if (inward) {
      b.add_triangle(p0, p1, q0);
      b.add_triangle(p1, q1, q0);
    } else {
      b.add_triangle(p0, q0, p1);
      b.add_triangle(p1, q0, q1);
    }
  }
}

void disk(SceneBuilder& b, const glm::vec2& c, float r, float y, int sides, uint32_t color,
          bool up) {
  const Circle circle(sides);
  const glm::vec3 n(0.0f, up ? 1.0f : -1.0f, 0.0f);
  const uint32_t first = b.vertex_count();
  for (int i = 0; i < sides; ++i) b.add_vertex(at(c, circle.dir[i], r, y), n, color);
  // Increasing angle faces down; reverse it for an upward disk.
  for (uint32_t i = 1; i + 1 < static_cast<uint32_t>(sides); ++i) {
    if (up)
      b.add_triangle(first, first + i + 1, first + i);
    else
      b.add_triangle(first, first + i, first + i + 1);
  }
}

void annulus(SceneBuilder& b, const glm::vec2& c, float r_in, float r_out, float y, int sides,
             uint32_t color, bool up) {
  FF_ASSERT(r_out > r_in && r_in >= 0.0f, "r_in %g r_out %g", r_in, r_out);
  const Circle circle(sides);
  const glm::vec3 n(0.0f, up ? 1.0f : -1.0f, 0.0f);
  const uint32_t first = b.vertex_count(), count = static_cast<uint32_t>(sides);
  for (int i = 0; i < sides; ++i) b.add_vertex(at(c, circle.dir[i], r_in, y), n, color);
  for (int i = 0; i < sides; ++i) b.add_vertex(at(c, circle.dir[i], r_out, y), n, color);
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t j = (i + 1) % count;
    const uint32_t a0 = first + i, a1 = first + j, o0 = first + count + i, o1 = first + count + j;
    if (up) {
      b.add_triangle(a0, o1, o0);
      b.add_triangle(a0, a1, o1);
    } else {
      b.add_triangle(a0, o0, o1);
      b.add_triangle(a0, o1, a1);
    }
  }
}

void cylinder(SceneBuilder& b, const glm::vec2& c, float r, float y0, float y1, int sides,
              uint32_t color) {
  round_side(b, c, r, y0, r, y1, sides, color);
  disk(b, c, r, y1, sides, color, true);
}

void cone(SceneBuilder& b, const glm::vec2& c, float r, float y0, float y1, int sides,
          uint32_t color, bool base) {
  round_side(b, c, r, y0, 0.0f, y1, sides, color);
  if (base) disk(b, c, r, y0, sides, color, false);
}

void pyramid(SceneBuilder& b, const glm::vec2& lo, const glm::vec2& hi, float y0, float y1,
             uint32_t color, bool base) {
  // Corners by increasing angle about the centre (from +X towards +Z).
  const glm::vec3 p[4] = {{hi.x, y0, lo.y}, {hi.x, y0, hi.y}, {lo.x, y0, hi.y}, {lo.x, y0, lo.y}};
  const glm::vec3 apex(0.5f * (lo.x + hi.x), y1, 0.5f * (lo.y + hi.y));
  for (int i = 0; i < 4; ++i) triangle(b, p[i], apex, p[(i + 1) % 4], color);
  if (base) {
    triangle(b, p[0], p[1], p[2], color);
    triangle(b, p[0], p[2], p[3], color);
  }
}

void ellipsoid(SceneBuilder& b, const glm::vec3& center, const glm::vec3& radii, int slices,
               int stacks, uint32_t color) {
  FF_ASSERT(stacks >= 2, "stacks %d", stacks);
  const Circle circle(slices);
  const glm::vec3 inv2 = 1.0f / (radii * radii);  // an ellipsoid's normal is p / r^2
  const uint32_t n = static_cast<uint32_t>(slices), first = b.vertex_count();
  auto vertex = [&](const glm::vec3& unit) {
    b.add_vertex(center + unit * radii, glm::normalize(unit * radii * inv2), color);
  };
  vertex({0.0f, 1.0f, 0.0f});         // top pole
  for (int k = 1; k < stacks; ++k) {  // rings from the top down
    const double phi = std::numbers::pi * k / stacks;
    const float s = static_cast<float>(std::sin(phi)), y = static_cast<float>(std::cos(phi));
    for (int i = 0; i < slices; ++i) vertex({s * circle.dir[i].x, y, s * circle.dir[i].y});
  }
  vertex({0.0f, -1.0f, 0.0f});  // bottom pole
  const uint32_t top = first, bottom = first + 1 + n * (stacks - 1);
  auto ring = [&](int k, uint32_t i) { return first + 1 + n * (k - 1) + i % n; };
  for (uint32_t i = 0; i < n; ++i) {
    b.add_triangle(ring(1, i), top, ring(1, i + 1));
    for (int k = 1; k + 1 < stacks; ++k) {  // ring k above ring k + 1
      b.add_triangle(ring(k + 1, i), ring(k, i), ring(k + 1, i + 1));
      b.add_triangle(ring(k + 1, i + 1), ring(k, i), ring(k, i + 1));
    }
    b.add_triangle(bottom, ring(stacks - 1, i), ring(stacks - 1, i + 1));
  }
}

void prism(SceneBuilder& b, std::span<const glm::vec2> polygon, float y0, float y1, uint32_t color,
           size_t fan) {
  const size_t n = polygon.size();
  FF_ASSERT(n >= 3 && fan < n && y1 > y0, "n %zu fan %zu y0 %g y1 %g", n, fan, y0, y1);
  double area2 = 0.0;  // > 0: increasing angle (from +X towards +Z), which faces down
  for (size_t i = 0; i < n; ++i) {
    const glm::vec2 &p = polygon[i], &q = polygon[(i + 1) % n];
    area2 += double(p.x) * q.y - double(q.x) * p.y;
  }
  // Walk the polygon by increasing angle whatever its winding.
  auto point = [&](size_t i) { return area2 > 0.0 ? polygon[i % n] : polygon[(n - i % n) % n]; };
  const glm::vec3 up(0.0f, y1 - y0, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    const glm::vec2 p = point(i), q = point(i + 1);
    quad(b, {p.x, y0, p.y}, up, {q.x - p.x, 0.0f, q.y - p.y}, color);
  }
  const uint32_t first = b.vertex_count();
  for (size_t i = 0; i < n; ++i) b.add_vertex({point(i).x, y1, point(i).y}, {0, 1, 0}, color);
  const size_t f = area2 > 0.0 ? fan : (n - fan) % n;
  for (size_t k = 1; k + 1 < n; ++k) {
    b.add_triangle(first + uint32_t(f), first + uint32_t((f + k + 1) % n),
                   first + uint32_t((f + k) % n));
  }
}

void l_shape(SceneBuilder& b, const glm::vec2& lo, const glm::vec2& hi, float arm, int corner,
             float y0, float y1, uint32_t color) {
  // The L for the (lo.x, lo.y) corner, mirrored to the others; vertex 3 is the inner corner,
  // which sees every other vertex.
  const float x0 = lo.x, z0 = lo.y, x1 = hi.x, z1 = hi.y;
  std::array<glm::vec2, 6> p = {glm::vec2{x0, z0},    {x1, z0},       {x1, z0 + arm},
                                {x0 + arm, z0 + arm}, {x0 + arm, z1}, {x0, z1}};
  for (glm::vec2& v : p) {
    if (corner & 1) v.x = x0 + x1 - v.x;
    if (corner & 2) v.y = z0 + z1 - v.y;
  }
  prism(b, p, y0, y1, color, 3);
}

void tube(SceneBuilder& b, const glm::vec3& p0, const glm::vec3& p1, float r0, float r1,
          const glm::vec3& side, int sides, uint32_t color) {
  const glm::vec3 axis = p1 - p0;
  const float length = glm::length(axis);
  FF_ASSERT(r0 > 0.0f && r1 > 0.0f && length > 0.0f, "r0 %g r1 %g length %g", r0, r1, length);
  const glm::vec3 a = axis / length;
  const glm::vec3 e1 = glm::normalize(side - glm::dot(side, a) * a), e2 = glm::cross(a, e1);
  const Circle circle(sides);
  const uint32_t first = b.vertex_count(), n = static_cast<uint32_t>(sides);
  for (int end = 0; end < 2; ++end) {
    const glm::vec3 c = end ? p1 : p0;
    const float r = end ? r1 : r0;
    for (int i = 0; i < sides; ++i) {
      const glm::vec3 d = circle.dir[i].x * e1 + circle.dir[i].y * e2;
      // The normal leans towards the narrow end by the slope of the side.
      b.add_vertex(c + r * d, glm::normalize(d * length + a * (r0 - r1)), color);
    }
  }
  // Going round from e1 to e2 = a x e1 is counter-clockwise seen from outside.
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    b.add_triangle(first + i, first + j, first + n + j);
    b.add_triangle(first + i, first + n + j, first + n + i);
  }
}

}  // namespace farfield::mesh
