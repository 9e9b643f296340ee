#include "farfield/scene/simplify.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace farfield {

namespace {

// Bounds of the distance between two surfaces are settled to this share of their extent (a
// triangle whose bound is below it is not refined further).
constexpr float kResolution = 5e-3f;

// The closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
glm::vec3 closest_on_triangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                              const glm::vec3& c) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const float denominator = va + vb + vc;
  if (!(std::abs(denominator) > 0)) return a;  // degenerate: any corner
  const float v = vb / denominator, w = vc / denominator;
  return a + ab * v + ac * w;
}

// Triangles bucketed in a uniform grid (each in every cell its box overlaps), searched in
// rings of cells around a point until no nearer triangle can remain.
class TriangleGrid {
 public:
  TriangleGrid(const MeshPart& mesh, const Bounds3& region) : mesh_(mesh) {
    const glm::vec3 size = glm::max(region.size(), glm::vec3(1e-6f));
    const double triangles = double(std::max<uint64_t>(1, mesh.triangle_count()));
    const float longest = std::max({size.x, size.y, size.z});
    // About one triangle a cell, at most 128 cells a side (flat meshes: thin grids).
    cell_ =
        std::max(longest / 128.0f, float(std::cbrt(double(size.x) * size.y * size.z / triangles)));
    cell_ = std::max(cell_, longest * 1e-4f);
    origin_ = region.min;
    for (int a = 0; a < 3; ++a) dims_[a] = std::max(1, int(std::ceil(size[a] / cell_)));
    first_.assign(size_t(dims_[0]) * dims_[1] * dims_[2] + 1, 0);
    // Two passes: count, then fill.
    for (int pass = 0; pass < 2; ++pass) {
      for (uint32_t t = 0; t < mesh.triangle_count(); ++t) {
        glm::ivec3 lo, hi;
        triangle_cells(t, lo, hi);
        for (int z = lo.z; z <= hi.z; ++z)
          for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) {
              const size_t c = cell_index(x, y, z);
              if (pass == 0)
                ++first_[c + 1];
              else
                items_[fill_[c]++] = t;
            }
      }
      if (pass == 0) {
        for (size_t c = 1; c < first_.size(); ++c) first_[c] += first_[c - 1];
        items_.resize(first_.back());
        fill_.assign(first_.begin(), first_.end() - 1);
      }
    }
    stamp_.assign(mesh.triangle_count(), 0);
  }

  struct Nearest {
    float distance;
    uint32_t triangle;
  };
  // The nearest triangle to p and its distance.
  Nearest nearest(const glm::vec3& p) {
    ++query_;
    const glm::ivec3 home = cell_of(p);
    Nearest best{std::numeric_limits<float>::infinity(), 0};
    const int rings = std::max({dims_[0], dims_[1], dims_[2]});
    auto visit = [&](int x, int y, int z) {
      if (x < 0 || y < 0 || z < 0 || x >= dims_[0] || y >= dims_[1] || z >= dims_[2]) return;
      const size_t c = cell_index(x, y, z);
      for (uint32_t k = first_[c]; k < first_[c + 1]; ++k) {
        const uint32_t t = items_[k];
        if (stamp_[t] == query_) continue;
        stamp_[t] = query_;
        const float d = distance_to(p, t);
        if (d < best.distance) best = {d, t};
      }
    };
    for (int r = 0; r <= rings; ++r) {
      // The shell of cells at Chebyshev distance r: two faces of z, then rings of y and x.
      for (int z = home.z - r; z <= home.z + r; ++z) {
        const bool cap = z == home.z - r || z == home.z + r;
        for (int y = home.y - r; y <= home.y + r; ++y) {
          if (cap || y == home.y - r || y == home.y + r) {
            for (int x = home.x - r; x <= home.x + r; ++x) visit(x, y, z);
          } else {
            visit(home.x - r, y, z);
            if (r > 0) visit(home.x + r, y, z);
          }
        }
      }
      // Triangles of later rings lie at least r cells away.
      if (best.distance <= float(r) * cell_) break;
    }
    return best;
  }
  float distance(const glm::vec3& p) { return nearest(p).distance; }
  float distance_to(const glm::vec3& p, uint32_t t) const {
    return glm::distance(p, closest_on_triangle(p, corner(t, 0), corner(t, 1), corner(t, 2)));
  }

 private:
  const glm::vec3& corner(uint32_t t, int k) const {
    return mesh_.vertices[mesh_.indices[size_t(t) * 3 + size_t(k)]].position;
  }
  glm::ivec3 cell_of(const glm::vec3& p) const {
    glm::ivec3 c(glm::floor((p - origin_) / cell_));
    return glm::clamp(c, glm::ivec3(0), glm::ivec3(dims_[0] - 1, dims_[1] - 1, dims_[2] - 1));
  }
  void triangle_cells(uint32_t t, glm::ivec3& lo, glm::ivec3& hi) const {
    const glm::vec3 a = corner(t, 0), b = corner(t, 1), c = corner(t, 2);
    lo = cell_of(glm::min(a, glm::min(b, c)));
    hi = cell_of(glm::max(a, glm::max(b, c)));
  }
  size_t cell_index(int x, int y, int z) const {
    return size_t(x) + size_t(dims_[0]) * (size_t(y) + size_t(dims_[1]) * size_t(z));
  }

  const MeshPart& mesh_;
  glm::vec3 origin_{0.0f};
  float cell_ = 1.0f;
  int dims_[3] = {1, 1, 1};
  std::vector<uint32_t> first_, fill_, items_, stamp_;
  uint32_t query_ = 0;
};

// An upper bound of the distance from every point of `from`'s triangles to the surface of
// `grid`, from distances at the points of a barycentric grid of level k on each triangle
// (sub-triangles of edge L/k). On a sub-triangle the distance is at most
//  - its corners' largest plus L / (k sqrt 3): distance to a surface is 1-Lipschitz and every
//    point lies within that of a corner;
//  - its corners' largest distance to any one triangle of the surface (the nearest of one of
//    its corners): distance to a triangle, a convex set, is convex, so its largest on a
//    triangle is at a corner. This settles sub-triangles that lie on a facet at once.
// Triangles start at level 2 and are refined, to at most level 16, while their bound exceeds
// both the largest distance sampled so far and `resolution`.
float distance_bound(const MeshPart& from, TriangleGrid& grid, float resolution) {
  struct Sample {
    float distance;
    uint32_t triangle;
  };
  std::vector<Sample> samples;
  float sampled = 0.0f;  // a lower bound of the answer
  auto bound_at_level = [&](uint32_t t, int k) {
    const glm::vec3 a = from.vertices[from.indices[3 * size_t(t)]].position,
                    b = from.vertices[from.indices[3 * size_t(t) + 1]].position,
                    c = from.vertices[from.indices[3 * size_t(t) + 2]].position;
    auto point = [&](int i, int j) {
      return a + (b - a) * (float(i) / float(k)) + (c - a) * (float(j) / float(k));
    };
    auto at = [&](int i, int j) -> Sample& { return samples[size_t(i * (k + 1) + j)]; };
    samples.assign(size_t((k + 1) * (k + 1)), {0.0f, 0});
    for (int i = 0; i <= k; ++i)
      for (int j = 0; i + j <= k; ++j) {
        const TriangleGrid::Nearest n = grid.nearest(point(i, j));
        at(i, j) = {n.distance, n.triangle};
        sampled = std::max(sampled, n.distance);
      }
    const float longest = std::max({glm::distance(a, b), glm::distance(b, c), glm::distance(c, a)});
    const float radius = longest / (float(k) * std::sqrt(3.0f));
    float bound = 0.0f;
    auto sub_triangle = [&](int i0, int j0, int i1, int j1, int i2, int j2) {
      const Sample* s[3] = {&at(i0, j0), &at(i1, j1), &at(i2, j2)};
      float b = std::max({s[0]->distance, s[1]->distance, s[2]->distance}) + radius;
      if (b <= sampled) return;  // cannot raise the answer
      const glm::vec3 p[3] = {point(i0, j0), point(i1, j1), point(i2, j2)};
      for (const Sample* candidate : s) {
        float convex = 0.0f;
        for (const glm::vec3& q : p)
          convex = std::max(convex, grid.distance_to(q, candidate->triangle));
        b = std::min(b, convex);
      }
      bound = std::max(bound, b);
    };
    for (int i = 0; i < k; ++i)
      for (int j = 0; i + j < k; ++j) {
        sub_triangle(i, j, i + 1, j, i, j + 1);
        if (i + j + 2 <= k) sub_triangle(i + 1, j, i + 1, j + 1, i, j + 1);
      }
    return bound;
  };
  std::vector<std::pair<uint32_t, float>> pending;  // triangle, bound
  for (uint32_t t = 0; t < from.triangle_count(); ++t) pending.push_back({t, bound_at_level(t, 2)});
  float result = 0.0f;
  for (int k = 4; !pending.empty(); k *= 2) {
    std::vector<std::pair<uint32_t, float>> next;
    for (const auto& [t, bound] : pending) {
      if (bound <= std::max(sampled, resolution)) {
        result = std::max(result, bound);
        continue;
      }
      if (k > 16) {
        result = std::max(result, bound);
        continue;
      }
      next.push_back({t, bound_at_level(t, k)});
    }
    pending.swap(next);
  }
  return std::max(result, sampled);
}

Bounds3 bounds_of(const MeshPart& part) {
  Bounds3 bounds;
  for (const Vertex& v : part.vertices) bounds.expand(v.position);
  return bounds;
}

}  // namespace

MeshPart gather_part(const Scene& scene, std::span<const uint32_t> objects, uint32_t material) {
  MeshPart part;
  part.material = material;
  const bool textured = scene.materials[material].textured();
  for (uint32_t i : objects) {
    const Object& o = scene.objects[i];
    if (o.material != material) continue;
    const uint32_t base = uint32_t(part.vertices.size());
    part.vertices.insert(part.vertices.end(), scene.vertices.begin() + o.first_vertex,
                         scene.vertices.begin() + o.first_vertex + o.vertex_count);
    if (textured)
      part.uvs.insert(part.uvs.end(), scene.uvs.begin() + o.first_uv,
                      scene.uvs.begin() + o.first_uv + o.vertex_count);
    for (uint32_t k = 0; k < o.index_count; ++k)
      part.indices.push_back(scene.indices[o.first_index + k] - o.first_vertex + base);
  }
  return part;
}

float surface_distance(const MeshPart& from, const MeshPart& to) {
  if (from.indices.empty()) return 0.0f;
  if (to.indices.empty()) return std::numeric_limits<float>::infinity();
  Bounds3 region = bounds_of(from);
  region.expand(bounds_of(to));
  TriangleGrid grid(to, region);
  return distance_bound(from, grid, kResolution * glm::length(region.size()));
}

float farthest_distance(const std::vector<glm::vec3>& points, const MeshPart& mesh) {
  if (points.empty()) return 0.0f;
  if (mesh.indices.empty()) return std::numeric_limits<float>::infinity();
  Bounds3 region;
  for (const Vertex& v : mesh.vertices) region.expand(v.position);
  for (const glm::vec3& p : points) region.expand(p);
  TriangleGrid grid(mesh, region);
  float farthest = 0.0f;
  for (const glm::vec3& p : points) farthest = std::max(farthest, grid.distance(p));
  return farthest;
}

SimplifiedPart simplify_part(const MeshPart& part, const SimplifyOptions& options) {
  SimplifiedPart out;
  out.mesh.material = part.material;
  const size_t vertex_count = part.vertices.size(), index_count = part.indices.size();
  if (index_count == 0) return out;
  const float* positions = &part.vertices[0].position.x;
  // Welded by position: the simplifier sees one vertex where faces meet at a hard edge.
  std::vector<uint32_t> welded(index_count);
  meshopt_generateShadowIndexBuffer(welded.data(), part.indices.data(), index_count, positions,
                                    vertex_count, sizeof(glm::vec3), sizeof(Vertex));
  const float scale = meshopt_simplifyScale(positions, vertex_count, sizeof(Vertex));
  const size_t target = std::clamp<size_t>(
      size_t(std::llround(options.target_ratio * double(index_count) / 3.0)) * 3, 3, index_count);
  const float relative_limit = std::isfinite(options.max_error_m) && scale > 0
                                   ? options.max_error_m / scale
                                   : std::numeric_limits<float>::max();
  std::vector<uint32_t> simplified(index_count);
  float relative_error = 0.0f;
  size_t count =
      meshopt_simplify(simplified.data(), welded.data(), index_count, positions, vertex_count,
                       sizeof(Vertex), target, relative_limit, 0, &relative_error);
  if (options.allow_sloppy && count > target + target / 4) {
    std::vector<uint32_t> sloppy(index_count);
    float sloppy_error = 0.0f;
    const size_t sloppy_count =
        meshopt_simplifySloppy(sloppy.data(), welded.data(), index_count, positions, vertex_count,
                               sizeof(Vertex), target, relative_limit, &sloppy_error);
    if (sloppy_count > 0 && sloppy_count < count) {
      simplified.swap(sloppy);
      count = sloppy_count;
      relative_error = sloppy_error;
      out.sloppy = true;
    }
  }
  simplified.resize(count);

  // Each welded corner takes the attributes of the original vertex at its position whose
  // normal is closest to its new face's: hard edges stay hard, smooth surfaces stay smooth.
  std::vector<uint32_t> welded_of(vertex_count, UINT32_MAX);
  for (size_t i = 0; i < index_count; ++i) welded_of[part.indices[i]] = welded[i];
  std::vector<uint32_t> first(vertex_count + 1, 0), members;
  for (uint32_t v = 0; v < vertex_count; ++v)
    if (welded_of[v] != UINT32_MAX) ++first[welded_of[v] + 1];
  for (size_t k = 1; k < first.size(); ++k) first[k] += first[k - 1];
  members.resize(first.back());
  {
    std::vector<uint32_t> fill(first.begin(), first.end() - 1);
    for (uint32_t v = 0; v < vertex_count; ++v)
      if (welded_of[v] != UINT32_MAX) members[fill[welded_of[v]]++] = v;
  }
  std::vector<glm::vec3> normals(vertex_count);
  for (uint32_t v = 0; v < vertex_count; ++v) normals[v] = unpack_normal(part.vertices[v].normal);
  std::vector<uint32_t> new_index(vertex_count, UINT32_MAX);
  for (size_t t = 0; t + 2 < simplified.size(); t += 3) {
    const glm::vec3 a = part.vertices[simplified[t]].position,
                    b = part.vertices[simplified[t + 1]].position,
                    c = part.vertices[simplified[t + 2]].position;
    const glm::vec3 cross = glm::cross(b - a, c - a);
    const float length = glm::length(cross);
    if (!(length > 0)) continue;  // collapsed to a line
    const glm::vec3 face = cross / length;
    for (int k = 0; k < 3; ++k) {
      const uint32_t w = simplified[t + size_t(k)];
      uint32_t chosen = w;
      float best = -2.0f;
      for (uint32_t m = first[w]; m < first[w + 1]; ++m) {
        const float d = glm::dot(normals[members[m]], face);
        if (d > best) {
          best = d;
          chosen = members[m];
        }
      }
      if (best < 0.5f) {  // no normal there fits the new face (clustered parts): a flat one
        Vertex flat = part.vertices[chosen];
        flat.normal = pack_normal(face);
        out.mesh.indices.push_back(uint32_t(out.mesh.vertices.size()));
        out.mesh.vertices.push_back(flat);
        if (!part.uvs.empty()) out.mesh.uvs.push_back(part.uvs[chosen]);
        continue;
      }
      if (new_index[chosen] == UINT32_MAX) {
        new_index[chosen] = uint32_t(out.mesh.vertices.size());
        out.mesh.vertices.push_back(part.vertices[chosen]);
        if (!part.uvs.empty()) out.mesh.uvs.push_back(part.uvs[chosen]);
      }
      out.mesh.indices.push_back(new_index[chosen]);
    }
  }
  // The error in metres, raised to a bound of the distance between the two surfaces both
  // ways (meshoptimizer's is an estimate from its quadrics). Nothing left: the part's size.
  out.error_m = relative_error * scale;
  if (!out.mesh.indices.empty())
    out.error_m =
        std::max({out.error_m, surface_distance(out.mesh, part), surface_distance(part, out.mesh)});
  else
    out.error_m = glm::length(bounds_of(part).size());
  return out;
}

}  // namespace farfield
