#include "farfield/scene/simplify.hpp"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

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

// Triangles in a bounding-volume hierarchy (median splits of their centres along the longest
// axis), searched nearest box first and pruned by the best distance so far: a query costs
// about the logarithm of the triangles however far the point lies from the surface (a grid
// walks every cell within that distance), which matters for coarse levels whose error spans
// many triangles. A hint (the nearest triangle of a neighbouring point) starts the bound.
class TriangleTree {
 public:
  explicit TriangleTree(const MeshPart& mesh) : mesh_(mesh) {
    const uint32_t count = uint32_t(mesh.triangle_count());
    order_.resize(count);
    std::vector<glm::vec3> centres(count);
    for (uint32_t t = 0; t < count; ++t) {
      order_[t] = t;
      centres[t] = (corner(t, 0) + corner(t, 1) + corner(t, 2)) / 3.0f;
    }
    if (count == 0) return;
    nodes_.reserve(2 * size_t(count) / kLeaf + 2);
    nodes_.push_back({});
    struct Pending {
      uint32_t node, begin, end;
    };
    std::vector<Pending> stack{{0, 0, count}};
    while (!stack.empty()) {
      const Pending p = stack.back();
      stack.pop_back();
      Node& node = nodes_[p.node];
      Bounds3 box, centre_box;
      for (uint32_t k = p.begin; k < p.end; ++k) {
        const uint32_t t = order_[k];
        for (int c = 0; c < 3; ++c) box.expand(corner(t, c));
        centre_box.expand(centres[t]);
      }
      node.min = box.min;
      node.max = box.max;
      if (p.end - p.begin <= kLeaf) {
        node.first = p.begin;
        node.count = p.end - p.begin;
        continue;
      }
      const glm::vec3 extent = centre_box.size();
      const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                       : extent.y >= extent.z                       ? 1
                                                                    : 2;
      const uint32_t middle = p.begin + (p.end - p.begin) / 2;
      std::nth_element(order_.begin() + p.begin, order_.begin() + middle, order_.begin() + p.end,
                       [&](uint32_t l, uint32_t r) { return centres[l][axis] < centres[r][axis]; });
      const uint32_t left = uint32_t(nodes_.size());
      node.first = left;  // children at left and left + 1; `node` is invalid past here
      nodes_.push_back({});
      nodes_.push_back({});
      stack.push_back({left, p.begin, middle});
      stack.push_back({left + 1, middle, p.end});
    }
  }

  struct Nearest {
    float distance;
    uint32_t triangle;
  };
  // The nearest triangle to p and its distance; `hint`, a triangle likely near, bounds the
  // search from the start.
  Nearest nearest(const glm::vec3& p, uint32_t hint = 0) const {
    Nearest best{std::numeric_limits<float>::infinity(), 0};
    if (nodes_.empty()) return best;
    if (hint < order_.size()) best = {distance_to(p, hint), hint};
    float best2 = best.distance * best.distance;
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (box_distance2(node, p) >= best2) continue;
      if (node.count > 0) {
        for (uint32_t k = node.first; k < node.first + node.count; ++k) {
          const uint32_t t = order_[k];
          const glm::vec3 d = p - closest_on_triangle(p, corner(t, 0), corner(t, 1), corner(t, 2));
          const float d2 = glm::dot(d, d);
          if (d2 < best2) {
            best2 = d2;
            best.triangle = t;
          }
        }
        continue;
      }
      // The nearer child last, so that it is searched first.
      const float left = box_distance2(nodes_[node.first], p),
                  right = box_distance2(nodes_[node.first + 1], p);
      if (top + 2 > 64) continue;  // depth past 62 cannot occur for 2^32 triangles
      if (left < right) {
        stack[top++] = node.first + 1;
        stack[top++] = node.first;
      } else {
        stack[top++] = node.first;
        stack[top++] = node.first + 1;
      }
    }
    best.distance = std::sqrt(best2);
    return best;
  }
  float distance(const glm::vec3& p) const { return nearest(p).distance; }
  float distance_to(const glm::vec3& p, uint32_t t) const {
    return glm::distance(p, closest_on_triangle(p, corner(t, 0), corner(t, 1), corner(t, 2)));
  }

 private:
  static constexpr uint32_t kLeaf = 4;
  struct Node {
    glm::vec3 min{0.0f}, max{0.0f};
    uint32_t first = 0;  // leaves: into order_; inner nodes: the first of two children
    uint32_t count = 0;  // triangles of a leaf; 0 for inner nodes
  };
  static float box_distance2(const Node& node, const glm::vec3& p) {
    const glm::vec3 d = glm::max(glm::max(node.min - p, p - node.max), glm::vec3(0.0f));
    return glm::dot(d, d);
  }
  const glm::vec3& corner(uint32_t t, int k) const {
    return mesh_.vertices[mesh_.indices[size_t(t) * 3 + size_t(k)]].position;
  }

  const MeshPart& mesh_;
  std::vector<Node> nodes_;
  std::vector<uint32_t> order_;
};

// An upper bound of the distance from every point of `from`'s triangles to the surface of
// `tree`, from distances at the points of a barycentric grid of level k on each triangle
// (sub-triangles of edge L/k). On a sub-triangle the distance is at most
//  - its corners' largest plus L / (k sqrt 3): distance to a surface is 1-Lipschitz and every
//    point lies within that of a corner;
//  - its corners' largest distance to any one triangle of the surface (the nearest of one of
//    its corners): distance to a triangle, a convex set, is convex, so its largest on a
//    triangle is at a corner. This settles sub-triangles that lie on a facet at once.
// Triangles start at level 1 (their corners, measured once per position however many
// triangles share it: most triangles of a detailed mesh settle there); where their bound
// exceeds both the largest distance sampled so far and `resolution` they are split
// adaptively, down to the sub-triangles of level 16.
float distance_bound(const MeshPart& from, const TriangleTree& tree, float resolution) {
  struct Sample {
    float distance;
    uint32_t triangle;
  };
  float sampled = 0.0f;  // a lower bound of the answer
  // A bound of one triangle (or sub-triangle) from its corners p and their samples s.
  auto settle = [&](const glm::vec3* p, const Sample* const* s, float radius) {
    float b = std::max({s[0]->distance, s[1]->distance, s[2]->distance}) + radius;
    if (b <= sampled) return b;  // cannot raise the answer
    for (int c = 0; c < 3 && b > sampled; ++c) {
      if (c > 0 &&
          (s[c]->triangle == s[0]->triangle || (c == 2 && s[2]->triangle == s[1]->triangle)))
        continue;  // the same triangle gives the same bound
      float convex = 0.0f;
      for (int q = 0; q < 3 && convex < b; ++q)
        convex = std::max(convex, tree.distance_to(p[q], s[c]->triangle));
      b = std::min(b, convex);
    }
    return b;
  };
  auto corner = [&](uint32_t t, int k) -> const glm::vec3& {
    return from.vertices[from.indices[3 * size_t(t) + size_t(k)]].position;
  };
  auto longest_edge = [&](uint32_t t) {
    const glm::vec3 &a = corner(t, 0), &b = corner(t, 1), &c = corner(t, 2);
    return std::max({glm::distance(a, b), glm::distance(b, c), glm::distance(c, a)});
  };

  // Level 1: the corners, one query per distinct position.
  std::vector<uint32_t> shadow(from.indices.size());
  meshopt_generateShadowIndexBuffer(shadow.data(), from.indices.data(), from.indices.size(),
                                    &from.vertices[0].position.x, from.vertices.size(),
                                    sizeof(glm::vec3), sizeof(Vertex));
  std::vector<Sample> at_vertex(from.vertices.size(), {-1.0f, 0});
  uint32_t hint = 0;
  for (uint32_t v : shadow) {
    if (at_vertex[v].distance >= 0.0f) continue;
    const TriangleTree::Nearest n = tree.nearest(from.vertices[v].position, hint);
    hint = n.triangle;
    at_vertex[v] = {n.distance, n.triangle};
    sampled = std::max(sampled, n.distance);
  }
  std::vector<std::pair<uint32_t, float>> pending;  // triangle, bound
  pending.reserve(from.triangle_count());
  for (uint32_t t = 0; t < from.triangle_count(); ++t) {
    const glm::vec3 p[3] = {corner(t, 0), corner(t, 1), corner(t, 2)};
    const Sample* s[3] = {&at_vertex[shadow[3 * size_t(t)]], &at_vertex[shadow[3 * size_t(t) + 1]],
                          &at_vertex[shadow[3 * size_t(t) + 2]]};
    pending.push_back({t, settle(p, s, longest_edge(t) / std::sqrt(3.0f))});
  }

  // Unsettled triangles, the loosest first (refining it raises `sampled` soonest), split in
  // four at their edge midpoints where their bound is still too loose, at most four times
  // (sub-triangles of an edge 1/16 of the triangle's).
  std::sort(pending.begin(), pending.end(),
            [](const auto& l, const auto& r) { return l.second > r.second; });
  struct Piece {
    glm::vec3 p[3];
    Sample s[3];
    int depth;
  };
  std::vector<Piece> stack;
  float result = 0.0f;
  for (const auto& [t, bound] : pending) {
    if (bound <= std::max(sampled, resolution)) {
      result = std::max(result, bound);
      continue;
    }
    Piece whole{{corner(t, 0), corner(t, 1), corner(t, 2)}, {}, 0};
    for (int c = 0; c < 3; ++c) whole.s[c] = at_vertex[shadow[3 * size_t(t) + size_t(c)]];
    stack.push_back(whole);
    while (!stack.empty()) {
      const Piece piece = stack.back();
      stack.pop_back();
      const glm::vec3 m[3] = {(piece.p[0] + piece.p[1]) * 0.5f, (piece.p[1] + piece.p[2]) * 0.5f,
                              (piece.p[2] + piece.p[0]) * 0.5f};
      Sample ms[3];
      for (int c = 0; c < 3; ++c) {
        const TriangleTree::Nearest n = tree.nearest(m[c], piece.s[c].triangle);
        ms[c] = {n.distance, n.triangle};
        sampled = std::max(sampled, n.distance);
      }
      const Piece children[4] = {{{piece.p[0], m[0], m[2]}, {piece.s[0], ms[0], ms[2]}, 0},
                                 {{m[0], piece.p[1], m[1]}, {ms[0], piece.s[1], ms[1]}, 0},
                                 {{m[2], m[1], piece.p[2]}, {ms[2], ms[1], piece.s[2]}, 0},
                                 {{m[0], m[1], m[2]}, {ms[0], ms[1], ms[2]}, 0}};
      for (Piece child : children) {
        child.depth = piece.depth + 1;
        const float longest =
            std::max({glm::distance(child.p[0], child.p[1]), glm::distance(child.p[1], child.p[2]),
                      glm::distance(child.p[2], child.p[0])});
        const Sample* cs[3] = {&child.s[0], &child.s[1], &child.s[2]};
        const float b = settle(child.p, cs, longest / std::sqrt(3.0f));
        if (b <= std::max(sampled, resolution) || child.depth >= 4)
          result = std::max(result, b);
        else
          stack.push_back(child);
      }
    }
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

namespace {

float surface_distance(const MeshPart& from, const MeshPart& to, const TriangleTree& to_tree) {
  if (from.indices.empty()) return 0.0f;
  if (to.indices.empty()) return std::numeric_limits<float>::infinity();
  Bounds3 region = bounds_of(from);
  region.expand(bounds_of(to));
  return distance_bound(from, to_tree, kResolution * glm::length(region.size()));
}

}  // namespace

float surface_distance(const MeshPart& from, const MeshPart& to) {
  const TriangleTree to_tree(to);
  return surface_distance(from, to, to_tree);
}

namespace {

// Each triangle of `mesh` the mean colour of `from`'s surface beneath it: a simplified
// triangle spans what were several (a street and a lawn, windows and their wall), and its
// corners' colours interpolated across it smear them into one another (meshoptimizer 0.18
// simplifies by position alone). The mean is what a flat colour's squared error is least
// with. It is sampled at points spread evenly over the triangle, one per sub-triangle of a
// split into k^2 that brings them to about `from`'s mean triangle size (at most
// kMostColourSplits^2 points); each point takes the colour of the nearest of `from`'s
// triangles (its corners averaged). One point, the centre, where k is 1; past that each point
// lies at a random place in its sub-triangle, so that a regular pattern (rows of windows) is
// not sampled in step with itself.
constexpr int kMostColourSplits = 8;

void take_colours_from(const MeshPart& from, const TriangleTree& tree, MeshPart& mesh) {
  if (mesh.indices.empty() || from.indices.empty()) return;
  auto area_of = [](const MeshPart& m, size_t t) {
    const glm::vec3 a = m.vertices[m.indices[t]].position;
    return 0.5 * double(glm::length(glm::cross(m.vertices[m.indices[t + 1]].position - a,
                                               m.vertices[m.indices[t + 2]].position - a)));
  };
  double from_area = 0;
  for (size_t t = 0; t + 2 < from.indices.size(); t += 3) from_area += area_of(from, t);
  const double mean_area = from_area / double(from.indices.size() / 3);
  MeshPart out;
  out.material = mesh.material;
  std::unordered_map<uint64_t, uint32_t> made;  // (vertex, colour) -> its copy
  uint32_t hint = 0;
  uint64_t sum[4];
  uint32_t samples = 0;
  auto sample = [&](const glm::vec3& p) {
    hint = tree.nearest(p, hint).triangle;
    for (int k = 0; k < 3; ++k) {
      const uint32_t c = from.vertices[from.indices[size_t(hint) * 3 + size_t(k)]].color;
      for (int ch = 0; ch < 4; ++ch) sum[ch] += (c >> (8 * ch)) & 0xffu;
    }
    samples += 3;
  };
  uint32_t random = 0x9e3779b9u;  // a fixed sequence: bakes repeat
  auto uniform = [&] {
    random ^= random << 13, random ^= random >> 17, random ^= random << 5;
    return float(random >> 8) * (1.0f / 16777216.0f);
  };
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const glm::vec3 a = mesh.vertices[mesh.indices[t]].position,
                    b = mesh.vertices[mesh.indices[t + 1]].position,
                    c = mesh.vertices[mesh.indices[t + 2]].position;
    const double area = area_of(mesh, t);
    const int k = mean_area > 0 ? std::clamp(int(std::lround(std::sqrt(area / mean_area))), 1,
                                             kMostColourSplits)
                                : 1;
    sum[0] = sum[1] = sum[2] = sum[3] = 0;
    samples = 0;
    if (k == 1) {
      sample((a + b + c) / 3.0f);
    } else {
      // Sub-triangle (i, j) upright: corners at grid points (i, j), (i+1, j), (i, j+1); and,
      // where i + j < k - 1, turned: (i+1, j+1), (i, j+1), (i+1, j). Grid point (i, j) is
      // a + (b - a) i/k + (c - a) j/k.
      const glm::vec3 u = (b - a) / float(k), v = (c - a) / float(k);
      for (int j = 0; j < k; ++j)
        for (int i = 0; i + j < k; ++i) {
          float r = uniform(), s = uniform();
          if (r + s > 1.0f) r = 1.0f - r, s = 1.0f - s;
          sample(a + u * (float(i) + r) + v * (float(j) + s));
          if (i + j < k - 1) {
            r = uniform(), s = uniform();
            if (r + s > 1.0f) r = 1.0f - r, s = 1.0f - s;
            sample(a + u * (float(i + 1) - r) + v * (float(j + 1) - s));
          }
        }
    }
    uint32_t colour = 0;
    for (int ch = 0; ch < 4; ++ch)
      colour |= uint32_t((sum[ch] + samples / 2) / samples) << (8 * ch);
    for (int n = 0; n < 3; ++n) {
      const uint32_t vertex = mesh.indices[t + size_t(n)];
      const auto [at, fresh] =
          made.try_emplace(uint64_t(vertex) << 32 | colour, uint32_t(out.vertices.size()));
      if (fresh) {
        Vertex copy = mesh.vertices[vertex];
        copy.color = colour;
        out.vertices.push_back(copy);
        if (!mesh.uvs.empty()) out.uvs.push_back(mesh.uvs[vertex]);
      }
      out.indices.push_back(at->second);
    }
  }
  mesh = std::move(out);
}

}  // namespace

float farthest_distance(const std::vector<glm::vec3>& points, const MeshPart& mesh) {
  if (points.empty()) return 0.0f;
  if (mesh.indices.empty()) return std::numeric_limits<float>::infinity();
  const TriangleTree tree(mesh);
  float farthest = 0.0f;
  for (const glm::vec3& p : points) farthest = std::max(farthest, tree.distance(p));
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
  const TriangleTree part_tree(part);
  take_colours_from(part, part_tree, out.mesh);
  // The error in metres, raised to a bound of the distance between the two surfaces both
  // ways (meshoptimizer's is an estimate from its quadrics). Nothing left: the part's size.
  out.error_m = relative_error * scale;
  if (!out.mesh.indices.empty())
    out.error_m = std::max({out.error_m, surface_distance(out.mesh, part, part_tree),
                            surface_distance(part, out.mesh)});
  else
    out.error_m = glm::length(bounds_of(part).size());
  return out;
}

}  // namespace farfield
