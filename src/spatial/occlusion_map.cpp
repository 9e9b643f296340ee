#include "farfield/spatial/occlusion_map.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>

namespace farfield {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// A texel corner counts as inside a face only by this margin (texels), and a box as hidden
// only where it lies this much (relative) behind the mark: float rounding stays conservative.
constexpr float kEdgeMargin = 1e-3f, kDepthMargin = 1e-4f;

// The lines of a convex polygon's edges (a, b, c: a x + b y + c), oriented so that inside is
// positive whatever its winding, normalised to texel units.
void edge_lines(const glm::vec2* poly, int count, glm::vec3* edges) {
  double area = 0;
  for (int k = 0; k < count; ++k) {
    const glm::vec2 &a = poly[k], &b = poly[(k + 1) % count];
    area += double(a.x) * b.y - double(b.x) * a.y;
  }
  const float orientation = area > 0 ? 1.0f : -1.0f;
  for (int k = 0; k < count; ++k) {
    const glm::vec2 &a = poly[k], &b = poly[(k + 1) % count];
    glm::vec2 normal(-(b.y - a.y), b.x - a.x);
    const float l = glm::length(normal);
    if (!(l > 0.0f)) {
      edges[k] = glm::vec3(0.0f, 0.0f, 1.0f);  // a repeated point: no constraint
      continue;
    }
    normal *= orientation / l;
    edges[k] = glm::vec3(normal, -glm::dot(normal, a));
  }
}

// Whether (x, y) lies inside every edge line by the margin.
bool inside_edges(const glm::vec3* edges, int count, float x, float y) {
  for (int k = 0; k < count; ++k)
    if (!(edges[k].x * x + edges[k].y * y + edges[k].z >= kEdgeMargin)) return false;
  return true;
}

}  // namespace

void OcclusionMap::reset(const View& view, int texel_px) {
  texel_px = std::max(texel_px, 1);
  view_matrix_ = view.view_matrix();
  eye_ = view.pose.position;
  const glm::mat4 projection = view.projection_matrix();
  near_ = view.near_m;
  texels_x_ = float(view.width) / float(texel_px);
  texels_y_ = float(view.height) / float(texel_px);
  width_ = (view.width + texel_px - 1) / texel_px;
  height_ = (view.height + texel_px - 1) / texel_px;
  // Symmetric perspective: ndc.x = P00 x / depth, texel x = (ndc.x + 1) / 2 * texels_x_.
  scale_x_ = 0.5f * projection[0][0] * texels_x_;
  scale_y_ = 0.5f * projection[1][1] * texels_y_;
  depth_.assign(size_t(width_) * size_t(height_), kInf);
  occluders_ = 0;
  sampled_ = texel_px == 1;
  levels_ = 0;
}

void OcclusionMap::add_box(const Bounds3& box) {
  if (box.empty() || depth_.empty()) return;
  ++occluders_;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const float plane = side ? box.max[axis] : box.min[axis];
      // Faces towards the eye only: the eye beyond the face's plane.
      if (side ? eye_[axis] <= plane : eye_[axis] >= plane) continue;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      glm::vec3 corners[4];
      const float us[4] = {box.min[u], box.max[u], box.max[u], box.min[u]};
      const float vs[4] = {box.min[v], box.min[v], box.max[v], box.max[v]};
      for (int k = 0; k < 4; ++k) {
        glm::vec3 p;
        p[axis] = plane;
        p[u] = us[k];
        p[v] = vs[k];
        corners[k] = glm::vec3(view_matrix_ * glm::vec4(p, 1.0f));
      }
      fill_polygon(corners, 4);
    }
  }
}

void OcclusionMap::add_mesh(const Scene& scene, uint32_t object, bool both_sides) {
  if (depth_.empty()) return;
  ++occluders_;
  const Object& o = scene.objects[object];
  // Each vertex to view space and, in front of the near plane, to texels, once.
  view_points_.resize(o.vertex_count);
  texel_points_.resize(o.vertex_count);
  for (uint32_t v = 0; v < o.vertex_count; ++v) {
    const glm::vec3 p =
        glm::vec3(view_matrix_ * glm::vec4(scene.vertices[o.first_vertex + v].position, 1.0f));
    view_points_[v] = p;
    texel_points_[v] = -p.z >= near_ ? to_texels(p) : glm::vec2(NAN);
  }
  const uint32_t* index = scene.indices.data() + o.first_index;
  for (uint32_t t = 0; t < o.index_count; t += 3) {
    const uint32_t a = index[t] - o.first_vertex, b = index[t + 1] - o.first_vertex,
                   c = index[t + 2] - o.first_vertex;
    const glm::vec3 corners[3] = {view_points_[a], view_points_[b], view_points_[c]};
    // A face the renderer culls (its back, single-sided) hides nothing.
    const glm::vec3 normal = glm::cross(corners[1] - corners[0], corners[2] - corners[0]);
    if (!both_sides && glm::dot(normal, corners[0]) >= 0.0f) continue;
    const glm::vec2 &ta = texel_points_[a], &tb = texel_points_[b], &tc = texel_points_[c];
    if (!std::isnan(ta.x) && !std::isnan(tb.x) && !std::isnan(tc.x)) {
      // Wholly in front of the near plane: no pixel centre within its box, nothing to mark.
      const glm::vec2 lo = glm::min(glm::min(ta, tb), tc), hi = glm::max(glm::max(ta, tb), tc);
      if (std::ceil(lo.x - 0.5f) > std::floor(hi.x - 0.5f) ||
          std::ceil(lo.y - 0.5f) > std::floor(hi.y - 0.5f))
        continue;
    }
    fill_polygon(corners, 3);
  }
}

void OcclusionMap::finish() {
  levels_ = 0;
  if (!sampled_ || depth_.empty()) return;
  // Level k + 1 holds the farthest mark of each 2 x 2 block of level k; texels past the map's
  // edge hold nothing that can be seen, so they do not count. Storage is kept between frames.
  int w = width_, h = height_;
  const float* below = depth_.data();
  while (w > 1 || h > 1) {
    const int nw = (w + 1) / 2, nh = (h + 1) / 2;
    if (pyramid_.size() <= levels_) pyramid_.emplace_back();
    Level& level = pyramid_[levels_++];
    level.width = nw;
    level.height = nh;
    level.depth.resize(size_t(nw) * size_t(nh));
    for (int y = 0; y < nh; ++y) {
      const float* r0 = below + size_t(2 * y) * size_t(w);
      const float* r1 = 2 * y + 1 < h ? r0 + w : r0;
      float* out = &level.depth[size_t(y) * size_t(nw)];
      for (int x = 0; x < nw; ++x) {
        const int x1 = 2 * x + 1 < w ? 2 * x + 1 : 2 * x;
        out[x] = std::max(std::max(r0[2 * x], r0[x1]), std::max(r1[2 * x], r1[x1]));
      }
    }
    below = level.depth.data();
    w = nw;
    h = nh;
  }
}

void OcclusionMap::fill_polygon(const glm::vec3* corners, int corner_count) {
  // The face's plane in view space, n.p = c, with the eye (the origin) on its front side.
  glm::vec3 n = glm::cross(corners[1] - corners[0], corners[2] - corners[0]);
  const float length = glm::length(n);
  if (!(length > 0.0f)) return;
  n /= length;
  float c = glm::dot(n, corners[0]);
  if (c > 0.0f) n = -n, c = -c;
  if (!(c < -1e-6f)) return;  // seen edge-on

  // Clipped to the near plane (depth = -z >= near).
  glm::vec3 clipped[8];
  int count = 0;
  for (int k = 0; k < corner_count; ++k) {
    const glm::vec3 &a = corners[k], &b = corners[(k + 1) % corner_count];
    const float da = -a.z - near_, db = -b.z - near_;
    if (da >= 0.0f) clipped[count++] = a;
    if ((da >= 0.0f) != (db >= 0.0f)) clipped[count++] = a + (b - a) * (da / (da - db));
  }
  if (count < 3) return;
  glm::vec2 poly[8];
  glm::vec2 lo(kInf), hi(-kInf);
  for (int k = 0; k < count; ++k) {
    poly[k] = to_texels(clipped[k]);
    lo = glm::min(lo, poly[k]);
    hi = glm::max(hi, poly[k]);
  }
  if (sampled_) {
    fill_centres(poly, count, n, c, lo, hi);
    return;
  }
  // Texel corners (lattice points) that can be inside, within the map.
  const int i0 = std::max(0, int(std::ceil(lo.x))), i1 = std::min(width_, int(std::floor(hi.x)));
  const int j0 = std::max(0, int(std::ceil(lo.y))), j1 = std::min(height_, int(std::floor(hi.y)));
  if (i1 <= i0 || j1 <= j0) return;

  glm::vec3 edges[8];
  edge_lines(poly, count, edges);
  const auto corner_in = [&](float x, float y) { return inside_edges(edges, count, x, y); };
  const auto covered = [&](int x, int y) {
    const float x0 = float(x), y0 = float(y);
    return corner_in(x0, y0) && corner_in(x0 + 1.0f, y0) && corner_in(x0, y0 + 1.0f) &&
           corner_in(x0 + 1.0f, y0 + 1.0f);
  };
  // The plane's farthest point over a texel is the corner where n . r is largest (depth is
  // c / (n . r), both negative): the same corner of every texel.
  const int far_x = n.x > 0.0f ? 1 : 0, far_y = n.y > 0.0f ? 1 : 0;
  // Texels x in [i0, i1 - 1], y in [j0, j1 - 1] have their corners in the lattice box.
  for (int y = j0; y < j1; ++y) {
    // The span of texels whose four corners lie inside every edge: for each edge the corner
    // nearest to it decides, so the span follows from the edges alone, widened by a texel on
    // each side and narrowed by the exact corner test (the polygon is convex: a row's
    // covered texels are one run).
    float left = float(i0), right = float(i1 - 1);
    for (int k = 0; k < count; ++k) {
      const float ey = float(y) + (edges[k].y > 0.0f ? 0.0f : 1.0f);
      const float rest = kEdgeMargin - edges[k].y * ey - edges[k].z;  // ex * x >= rest
      if (edges[k].x > 0.0f)
        left = std::max(left, rest / edges[k].x);
      else if (edges[k].x < 0.0f)
        right = std::min(right, rest / edges[k].x - 1.0f);
      else if (rest > 0.0f)
        right = -1.0f;
    }
    if (!(left <= right + 2.0f)) continue;  // also NaN
    int from = std::max(i0, int(std::ceil(left)) - 1);
    int to = std::min(i1 - 1, int(std::floor(right)) + 1);
    while (from <= to && !covered(from, y)) ++from;
    while (to >= from && !covered(to, y)) --to;
    if (to < from) continue;
    const float b = (float(y + far_y) - 0.5f * texels_y_) / scale_y_;
    float* row = &depth_[size_t(y) * size_t(width_)];
    for (int x = from; x <= to; ++x) {
      // The view ray through the corner, (a, b, -1) per unit of depth, meets the plane at
      // depth c / (n . r).
      const float a = (float(x + far_x) - 0.5f * texels_x_) / scale_x_;
      const float nr = n.x * a + n.y * b - n.z;
      if (nr < 0.0f) row[x] = std::min(row[x], c / nr);
    }
  }
}

void OcclusionMap::fill_centres(const glm::vec2* poly, int count, const glm::vec3& n, float c,
                                const glm::vec2& lo, const glm::vec2& hi) {
  // Pixel centres (i + 0.5, j + 0.5) inside the polygon by the margin, within the map.
  const int i0 = std::max(0, int(std::ceil(lo.x - 0.5f))),
            i1 = std::min(width_ - 1, int(std::floor(hi.x - 0.5f)));
  const int j0 = std::max(0, int(std::ceil(lo.y - 0.5f))),
            j1 = std::min(height_ - 1, int(std::floor(hi.y - 0.5f)));
  if (i1 < i0 || j1 < j0) return;
  glm::vec3 edges[8];
  edge_lines(poly, count, edges);
  float inverse_x[8];  // per edge 1 / a, once a polygon instead of once a row
  for (int k = 0; k < count; ++k) inverse_x[k] = edges[k].x != 0.0f ? 1.0f / edges[k].x : 0.0f;
  // Row by row, the span of centres inside every edge; 1/depth is affine along it.
  const float da = n.x / scale_x_;  // n.r per pixel along x
  for (int j = j0; j <= j1; ++j) {
    const float y = float(j) + 0.5f, b = (y - 0.5f * texels_y_) / scale_y_;
    float left = float(i0) + 0.5f, right = float(i1) + 0.5f;
    for (int k = 0; k < count; ++k) {
      const float rest = kEdgeMargin - edges[k].y * y - edges[k].z;  // ex * x >= rest
      if (edges[k].x > 0.0f)
        left = std::max(left, rest * inverse_x[k]);
      else if (edges[k].x < 0.0f)
        right = std::min(right, rest * inverse_x[k]);
      else if (rest > 0.0f)
        right = -1.0f;  // a horizontal edge this row lies outside of
    }
    int from = std::max(i0, int(std::ceil(left - 0.5f)));
    int to = std::min(i1, int(std::floor(right - 0.5f)));
    // The span's ends are computed in floats: test them again exactly.
    if (from <= to && !inside_edges(edges, count, float(from) + 0.5f, y)) ++from;
    if (from <= to && !inside_edges(edges, count, float(to) + 0.5f, y)) --to;
    if (to < from) continue;
    float* row = &depth_[size_t(j) * size_t(width_)];
    const float nr0 = n.x * ((float(from) + 0.5f - 0.5f * texels_x_) / scale_x_) + n.y * b - n.z;
    // Without branches, so that the compiler runs it several pixels at a time.
    const int span = to - from + 1;
    float* at = row + from;
    for (int i = 0; i < span; ++i) {
      const float nr = nr0 + da * float(i), depth = c / nr;
      at[i] = std::min(at[i], nr < 0.0f ? depth : kInf);
    }
  }
}

bool OcclusionMap::hidden(const Bounds3& box) const {
  if (box.empty() || depth_.empty()) return false;
  // The corners in view space from one of them and the box's edges along the view matrix's
  // columns (the matrix is affine): one product instead of eight.
  const glm::vec3 origin = glm::vec3(view_matrix_ * glm::vec4(box.min, 1.0f));
  const glm::vec3 size = box.max - box.min;
  const glm::vec3 ex = glm::vec3(view_matrix_[0]) * size.x,
                  ey = glm::vec3(view_matrix_[1]) * size.y,
                  ez = glm::vec3(view_matrix_[2]) * size.z;
  float nearest = kInf;
  glm::vec2 lo(kInf), hi(-kInf);
  for (int k = 0; k < 8; ++k) {
    glm::vec3 p = origin;
    if (k & 1) p += ex;
    if (k & 2) p += ey;
    if (k & 4) p += ez;
    const float depth = -p.z;
    if (!(depth >= near_)) return false;  // crosses the near plane: cannot tell
    nearest = std::min(nearest, depth);
    // to_texels with one division instead of two: a texel's edge moved by a rounding error
    // changes no pixel centre reached (texel_px >= 2 here; texel_px 1 is tested through the
    // pyramid at half-pixel margins).
    const float inverse = 1.0f / depth;
    const glm::vec2 t(0.5f * texels_x_ + scale_x_ * p.x * inverse,
                      0.5f * texels_y_ + scale_y_ * p.y * inverse);
    lo = glm::min(lo, t);
    hi = glm::max(hi, t);
  }
  const float limit = nearest / (1.0f + kDepthMargin);
  if (sampled_) return hidden_centres(lo, hi, limit);
  // Every texel holding a pixel centre the box's projection can reach.
  const int x0 = std::max(0, int(std::floor(lo.x))),
            x1 = std::min(width_ - 1, int(std::floor(hi.x)));
  const int y0 = std::max(0, int(std::floor(lo.y))),
            y1 = std::min(height_ - 1, int(std::floor(hi.y)));
  if (x1 < x0 || y1 < y0) return false;  // off screen: the frustum's to say
  for (int y = y0; y <= y1; ++y) {
    const float* row = &depth_[size_t(y) * size_t(width_)];
    for (int x = x0; x <= x1; ++x)
      if (!(row[x] < limit)) return false;
  }
  return true;
}

bool OcclusionMap::hidden_centres(const glm::vec2& lo, const glm::vec2& hi, float limit) const {
  // The pixels whose centres the projection can reach, at the level of the pyramid where they
  // span at most 4 x 4 texels (each the farthest mark of its block).
  int x0 = std::max(0, int(std::floor(lo.x - 0.5f))),
      x1 = std::min(width_ - 1, int(std::ceil(hi.x - 0.5f)));
  int y0 = std::max(0, int(std::floor(lo.y - 0.5f))),
      y1 = std::min(height_ - 1, int(std::ceil(hi.y - 0.5f)));
  if (x1 < x0 || y1 < y0) return false;
  const std::vector<float>* level = &depth_;
  int w = width_;
  for (size_t l = 0; (x1 - x0 > 3 || y1 - y0 > 3) && l < levels_; ++l) {
    x0 >>= 1, x1 >>= 1, y0 >>= 1, y1 >>= 1;
    level = &pyramid_[l].depth;
    w = pyramid_[l].width;
  }
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      if (!((*level)[size_t(y) * size_t(w) + size_t(x)] < limit)) return false;
  return true;
}

size_t OcclusionMap::marked() const {
  return size_t(std::count_if(depth_.begin(), depth_.end(), [](float d) { return d < kInf; }));
}

}  // namespace farfield
