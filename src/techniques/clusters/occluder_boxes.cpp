#include "farfield/techniques/clusters/occluder_boxes.hpp"

#include <cmath>

#include "farfield/core/parallel.hpp"
#include "farfield/spatial/occluders.hpp"
#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

namespace {

constexpr const char* kOccluderBoxes = "clusters/occluder_boxes";

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

std::vector<Bounds3> find_occluder_boxes(const Scene& scene, int threads, Progress& progress) {
  std::vector<Bounds3> boxes(scene.objects.size());
  parallel_for(boxes.size(), threads, progress, "find occluder boxes", [&](size_t i) {
    if (auto box = inscribed_box(scene, uint32_t(i))) boxes[i] = *box;
  });
  return boxes;
}

Result<void> save_occluder_boxes(const std::vector<Bounds3>& boxes, Store& store) {
  return store.put(kOccluderBoxes, bytes_of(boxes));
}

Result<std::vector<Bounds3>> load_occluder_boxes(const Store& store, const Scene& scene) {
  auto boxes = read_array<Bounds3>(store, kOccluderBoxes);
  if (!boxes) return boxes.error();
  auto refused = [&](const char* why) {
    return make_error(store.path(), ": blob '", kOccluderBoxes, "' ", why);
  };
  if (boxes->size() != scene.objects.size()) return refused("is not one box per object");
  for (size_t i = 0; i < boxes->size(); ++i) {
    const Bounds3& b = (*boxes)[i];
    if (b.empty()) continue;
    Bounds3 around = scene.objects[i].bounds;
    const glm::vec3 slack = around.size() * 1e-3f + glm::vec3(1e-4f);
    if (!finite(b.min) || !finite(b.max) || glm::any(glm::lessThan(b.min, around.min - slack)) ||
        glm::any(glm::greaterThan(b.max, around.max + slack)))
      return refused("holds a box outside its object");
  }
  return boxes;
}

}  // namespace farfield
