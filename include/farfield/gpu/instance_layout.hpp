// A scene drawn instanced (Scene::instances, gpu::InstanceDrawing::placed): the renderer's
// buffers hold the scene's stored form (scene/instances.hpp), where an instance has no
// geometry of its own, and an instance's draws read its prototype's indices with its
// placement. Techniques name triangles and vertices by their numbers in the scene as held;
// this maps them onto the uploaded ones, with no GL, so that it is tested on its own.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "farfield/scene/scene.hpp"

namespace farfield::gpu {

// A draw's placement (the PLACED shader variants read it per draw command): the rows of its
// 3 x 4 affine matrix and of its normals' matrix (w unused).
struct Placement {
  glm::vec4 rows[3];
  glm::vec4 normal_rows[3];
};
static_assert(sizeof(Placement) == 96);

Placement identity_placement();
// An instance's: positions by its linear part then its offset, normals by the linear part's
// inverse transpose.
Placement placement_of(const Instance& instance);

// What the renderer uploads of a scene drawn instanced: its stored form, the instances'
// objects left without indices so that no chunk plans them.
Scene uploaded_form(const Scene& held);

class InstanceLayout {
 public:
  static constexpr uint32_t kOwn = UINT32_MAX;  // an object drawn as it is, not an instance

  InstanceLayout() = default;  // nothing placed: numbers are uploaded as held
  // `uploaded`: uploaded_form(held).
  InstanceLayout(const Scene& held, const Scene& uploaded);

  bool placed() const { return !index_segments_.empty(); }
  size_t instance_count() const { return instance_materials_.size(); }
  uint32_t instance_material(uint32_t instance) const { return instance_materials_[instance]; }

  // Held indices from `at` (before `end`) that map onto uploaded ones in one run, of one
  // instance or none: `count` of them from uploaded index `uploaded_at`.
  struct Run {
    uint32_t uploaded_at, count;
    uint32_t instance;  // kOwn, or into Scene::instances
  };
  Run index_run(uint32_t at, uint32_t end) const;

  // `held` vertex numbers (whole triangles, such as DrawList::scene_indices) made uploaded
  // ones into `uploaded`, and each triangle's instance (kOwn: none) into `instances`; a
  // triangle's corners must lie in one object (asserted).
  void place_vertices(const std::vector<uint32_t>& held, std::vector<uint32_t>& uploaded,
                      std::vector<uint32_t>& instances) const;

 private:
  // Held numbers [held_first, +count) are uploaded [uploaded_first, +count): runs of objects
  // drawn as they are (consecutive in both numberings) and single instances; sorted.
  struct Segment {
    uint32_t held_first, count, uploaded_first;
    uint32_t instance;
  };
  static const Segment& segment_of(const std::vector<Segment>& segments, uint32_t held);
  std::vector<Segment> index_segments_, vertex_segments_;
  std::vector<uint32_t> instance_materials_;  // per instance, its object's material
};

}  // namespace farfield::gpu
