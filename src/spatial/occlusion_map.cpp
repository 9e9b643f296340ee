#include "farfield/spatial/occlusion_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace farfield {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// A texel corner counts as inside a face only by this margin (texels), and a box as hidden
// only where it lies this much (relative) behind the mark: float rounding stays conservative.
constexpr float kEdgeMargin = 1e-3f, kDepthMargin = 1e-4f;

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
}

glm::vec2 OcclusionMap::to_texels(const glm::vec3& p) const {
  const float depth = -p.z;
  return {0.5f * texels_x_ + scale_x_ * p.x / depth, 0.5f * texels_y_ + scale_y_ * p.y / depth};
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
      fill_face(corners);
    }
  }
}

void OcclusionMap::fill_face(const glm::vec3* corners) {
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
  for (int k = 0; k < 4; ++k) {
    const glm::vec3 &a = corners[k], &b = corners[(k + 1) % 4];
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
  // Texel corners (lattice points) that can be inside, within the map.
  const int i0 = std::max(0, int(std::ceil(lo.x))), i1 = std::min(width_, int(std::floor(hi.x)));
  const int j0 = std::max(0, int(std::ceil(lo.y))), j1 = std::min(height_, int(std::floor(hi.y)));
  if (i1 <= i0 || j1 <= j0) return;

  // Edge lines, oriented so that inside is positive, normalised to texel units.
  double area = 0;
  for (int k = 0; k < count; ++k) {
    const glm::vec2 &a = poly[k], &b = poly[(k + 1) % count];
    area += double(a.x) * b.y - double(b.x) * a.y;
  }
  const float orientation = area > 0 ? 1.0f : -1.0f;
  glm::vec3 edges[8];
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

  const int cols = i1 - i0 + 1, rows = j1 - j0 + 1;
  corner_depth_.resize(size_t(cols) * size_t(rows));
  for (int j = 0; j < rows; ++j) {
    const float y = float(j0 + j), b = (y - 0.5f * texels_y_) / scale_y_;
    for (int i = 0; i < cols; ++i) {
      const float x = float(i0 + i);
      bool in = true;
      for (int k = 0; k < count && in; ++k)
        in = edges[k].x * x + edges[k].y * y + edges[k].z >= kEdgeMargin;
      float depth = -1.0f;  // outside
      if (in) {
        // The view ray through the point, (a, b, -1) per unit of depth, meets the plane at
        // depth c / (n . r).
        const float a = (x - 0.5f * texels_x_) / scale_x_;
        const float nr = n.x * a + n.y * b - n.z;
        depth = nr < 0.0f ? c / nr : -1.0f;
      }
      corner_depth_[size_t(j) * size_t(cols) + size_t(i)] = depth;
    }
  }
  for (int j = 0; j + 1 < rows; ++j) {
    const int y = j0 + j;
    if (y >= height_) break;
    const float* below = &corner_depth_[size_t(j) * size_t(cols)];
    const float* above = below + cols;
    for (int i = 0; i + 1 < cols; ++i) {
      const int x = i0 + i;
      if (x >= width_) break;
      const float d0 = below[i], d1 = below[i + 1], d2 = above[i], d3 = above[i + 1];
      if (d0 < 0.0f || d1 < 0.0f || d2 < 0.0f || d3 < 0.0f) continue;
      float& mark = depth_[size_t(y) * size_t(width_) + size_t(x)];
      mark = std::min(mark, std::max(std::max(d0, d1), std::max(d2, d3)));
    }
  }
}

bool OcclusionMap::hidden(const Bounds3& box) const {
  if (box.empty() || depth_.empty()) return false;
  float nearest = kInf;
  glm::vec2 lo(kInf), hi(-kInf);
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 corner((k & 1) ? box.max.x : box.min.x, (k & 2) ? box.max.y : box.min.y,
                           (k & 4) ? box.max.z : box.min.z);
    const glm::vec3 p = glm::vec3(view_matrix_ * glm::vec4(corner, 1.0f));
    const float depth = -p.z;
    if (!(depth >= near_)) return false;  // crosses the near plane: cannot tell
    nearest = std::min(nearest, depth);
    const glm::vec2 t = to_texels(p);
    lo = glm::min(lo, t);
    hi = glm::max(hi, t);
  }
  // Every texel holding a pixel centre the box's projection can reach.
  const int x0 = std::max(0, int(std::floor(lo.x))),
            x1 = std::min(width_ - 1, int(std::floor(hi.x)));
  const int y0 = std::max(0, int(std::floor(lo.y))),
            y1 = std::min(height_ - 1, int(std::floor(hi.y)));
  if (x1 < x0 || y1 < y0) return false;  // off screen: the frustum's to say
  const float limit = nearest / (1.0f + kDepthMargin);
  for (int y = y0; y <= y1; ++y) {
    const float* row = &depth_[size_t(y) * size_t(width_)];
    for (int x = x0; x <= x1; ++x)
      if (!(row[x] < limit)) return false;
  }
  return true;
}

size_t OcclusionMap::marked() const {
  return size_t(std::count_if(depth_.begin(), depth_.end(), [](float d) { return d < kInf; }));
}

}  // namespace farfield
