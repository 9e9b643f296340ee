#include "colorcube_technique.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/core/frustum.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

namespace {

// Adds a proxy range, extending the last one when they touch.
void append(DrawList& out, uint32_t first, uint32_t count) {
  if (count == 0) return;
  if (!out.proxies.empty() && out.proxies.back().first_index + out.proxies.back().index_count == first)
    out.proxies.back().index_count += count;
  else
    out.proxies.push_back({first, count, 0});
}

}  // namespace

Result<ColorcubeOptions> colorcube_options(const std::map<std::string, std::string>& settings) {
  ColorcubeOptions o;
  for (const auto& [key, text] : settings) {
    if (key == "coverage") {
      if (text != "binary" && text != "fraction")
        return make_error("--set colorcube.coverage must be binary or fraction (got '", text, "')");
      o.tree.leaf.coverage = text == "binary" ? CoverageMode::binary : CoverageMode::fraction;
      continue;
    }
    auto v = setting_number("colorcube", key, text);
    if (!v) return v.error();
    if (key == "depth") o.tree.depth = int(*v);
    else if (key == "cluster") o.tree.leaf.cluster = int(*v);
    else if (key == "oversampling") o.tree.leaf.oversampling = int(*v);
    else if (key == "threshold") o.tree.coverage_threshold = float(*v);
    else if (key == "alpha") o.tree.coverage_as_alpha = *v != 0.0;
    else if (key == "pixels") o.pixel_tolerance = float(*v);
    else if (key == "threads") o.tree.threads = int(*v);
    else
      return make_error("--set colorcube.", key, ": unknown setting (known: depth, cluster, "
                        "oversampling, coverage, threshold, alpha, pixels, threads)");
  }
  if (!(o.pixel_tolerance > 0.0f)) return make_error("--set colorcube.pixels must be > 0");
  return o;
}

Result<void> ColorcubeTechnique::load(const Scene& scene) {
  Progress quiet(true);
  auto tree = build_cube_tree(scene, options_.tree, quiet);
  if (!tree) return make_error("colorcube: ", tree.error().message);
  tree_ = std::move(*tree);
  stack_.reserve(8 * tree_.stats.levels + 8);
  frames_ = cube_faces_drawn_ = leaf_triangles_drawn_ = 0;
  return {};
}

Result<void> ColorcubeTechnique::bake(const Scene& scene, Store& store, Progress& progress) {
  auto tree = build_cube_tree(scene, options_.tree, progress);
  if (!tree) return make_error("colorcube: ", tree.error().message);
  if (auto ok = save_cube_tree(*tree, scene_fingerprint(scene), store); !ok) return ok;
  tree_ = std::move(*tree);
  stack_.reserve(8 * tree_.stats.levels + 8);
  return {};
}

Result<void> ColorcubeTechnique::load_baked(const Scene& scene, const Store& store) {
  auto tree = load_cube_tree(store, scene_fingerprint(scene));
  if (!tree) return tree.error();
  tree_ = std::move(*tree);
  frames_ = cube_faces_drawn_ = leaf_triangles_drawn_ = 0;
  stack_.reserve(8 * tree_.stats.levels + 8);
  return {};
}

void ColorcubeTechnique::select(const View& view, const FrameBudget&, DrawList& out) {
  out.clear();
  if (tree_.cells.empty()) return;
  ++frames_;
  const Frustum frustum(view);
  const glm::vec3 eye = view.pose.position, forward = view.pose.forward();
  // paper 002, Sec. 3.1: a cube is drawn when size / depth < epsilon; epsilon is the angular
  // size of `pixel_tolerance` pixels at the centre of the view.
  const float epsilon = options_.pixel_tolerance * 2.0f *
                        std::tan(glm::radians(view.hfov_deg) * 0.5f) / float(view.width);
  const float cluster = float(tree_.stats.cluster);
  stack_.clear();
  stack_.push_back(0);
  while (!stack_.empty()) {
    const CubeCell& cell = tree_.cells[stack_.back()];
    stack_.pop_back();
    if (frustum.classify(cell.reach) == Visibility::none) continue;
    // The depth of the nearest corner of what the cell may draw, in the field of view.
    float depth = INFINITY;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner(k & 1 ? cell.reach.max.x : cell.reach.min.x,
                             k & 2 ? cell.reach.max.y : cell.reach.min.y,
                             k & 4 ? cell.reach.max.z : cell.reach.min.z);
      depth = std::min(depth, glm::dot(corner - eye, forward));
    }
    const float cube_size = (cell.bounds.max.x - cell.bounds.min.x) / cluster;
    if (depth > 0.0f && cube_size < epsilon * depth) {
      for (int face = 0; face < 6; ++face) {
        if (cell.faces_count[face] == 0) continue;
        const int a = face_axis(face);
        // Some cube of the cluster faces the eye only if the eye is past the cell's far plane.
        const bool facing = face_sign(face) > 0 ? eye[a] > cell.bounds.min[a] + cube_size
                                                : eye[a] < cell.bounds.max[a] - cube_size;
        if (!facing) continue;
        append(out, cell.faces_begin[face], cell.faces_count[face]);
        cube_faces_drawn_ += cell.faces_count[face] / 6;  // two triangles a face
      }
      continue;
    }
    if (cell.leaf()) {
      append(out, cell.geometry_begin, cell.geometry_count);
      leaf_triangles_drawn_ += cell.geometry_count / 3;
      continue;
    }
    // Children nearest first: pushed farthest first.
    const size_t first = stack_.size();
    for (uint32_t c = 0; c < cell.child_count; ++c) stack_.push_back(cell.first_child + c);
    std::sort(stack_.begin() + first, stack_.end(), [&](uint32_t a, uint32_t b) {
      return glm::distance(tree_.cells[a].bounds.center(), eye) >
             glm::distance(tree_.cells[b].bounds.center(), eye);
    });
  }
}

std::vector<std::pair<std::string, double>> ColorcubeTechnique::figures() const {
  const CubeTreeStats& s = tree_.stats;  // paper 002, Table 1
  return {{"tree_cells", s.cells},
          {"leaves", s.leaves},
          {"levels", s.levels},
          {"clustering_factor", s.cluster},
          {"oversampling_factor", s.oversampling},
          {"cube_faces_in_model", double(s.cube_faces)},
          {"leaf_triangles", double(s.geometry_triangles)},
          {"preprocessing_leaves_s", s.leaf_bake_s},
          {"preprocessing_hierarchy_s", s.hierarchy_s},
          // Per frame over the frames selected so far (bench: warm-up frames and the path).
          {"mean_cube_faces_drawn", frames_ ? double(cube_faces_drawn_) / double(frames_) : 0.0},
          {"mean_leaf_triangles_drawn",
           frames_ ? double(leaf_triangles_drawn_) / double(frames_) : 0.0}};
}

std::string ColorcubeTechnique::describe() const {
  const CubeTreeStats& s = tree_.stats;
  char line[256];
  std::snprintf(line, sizeof(line),
                "%u cells (%u leaves), %u levels, cluster %ux%ux%u, oversampling %ux%u, %llu cube "
                "faces, %llu leaf triangles, bake %.2f s + %.2f s",
                s.cells, s.leaves, s.levels, s.cluster, s.cluster, s.cluster, s.oversampling,
                s.oversampling, (unsigned long long)s.cube_faces,
                (unsigned long long)s.geometry_triangles, s.leaf_bake_s, s.hierarchy_s);
  return line;
}

}  // namespace farfield
