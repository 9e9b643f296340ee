// The nearest surface along a ray through a scene's triangles, found through an octree of its
// objects (spatial/octree.hpp): nodes and objects whose boxes the ray misses are skipped, the
// rest tested triangle by triangle (Moller-Trumbore, both sides). For walking (ground under
// the eye, walls ahead of it), the reference of picking, and occluder queries.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "farfield/scene/scene.hpp"
#include "farfield/spatial/octree.hpp"

namespace farfield {

struct RayHit {
  float distance = 0;  // along the unit direction, metres
  uint32_t object = 0;
  uint32_t triangle = 0;  // index / 3 of the triangle hit
};

class RayCaster {
 public:
  // Keeps a reference to `scene`, which must outlive it.
  explicit RayCaster(const Scene& scene);
  // Which sides of a triangle a ray can hit: both (walking: a wall is a wall from behind),
  // or as the renderer draws them (back faces of one-sided opaque materials culled: picking).
  enum class Faces : uint8_t { both, as_drawn };
  // The nearest hit within `max_distance` along `direction` (unit length) from `origin`.
  // Not thread-safe (it marks the objects it tested).
  std::optional<RayHit> cast(const glm::vec3& origin, const glm::vec3& direction,
                             float max_distance, Faces faces = Faces::both) const;

 private:
  const Scene& scene_;
  Octree tree_;
  // Per object, the cast that last tested it: an object listed in several leaves is tested
  // once a cast, without clearing a flag per object every cast.
  mutable std::vector<uint32_t> tested_in_;
  mutable uint32_t cast_ = 0;
};

}  // namespace farfield
