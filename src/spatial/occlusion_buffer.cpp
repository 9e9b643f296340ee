#include "farfield/spatial/occlusion_buffer.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace farfield {

namespace {

// Room for the renderer's sub-pixel snapping of vertices (llvmpipe: 1/256 pixel), in pixels.
constexpr float kMargin = 1.0f / 32.0f;

}  // namespace

// The pixels whose centres (x + 0.5, y + 0.5) lie in the screen rectangle [lo, hi], clamped
// to the frame; empty when x0 > x1 or y0 > y1.
OcclusionBuffer::PixelRange OcclusionBuffer::centres_within(const glm::vec2& lo, const glm::vec2& hi) const {
  return {std::max(0, int(std::ceil(lo.x - 0.5f))), std::min(width_ - 1, int(std::floor(hi.x - 0.5f))),
          std::max(0, int(std::ceil(lo.y - 0.5f))), std::min(height_ - 1, int(std::floor(hi.y - 0.5f)))};
}

void OcclusionBuffer::reset(const View& view) {
  view_projection_ = view.view_projection();
  near_ = view.near_m;
  if (width_ != view.width || height_ != view.height) {
    width_ = view.width;
    height_ = view.height;
    depth_.assign(size_t(width_) * size_t(height_), INFINITY);
  } else {  // clear only what the last frame marked
    for (int y = dirty_y0_; y <= dirty_y1_; ++y)
      std::fill_n(depth_.begin() + ptrdiff_t(size_t(y) * size_t(width_) + size_t(dirty_x0_)),
                  dirty_x1_ - dirty_x0_ + 1, INFINITY);
  }
  dirty_x0_ = width_;
  dirty_y0_ = height_;
  dirty_x1_ = dirty_y1_ = -1;
}

void OcclusionBuffer::mark(int x, int y, float depth) {
  float& mark = depth_[size_t(y) * size_t(width_) + size_t(x)];
  mark = std::min(mark, depth);
  dirty_x0_ = std::min(dirty_x0_, x);
  dirty_x1_ = std::max(dirty_x1_, x);
  dirty_y0_ = std::min(dirty_y0_, y);
  dirty_y1_ = std::max(dirty_y1_, y);
}

// The projection near a box, linearised about its centre: the screen position (pixels) of
// centre + d is s0 + (jx . d, jy . d) within `error` pixels, its depth w + row_w . d exactly.
// A box's outline is then the hexagon spanned by its three projected edges e[a]: the points
// within half[a] of s0 along each normal[a] (perpendicular to e[a]).
struct OcclusionBuffer::Local {
  glm::vec2 s0;
  glm::vec3 jx, jy, row_w;
  float w = 0.0f, error = INFINITY;
  glm::vec2 e[3], normal[3], extent{0.0f};
  float half[3]{}, depth_reach = 0.0f;  // |w - depth| within the box
};

bool OcclusionBuffer::linearise(const Bounds3& box, Local& l) const {
  const glm::mat4& m = view_projection_;
  const glm::vec3 row_x(m[0][0], m[1][0], m[2][0]), row_y(m[0][1], m[1][1], m[2][1]);
  l.row_w = {m[0][3], m[1][3], m[2][3]};
  const glm::vec3 centre = box.center(), size = box.size();
  const float reach = 0.5f * glm::length(size);
  const glm::vec4 clip = m * glm::vec4(centre, 1.0f);
  if (clip.w - glm::length(l.row_w) * reach < near_) return false;
  // r bounds the relative change of w over the box. The linearised projection errs by at
  // most r / (1 - r) * (r |ndc(centre)| + |row| reach / w) in NDC (the expansion of
  // (X0 + dX) / (W0 + dW) about the centre).
  const float r = glm::length(l.row_w) * reach / clip.w;
  if (r > 0.05f) return false;
  l.error = r / (1.0f - r) *
            std::max((r * std::abs(clip.x / clip.w) + glm::length(row_x) * reach / clip.w) * 0.5f * float(width_),
                     (r * std::abs(clip.y / clip.w) + glm::length(row_y) * reach / clip.w) * 0.5f * float(height_));
  if (!(l.error < 0.25f)) return false;
  l.w = clip.w;
  l.s0 = {(clip.x / clip.w + 1.0f) * 0.5f * float(width_), (clip.y / clip.w + 1.0f) * 0.5f * float(height_)};
  l.jx = (row_x - (clip.x / clip.w) * l.row_w) * (0.5f * float(width_) / clip.w);
  l.jy = (row_y - (clip.y / clip.w) * l.row_w) * (0.5f * float(height_) / clip.w);
  return true;
}

void OcclusionBuffer::outline(const glm::vec3& size, Local& l) {
  l.extent = glm::vec2(0.0f);
  l.depth_reach = 0.0f;
  for (int a = 0; a < 3; ++a) {
    l.e[a] = {l.jx[a] * size[a], l.jy[a] * size[a]};
    l.normal[a] = {-l.e[a].y, l.e[a].x};
    l.extent += 0.5f * glm::abs(l.e[a]);
    l.depth_reach += 0.5f * std::abs(l.row_w[a] * size[a]);
  }
  for (int a = 0; a < 3; ++a)
    l.half[a] = 0.5f * (std::abs(glm::dot(l.normal[a], l.e[(a + 1) % 3])) +
                        std::abs(glm::dot(l.normal[a], l.e[(a + 2) % 3])));
}

void OcclusionBuffer::add_boxes(const Bounds3& region, std::span<const Bounds3> boxes) {
  Local l;
  if (!linearise(region, l)) return;  // too near or too large: mark nothing
  const glm::vec3 middle = region.center();
  for (const Bounds3& box : boxes) {
    outline(box.size(), l);
    // Only pixel centres inside by the margin, the linearisation's error included.
    float inner[3];
    for (int a = 0; a < 3; ++a) inner[a] = l.half[a] - (kMargin + l.error) * glm::length(l.normal[a]);
    const glm::vec3 d = box.center() - middle;
    const glm::vec2 p(l.s0.x + glm::dot(l.jx, d), l.s0.y + glm::dot(l.jy, d));
    const auto [x0, x1, y0, y1] = centres_within(p - l.extent, p + l.extent);
    if (x0 > x1 || y0 > y1) continue;
    const float depth = l.w + glm::dot(l.row_w, d) + l.depth_reach;  // the box's farthest
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const glm::vec2 q(float(x) + 0.5f - p.x, float(y) + 0.5f - p.y);
        if (std::abs(glm::dot(l.normal[0], q)) <= inner[0] &&
            std::abs(glm::dot(l.normal[1], q)) <= inner[1] &&
            std::abs(glm::dot(l.normal[2], q)) <= inner[2])
          mark(x, y, depth);
      }
  }
}

bool OcclusionBuffer::hidden(const Bounds3& box) const {
  if (box.empty() || depth_.empty()) return false;
  Local l;
  if (linearise(box, l)) {
    // A small box: only the pixel centres its outline may reach (widened by the margin).
    outline(box.size(), l);
    float outer[3];
    for (int a = 0; a < 3; ++a) outer[a] = l.half[a] + (kMargin + l.error) * glm::length(l.normal[a]);
    const float nearest = l.w - l.depth_reach;
    const glm::vec2 widened = l.extent + l.error + kMargin;
    const auto [x0, x1, y0, y1] = centres_within(l.s0 - widened, l.s0 + widened);
    for (int y = y0; y <= y1; ++y) {
      const float* row = depth_.data() + size_t(y) * size_t(width_);
      for (int x = x0; x <= x1; ++x) {
        const glm::vec2 q(float(x) + 0.5f - l.s0.x, float(y) + 0.5f - l.s0.y);
        if (std::abs(glm::dot(l.normal[0], q)) > outer[0] || std::abs(glm::dot(l.normal[1], q)) > outer[1] ||
            std::abs(glm::dot(l.normal[2], q)) > outer[2])
          continue;
        if (!(row[x] < nearest)) return false;
      }
    }
    return true;
  }
  glm::vec2 lo(INFINITY), hi(-INFINITY);
  float nearest = INFINITY;
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 corner(k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y,
                           k & 4 ? box.max.z : box.min.z);
    const glm::vec4 clip = view_projection_ * glm::vec4(corner, 1.0f);
    if (clip.w < near_) return false;  // reaches the eye
    nearest = std::min(nearest, clip.w);
    const glm::vec2 s((clip.x / clip.w + 1.0f) * 0.5f * float(width_),
                      (clip.y / clip.w + 1.0f) * 0.5f * float(height_));
    lo = glm::min(lo, s);
    hi = glm::max(hi, s);
  }
  // Every pixel centre the box's projection may cover (its bounding rectangle, widened by
  // the margin); outside the frame nothing can be seen.
  const auto [x0, x1, y0, y1] = centres_within(lo - kMargin, hi + kMargin);
  for (int y = y0; y <= y1; ++y) {
    const float* row = depth_.data() + size_t(y) * size_t(width_);
    for (int x = x0; x <= x1; ++x)
      if (!(row[x] < nearest)) return false;
  }
  return true;
}

size_t OcclusionBuffer::marked() const {
  return size_t(std::count_if(depth_.begin(), depth_.end(), [](float d) { return d < INFINITY; }));
}

}  // namespace farfield
