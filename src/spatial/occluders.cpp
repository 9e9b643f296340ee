#include "farfield/spatial/occluders.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/core/assert.hpp"

namespace farfield {

namespace {

// Whether a triangle meets a box (separating axes: the box's three, the triangle's normal,
// and the nine cross products of their edges; Akenine-Moller 2001).
bool triangle_meets_box(const glm::vec3& centre, const glm::vec3& half, glm::vec3 a, glm::vec3 b,
                        glm::vec3 c) {
  a -= centre, b -= centre, c -= centre;
  for (int k = 0; k < 3; ++k) {
    if (std::min({a[k], b[k], c[k]}) > half[k] || std::max({a[k], b[k], c[k]}) < -half[k])
      return false;
  }
  const glm::vec3 e[3] = {b - a, c - b, a - c};
  auto separated = [&](const glm::vec3& axis) {
    const float pa = glm::dot(a, axis), pb = glm::dot(b, axis), pc = glm::dot(c, axis);
    const float r =
        half.x * std::abs(axis.x) + half.y * std::abs(axis.y) + half.z * std::abs(axis.z);
    return std::min({pa, pb, pc}) > r || std::max({pa, pb, pc}) < -r;
  };
  if (separated(glm::cross(e[0], e[1]))) return false;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      glm::vec3 unit(0.0f);
      unit[k] = 1.0f;
      if (separated(glm::cross(unit, e[i]))) return false;
    }
  }
  return true;
}

// Whether a ray crosses a triangle ahead of its origin (Moller-Trumbore, either side).
bool ray_crosses(const glm::vec3& origin, const glm::vec3& dir, const glm::vec3& a,
                 const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 e1 = b - a, e2 = c - a, p = glm::cross(dir, e2);
  const float det = glm::dot(e1, p);
  if (std::abs(det) < 1e-12f) return false;
  const float inv = 1.0f / det;
  const glm::vec3 s = origin - a;
  const float u = glm::dot(s, p) * inv;
  if (u < 0.0f || u > 1.0f) return false;
  const glm::vec3 q = glm::cross(s, e1);
  const float v = glm::dot(dir, q) * inv;
  if (v < 0.0f || u + v > 1.0f) return false;
  return glm::dot(e2, q) * inv > 0.0f;
}

}  // namespace

std::optional<Bounds3> inscribed_box(const Scene& scene, uint32_t object) {
  const Object& o = scene.objects[object];
  const Material& m = scene.materials[o.material];
  if (m.transparent() || m.alpha_mode != AlphaMode::opaque || o.index_count == 0)
    return std::nullopt;
  const glm::vec3 size = o.bounds.size();
  if (!(std::min({size.x, size.y, size.z}) > 0.0f)) return std::nullopt;

  struct Candidate {
    float width, height, volume;
  };
  // Shares of the object's width and height, the largest volume first.
  static const std::vector<Candidate> kCandidates = [] {
    constexpr float kWidths[] = {0.97f, 0.92f, 0.85f, 0.75f, 0.6f, 0.45f};
    constexpr float kHeights[] = {0.97f, 0.9f, 0.8f, 0.7f, 0.55f, 0.4f, 0.25f};
    std::vector<Candidate> candidates;
    for (float w : kWidths)
      for (float h : kHeights) candidates.push_back({w, h, w * w * h});
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const Candidate& a, const Candidate& b) { return a.volume > b.volume; });
    return candidates;
  }();

  const uint32_t* idx = &scene.indices[o.first_index];
  const size_t triangles = o.index_count / 3;
  auto corner = [&](size_t t, int k) { return scene.vertices[idx[3 * t + k]].position; };
  // Above the horizon, none on an axis (a ray along a wall's diagonal would cross it twice).
  static const std::array<glm::vec3, 9> kDirections = [] {
    std::array<glm::vec3, 9> d;
    d[0] = glm::normalize(glm::vec3(0.0123f, 1.0f, 0.0371f));
    for (int k = 0; k < 8; ++k) {
      const float a = 0.2113f + float(k) * 0.7854f;
      d[size_t(k) + 1] = glm::normalize(glm::vec3(std::cos(a), 0.0537f, std::sin(a)));
    }
    return d;
  }();

  const glm::vec3 mid = o.bounds.center();
  for (const Candidate& c : kCandidates) {
    const glm::vec3 half(0.5f * c.width * size.x, 0.5f * c.height * size.y,
                         0.5f * c.width * size.z);
    const glm::vec3 centre(mid.x, o.bounds.min.y + 1e-3f * size.y + half.y, mid.z);
    bool clear = true;
    for (size_t t = 0; t < triangles && clear; ++t)
      clear = !triangle_meets_box(centre, half, corner(t, 0), corner(t, 1), corner(t, 2));
    if (!clear) continue;
    bool inside = true;
    for (const glm::vec3& dir : kDirections) {
      int crossings = 0;
      for (size_t t = 0; t < triangles; ++t)
        crossings += ray_crosses(centre, dir, corner(t, 0), corner(t, 1), corner(t, 2));
      if (crossings % 2 == 0) {
        inside = false;
        break;
      }
    }
    if (inside) return Bounds3{centre - half, centre + half};
  }
  return std::nullopt;
}

Occluders::Occluders(const Scene& scene, const OccluderOptions& options,
                     const std::vector<Bounds3>& known_boxes)
    : scene_(scene), options_(options) {
  if (options_.meshes) options_.texel_px = 1;  // mesh occluders are sampled per pixel
  std::vector<Bounds3> bounds(scene.objects.size());
  for (size_t i = 0; i < bounds.size(); ++i) {
    bounds[i] = scene.objects[i].bounds;
    const glm::vec3 s = bounds[i].size();
    largest_object_m_ = std::max(largest_object_m_, std::max({s.x, s.y, s.z}));
  }
  tree_ = build_octree(bounds, OctreeOptions{});
  state_.assign(scene.objects.size(), unknown);
  boxes_.resize(scene.objects.size());
  if (!known_boxes.empty()) {
    FF_ASSERT(known_boxes.size() == boxes_.size(), "%zu known boxes for %zu objects",
              known_boxes.size(), boxes_.size());
    boxes_ = known_boxes;
    for (size_t i = 0; i < boxes_.size(); ++i) {
      state_[i] = boxes_[i].empty() ? none : found;
      found_ += state_[i] == found;
    }
    tried_ = uint32_t(boxes_.size());
  }
  seen_in_.assign(scene.objects.size(), 0);
}

const Bounds3* Occluders::box_of(uint32_t object) {
  if (state_[object] == unknown) {
    ++tried_;
    const std::optional<Bounds3> box = inscribed_box(scene_, object);
    state_[object] = box ? found : none;
    if (box) boxes_[object] = *box, ++found_;
  }
  return state_[object] == found ? &boxes_[object] : nullptr;
}

double Occluders::fill(OcclusionMap& map, const View& view, const Frustum& frustum) {
  const auto start = std::chrono::steady_clock::now();
  rasterise(map, view, frustum);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

void Occluders::rasterise(OcclusionMap& map, const View& view, const Frustum& frustum) {
  map.reset(view, options_.texel_px);
  if (tree_.nodes.empty() || options_.per_frame == 0) return;
  add_nearest(map, view, frustum);
  map.finish();
}

void Occluders::add_nearest(OcclusionMap& map, const View& view, const Frustum& frustum) {
  ++frame_;
  const glm::vec3 eye = view.pose.position;
  // Pixels per metre at unit distance, across the view.
  const float focal = 0.5f * float(view.width) / std::tan(0.5f * glm::radians(view.hfov_deg));
  // Beyond this distance no object's box can reach min_size_px.
  const float reach = largest_object_m_ * focal / std::max(options_.min_size_px, 1e-3f);

  // Nodes nearest first: a max-heap on the negated distance.
  heap_.clear();
  heap_.push_back({-distance_to(tree_.nodes[0].bounds, eye), 0});
  uint32_t added = 0;
  while (!heap_.empty() && added < options_.per_frame) {
    std::pop_heap(heap_.begin(), heap_.end());
    const auto [negative_distance, n] = heap_.back();
    heap_.pop_back();
    if (-negative_distance > reach) break;
    const OctreeNode& node = tree_.nodes[n];
    if (frustum.classify(node.bounds) == Visibility::none) continue;
    if (!node.leaf()) {
      for (uint32_t c = 0; c < node.child_count; ++c) {
        heap_.push_back(
            {-distance_to(tree_.nodes[node.first_child + c].bounds, eye), node.first_child + c});
        std::push_heap(heap_.begin(), heap_.end());
      }
      continue;
    }
    for (uint32_t i = node.items_begin; i < node.items_end && added < options_.per_frame; ++i) {
      const uint32_t o = tree_.items[i];
      if (seen_in_[o] == frame_) continue;
      seen_in_[o] = frame_;
      const Bounds3& bounds = scene_.objects[o].bounds;
      if (frustum.classify(bounds) == Visibility::none) continue;
      const Object& object = scene_.objects[o];
      const Material& material = scene_.materials[object.material];
      if (options_.meshes && !material.transparent() && material.alpha_mode == AlphaMode::opaque &&
          object.triangle_count() <= options_.mesh_triangles) {
        const glm::vec3 s = bounds.size();
        const float d = std::max(distance_to(bounds, eye), view.near_m);
        if (std::max({s.x, s.y, s.z}) * focal / d < options_.min_size_px) continue;
        // Nearest first: one that the nearer occluders hide already adds nothing.
        if (map.hidden(bounds)) continue;
        map.add_mesh(scene_, o, material.double_sided != 0);
        ++added;
        continue;
      }
      if (bounds.contains(eye) || eye.y <= bounds.min.y) continue;
      const Bounds3* box = box_of(o);
      if (!box) continue;
      const glm::vec3 s = box->size();
      const float d = std::max(distance_to(*box, eye), view.near_m);
      if (std::max({s.x, s.y, s.z}) * focal / d < options_.min_size_px) continue;
      // As above: a box the nearer ones hide would mark nothing, and is not counted.
      if (map.hidden(*box)) continue;
      map.add_box(*box);
      ++added;
    }
  }
}

}  // namespace farfield
