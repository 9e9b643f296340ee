// The occluders' boxes (spatial/occluders.hpp: per opaque object a box inside it) found by the
// clusters bake and kept in its pack, so that a walk of a scene left on disk, whose triangles
// the boxes are found in, still culls what the nearest objects hide, and a walk in memory does
// not look for them as it goes.
#pragma once

#include <vector>

#include "farfield/core/bounds.hpp"
#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

class Store;

// Per object its inscribed_box, or an empty box where it has none; on `threads` cores (0: all).
std::vector<Bounds3> find_occluder_boxes(const Scene& scene, int threads, Progress& progress);

// Blob "clusters/occluder_boxes" and back, refused (naming pack and blob) where it is not one
// box per object of `scene`, each empty or inside the object's bounds.
Result<void> save_occluder_boxes(const std::vector<Bounds3>& boxes, Store& store);
Result<std::vector<Bounds3>> load_occluder_boxes(const Store& store, const Scene& scene);

}  // namespace farfield
