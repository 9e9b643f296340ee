// A software occlusion buffer: per pixel, the view depth of the nearest opaque box a frame
// has drawn so far, filled on the CPU as a walk draws front to back, and asked whether a box
// is hidden behind what is there. Paper 002 draws every cube that passes frustum culling; in a
// field of trees seen across the ground most of them lie behind nearer ones.
//
// Exact for the renderer it mirrors (MSAA off, a pixel is filled when its centre is inside a
// triangle, depth test "nearer wins"): a box marks only pixel centres its outline covers by a
// margin, with its farthest depth; a box is hidden only when every pixel centre its
// projection can reach holds a mark nearer than the box's nearest point. A hidden box
// therefore cannot change the image.
#pragma once

#include <span>
#include <vector>

#include <glm/mat4x4.hpp>

#include "farfield/core/bounds.hpp"
#include "farfield/core/view.hpp"

namespace farfield {

class OcclusionBuffer {
 public:
  // Sizes the buffer to the view and clears it.
  void reset(const View& view);
  // Marks the pixels inside the outlines of boxes that lie inside `region` and are drawn
  // opaque (their faces towards the eye are). Near a small region the projection is nearly
  // affine: a box's outline is then a hexagon, three slab tests a pixel, the affine error
  // bound widening the margin. A region too near or too large for that marks nothing.
  void add_boxes(const Bounds3& region, std::span<const Bounds3> boxes);
  bool hidden(const Bounds3& box) const;
  // Pixels holding a mark; the view depth marked at a pixel (row 0 at the bottom), INFINITY
  // where none is.
  size_t marked() const;
  float depth_at(int x, int y) const { return depth_[size_t(y) * size_t(width_) + size_t(x)]; }

 private:
  struct Local;
  struct PixelRange {
    int x0, x1, y0, y1;
  };
  PixelRange centres_within(const glm::vec2& lo, const glm::vec2& hi) const;
  bool linearise(const Bounds3& box, Local& local) const;
  static void outline(const glm::vec3& size, Local& local);
  void mark(int x, int y, float depth);

  glm::mat4 view_projection_{1.0f};
  float near_ = 0.1f;
  int width_ = 0, height_ = 0;
  std::vector<float> depth_;  // row 0 at the bottom, as GL's window coordinates
  int dirty_x0_ = 0, dirty_x1_ = -1, dirty_y0_ = 0, dirty_y1_ = -1;  // the marked rectangle
};

}  // namespace farfield
