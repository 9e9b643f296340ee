// Occluders for the occlusion map (spatial/occlusion_map.hpp): per opaque object a box lying
// inside it, found the first time it is wanted, and per frame the boxes of the nearest
// objects in view. No bake: everything comes from the scene's triangles.
//
// A box is taken as inside its object when no triangle of the object meets it and rays from
// its centre in nine directions at or above the horizon each cross the object's surface an
// odd number of times. That is exact for a closed surface and, with directions above the
// horizon only, for one open at its bottom alone (the generators' buildings stand on the
// ground without a floor); for other meshes it is a check, not a proof. Faces are taken as
// oriented outwards (a renderer culling back faces shows nothing of a face seen from behind).
// A box is used only while the eye is outside its object's bounds and above its bottom,
// where every line of sight to the box crosses the object's surface first. With
// OccluderOptions::meshes the objects' own triangles are the occluders instead (no inside to
// prove: what the renderer draws hides what lies behind it).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "farfield/core/bounds.hpp"
#include "farfield/core/frustum.hpp"
#include "farfield/core/view.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/spatial/occlusion_map.hpp"
#include "farfield/spatial/octree.hpp"

namespace farfield {

// The largest of a few boxes standing on the object's bottom, centred on its footprint
// (widths and heights as shares of its bounds, largest volume first) that lies inside it;
// none for a transparent or cut-out material, or where no candidate does.
std::optional<Bounds3> inscribed_box(const Scene& scene, uint32_t object);

struct OccluderOptions {
  // Occluders rasterised a frame, the nearest objects' first; one that those already in the map
  // hide wholly adds nothing and is skipped, not counted (128 against the 32 of the previous
  // release: the 100M street at 33 ms gained 0.5 to 1.2 dB, boxes' fill 0.36 against 0.15 ms).
  uint32_t per_frame = 128;
  float min_size_px = 16.0f;  // an occluder whose largest side spans fewer pixels is skipped
  int texel_px = 4;           // the map's texels, in pixels a side
  // The nearest opaque objects' own triangles as occluders (the map then at one pixel a texel,
  // whatever texel_px says, sampled at pixel centres as the renderer does), for techniques that
  // draw objects whole: exact where boxes inside objects cover only part of them. An object of
  // more triangles than mesh_triangles gives its box instead.
  bool meshes = false;
  uint32_t mesh_triangles = 20000;
};

class Occluders {
 public:
  // Keeps a reference to `scene`, which must outlive it. `known_boxes`: per object its box
  // (empty where it has none) found beforehand, as a bake does; none given: each is found in
  // the scene's triangles the first time it is wanted.
  explicit Occluders(const Scene& scene, const OccluderOptions& options = {},
                     const std::vector<Bounds3>& known_boxes = {});
  // Resets `map` to the view and rasterises this frame's occluders into it; the time it took,
  // in milliseconds (bench's occlusion_ms).
  double fill(OcclusionMap& map, const View& view, const Frustum& frustum);
  // Objects whose box has been looked for, and found.
  uint32_t boxes_tried() const { return tried_; }
  uint32_t boxes_found() const { return found_; }

 private:
  void rasterise(OcclusionMap& map, const View& view, const Frustum& frustum);
  void add_nearest(OcclusionMap& map, const View& view, const Frustum& frustum);
  const Bounds3* box_of(uint32_t object);

  const Scene& scene_;
  OccluderOptions options_;
  Octree tree_;
  float largest_object_m_ = 0;  // the largest side of any object's bounds
  enum : uint8_t { unknown = 0, none, found };
  std::vector<uint8_t> state_;
  std::vector<Bounds3> boxes_;
  std::vector<uint32_t> seen_in_;  // per object, the frame that last looked at it
  uint32_t frame_ = 0, tried_ = 0, found_ = 0;
  std::vector<std::pair<float, uint32_t>> heap_;  // node distance (negated), node
};

}  // namespace farfield
