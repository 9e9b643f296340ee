// A coarse map of occluder depth for culling any technique's nodes (issue 14; the approach of
// Intel's Masked Software Occlusion Culling, HPG 2016, simplified: one depth per texel).
// Occluders are boxes that lie inside opaque objects (spatial/occluders.hpp), rasterised on
// the CPU into texels of `texel_px` x `texel_px` pixels; a box is hidden when every texel its
// projection reaches holds an occluder nearer than the box's nearest point.
//
// Conservative by construction: a texel is marked only where an occluder face covers it
// wholly (all four corners inside the face's projection), with the face's farthest view depth
// over the texel (1/depth is affine over a plane's projection, so that is at a corner); a
// box with a corner behind the near plane is never hidden. What the map hides cannot change
// the image, as long as the occluder boxes lie inside what the renderer draws.
//
// At one pixel a texel (texel_px 1) the map samples as the renderer does, at pixel centres: a
// pixel is marked with an occluder face's depth at its centre where the centre lies inside
// the face, so faces that share an edge leave no seam; the renderer's depth there can only be
// nearer. Occluders may then be the very triangles the renderer draws (add_mesh), and boxes
// are tested through a pyramid of the farthest marks of 2 x 2 blocks (finish()).
#pragma once

#include <cstdint>
#include <glm/mat4x4.hpp>
#include <vector>

#include "farfield/core/bounds.hpp"
#include "farfield/core/view.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

class OcclusionMap {
 public:
  // Sizes the map to the view (ceil(width / texel_px) texels across) and clears it.
  void reset(const View& view, int texel_px = 4);
  // Marks the texels that the faces of `box` towards the eye cover wholly.
  void add_box(const Bounds3& box);
  // Marks the pixel centres an object's own triangles cover (their fronts only, unless
  // `both_sides`): only at texel_px 1, and only for an object the renderer draws opaque.
  void add_mesh(const Scene& scene, uint32_t object, bool both_sides);
  // After the last occluder: at texel_px 1, builds the pyramid hidden() reads.
  void finish();
  // Whether an occluder lies in front of every point of `box` that reaches the screen.
  bool hidden(const Bounds3& box) const;

  int width() const { return width_; }
  int height() const { return height_; }
  // The marked view depth of a texel (row 0 at the bottom), INFINITY where none is.
  float depth_at(int x, int y) const { return depth_[size_t(y) * size_t(width_) + size_t(x)]; }
  size_t marked() const;
  uint32_t occluders() const { return occluders_; }

 private:
  // Texel coordinates of a view-space point in front of the near plane.
  glm::vec2 to_texels(const glm::vec3& p) const {
    const float depth = -p.z;
    return {0.5f * texels_x_ + scale_x_ * p.x / depth, 0.5f * texels_y_ + scale_y_ * p.y / depth};
  }
  // A convex polygon of up to four corners in view space, in order.
  void fill_polygon(const glm::vec3* corners, int count);
  // At texel_px 1: the pixel centres inside the projected polygon `poly` of the plane n.p = c.
  void fill_centres(const glm::vec2* poly, int count, const glm::vec3& n, float c,
                    const glm::vec2& lo, const glm::vec2& hi);
  bool hidden_centres(const glm::vec2& lo, const glm::vec2& hi, float limit) const;

  glm::mat4 view_matrix_{1.0f};
  glm::vec3 eye_{0.0f};
  float scale_x_ = 1, scale_y_ = 1;  // texel units per unit of x/depth, y/depth
  float near_ = 0.1f;
  int width_ = 0, height_ = 0;
  float texels_x_ = 0, texels_y_ = 0;    // the screen's extent in texels (fractional)
  std::vector<float> depth_;             // row 0 at the bottom, as GL's window coordinates
  std::vector<glm::vec3> view_points_;   // scratch: an occluder mesh's vertices in view space
  std::vector<glm::vec2> texel_points_;  // and in texels (NaN behind the near plane)
  uint32_t occluders_ = 0;
  bool sampled_ = false;  // texel_px 1: marks at pixel centres
  struct Level {
    int width, height;
    std::vector<float> depth;
  };
  std::vector<Level> pyramid_;  // levels 1, 2, ... above depth_ (finish()), kept for reuse
  size_t levels_ = 0;           // the levels of this frame's pyramid
};

}  // namespace farfield
