#include "colorcube_technique.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/core/frustum.hpp"
#include "farfield/core/text.hpp"
#include "farfield/scene/path_generator.hpp"
#include "farfield/store/bake_record.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

namespace {

// Adds a range of the cube mesh, extending the last one when they touch.
void append(DrawList& out, MeshHandle mesh, uint32_t first, uint32_t count) {
  if (count == 0) return;
  if (!out.meshes.empty() && out.meshes.back().mesh == mesh &&
      out.meshes.back().first_index + out.meshes.back().index_count == first)
    out.meshes.back().index_count += count;
  else
    out.meshes.push_back({mesh, first, count, {}});
}

constexpr SettingSpec kSettings[] = {
    {.key = "depth",
     .type = SettingType::integer,
     .default_value = "0",
     .help = "levels of the octree below the root; 0 derives it from the scene by "
             "colorcube.depth_rule, at most 262144 leaves",
     .symbol = "octree depth (002, Table 1)",
     .min = 0,
     .max = 12,
     .baked = true},
    {.key = "depth_rule",
     .type = SettingType::choice,
     .default_value = "detail",
     .help = "how depth 0 is derived: leaf cubes about the median triangle edge, or about 4000 "
             "triangles a leaf (paper 002 Sec. 6.4)",
     .choices = "detail|density",
     .baked = true},
    {.key = "cluster",
     .type = SettingType::integer,
     .default_value = "4",
     .help = "cubes per cell side",
     .symbol = "c (002, Sec. 4.2)",
     .min = 1,
     .max = 32,
     .baked = true},
    {.key = "oversampling",
     .type = SettingType::integer,
     .default_value = "1",
     .help = "pixels per cube side when a leaf is rendered",
     .unit = "px",
     .symbol = "k (002, Sec. 4.1)",
     .min = 1,
     .max = 5,
     .baked = true},
    {.key = "coverage",
     .type = SettingType::choice,
     .default_value = "binary",
     .help = "face coverage: any covered pixel (the paper's) or the covered fraction",
     .choices = "binary|fraction",
     .baked = true},
    {.key = "threshold",
     .type = SettingType::number,
     .default_value = "0",
     .help = "a face is drawn when its coverage exceeds this",
     .min = 0,
     .max = 1,
     .max_open = true,
     .baked = true},
    {.key = "alpha",
     .type = SettingType::flag,
     .default_value = "0",
     .help = "draw coverage as transparency (paper 002, Sec. 4.1)",
     .baked = true},
    {.key = "inner_faces",
     .type = SettingType::choice,
     .default_value = "drop",
     .help = "faces against a solid neighbour: dropped at bake, or kept as the paper does",
     .choices = "drop|keep",
     .baked = true},
    {.key = "occlusion",
     .type = SettingType::flag,
     .default_value = "1",
     .help = "skip cells hidden behind cube faces already drawn (the image is unchanged); 0 is "
             "the paper's walk"},
    {.key = "pixels",
     .type = SettingType::number,
     .default_value = "1",
     .help = "pixel tolerance: a cell is drawn as cubes when a cube covers less than this",
     .unit = "px",
     .symbol = "epsilon (002, Sec. 3.1)",
     .min = 0,
     .max = 1e4,
     .min_open = true},
    {.key = "force",
     .type = SettingType::flag,
     .default_value = "0",
     .help = "bake even when no cube would be drawn at the tolerance from where the whole "
             "scene is in view (the walk would be octree culling) (bake only)"},
    {.key = "threads",
     .type = SettingType::integer,
     .default_value = "0",
     .help = "leaf bake threads; 0: all cores",
     .min = 0,
     .max = 1024},
};

}  // namespace

const TechniqueDescriptor colorcube_descriptor{
    .name = "colorcube",
    .summary = "colour-cube octree walked like Barnes-Hut",
    .paper = "002",
    .settings = kSettings,
    .bake = BakeUse::optional,
    .bake_format = 2,  // 2: leaves' textured triangles as scene ranges
    .make = [](const SettingValues& v,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      ColorcubeOptions o;
      o.tree.depth = v.integer("depth");
      o.tree.depth_rule = v.text("depth_rule") == "detail" ? DepthRule::detail : DepthRule::density;
      o.tree.leaf.cluster = v.integer("cluster");
      o.tree.leaf.oversampling = v.integer("oversampling");
      o.tree.leaf.coverage =
          v.text("coverage") == "binary" ? CoverageMode::binary : CoverageMode::fraction;
      o.tree.coverage_threshold = float(v.number("threshold"));
      o.tree.coverage_as_alpha = v.flag("alpha");
      o.tree.drop_inner_faces = v.text("inner_faces") == "drop";
      o.occlusion = v.flag("occlusion");
      o.pixel_tolerance = float(v.number("pixels"));
      o.tree.threads = v.integer("threads");
      o.force = v.flag("force");
      return std::unique_ptr<Technique>(std::make_unique<ColorcubeTechnique>(o));
    },
};

Result<void> ColorcubeTechnique::use(CubeTree tree, const Scene& scene, gpu::Device& device) {
  tree_ = std::move(tree);
  scene_ = &scene;
  resources_.bind(device);
  auto mesh = resources_.mesh(tree_.proxies.vertices, tree_.proxies.indices);
  if (!mesh) return make_error("colorcube: ", mesh.error().message);
  mesh_ = *mesh;
  index_outlines();
  stack_.reserve(8 * tree_.stats.levels + 8);
  frames_ = cube_faces_drawn_ = leaf_triangles_drawn_ = cells_occluded_ = 0;
  return {};
}

namespace {

// Whether the walk would ever draw a cube (docs/techniques/colorcube.md, "When it applies"):
// a leaf cube is drawn once it projects below the tolerance, from a depth of its size over
// epsilon (paper 002, Sec. 3.1); the farthest a point is seen in the protocol's view (1024 px
// across 90 degrees) with the whole scene in sight is an orbit's distance plus the radius.
Result<void> check_cubes_drawable(const Scene& scene, const ColorcubeOptions& o,
                                  const ResolvedDepth& resolved) {
  const int c = o.tree.leaf.cluster;
  const double leaf_cube = leaf_cube_side(scene, resolved.depth, c);
  const double epsilon = o.pixel_tolerance * 2.0 / 1024.0;  // tan(45 degrees) = 1
  const double radius = 0.5 * glm::length(glm::dvec3(scene.bounds.size()));
  const double farthest = whole_view_distance(scene.bounds) + radius;
  const double nearest_cube = leaf_cube / epsilon;
  if (nearest_cube <= farthest) return {};
  const int deeper =
      std::min(12, int(std::ceil(std::log2(leaf_cube_side(scene, 0, c) / (epsilon * farthest)))));
  std::string why = formatted(
      "colorcube: no cube would be drawn: at depth %d a leaf cube is %.3g m, which shrinks "
      "below %.3g px only from %.0f m, and the scene is seen whole from %.0f m (every frame "
      "would be octree culling; colour cubes stand for sub-pixel detail seen from afar, paper "
      "002). ",
      resolved.depth, leaf_cube, double(o.pixel_tolerance), nearest_cube, farthest);
  if (o.tree.depth == 0 && resolved.limited_by_leaves)
    why += formatted("The depth was lowered from %d to stay under %llu leaves. ",
                     resolved.detail_depth, (unsigned long long)o.tree.max_leaves);
  else if (o.tree.depth == 0 && deeper > resolved.detail_depth)
    why += formatted(
        "Depth %d would make leaf cubes (%.3g m) smaller than the scene's triangles (median "
        "edge %.3g m). ",
        deeper, leaf_cube_side(scene, deeper, c), double(median_triangle_edge(scene)));
  why += formatted(
      "Set colorcube.depth=%d or deeper, a larger colorcube.pixels, or colorcube.force=1 to "
      "bake anyway",
      deeper);
  return make_error(why);
}

}  // namespace

Result<void> ColorcubeTechnique::bake(const BakeContext& context) {
  // The depth is resolved once (deriving it sorts every triangle's cell) for the check and
  // the build.
  const ResolvedDepth resolved = resolve_depth(context.scene, options_.tree);
  if (!options_.force)
    if (auto ok = check_cubes_drawable(context.scene, options_, resolved); !ok) return ok;
  CubeTreeOptions tree_options = options_.tree;
  tree_options.depth = resolved.depth;
  auto tree = build_cube_tree(context.scene, tree_options, context.progress);
  if (!tree) return make_error("colorcube: ", tree.error().message);
  if (auto ok = save_cube_tree(*tree, context.store); !ok) return ok;
  tree_ = std::move(*tree);
  return {};
}

Result<void> ColorcubeTechnique::load(const LoadContext& context) {
  // A pack that holds a colour-cube bake is read; without one the tree is built now.
  auto record = context.store ? read_bake_record(*context.store, "colorcube")
                              : Result<std::optional<BakeRecord>>(std::optional<BakeRecord>{});
  if (!record) return record.error();
  if (*record) {
    if (auto usable = usable_bake(*context.store, "colorcube", colorcube_descriptor.bake_format,
                                  scene_fingerprint(context.scene));
        !usable)
      return usable.error();
    auto tree = load_cube_tree(*context.store, context.scene);
    if (!tree) return tree.error();
    return use(std::move(*tree), context.scene, context.device);
  }
  auto tree = build_cube_tree(context.scene, options_.tree, context.progress);
  if (!tree) return make_error("colorcube: ", tree.error().message);
  return use(std::move(*tree), context.scene, context.device);
}

void ColorcubeTechnique::select(const FrameInput& input, DrawList& out) {
  // Colour cubes stand in for the scene everywhere: no far field of their own and no near
  // region (DESIGN.md; a near part of composite is octree or brute).
  if (tree_.cells.empty() || input.region.kind == Region::Kind::far_field) return;
  const View& view = input.view;
  ++frames_;
  const Frustum frustum(view);
  const glm::vec3 eye = view.pose.position, forward = view.pose.forward();
  // paper 002, Sec. 3.1: a cube is drawn when size / depth < epsilon; epsilon is the angular
  // size of `pixel_tolerance` pixels at the centre of the view.
  const float epsilon = options_.pixel_tolerance * 2.0f *
                        std::tan(glm::radians(view.hfov_deg) * 0.5f) / float(view.width);
  const float cluster = float(tree_.stats.cluster);
  if (options_.occlusion) occlusion_.reset(view);
  stack_.clear();
  stack_.push_back(0);
  while (!stack_.empty()) {
    const uint32_t index = stack_.back();
    const CubeCell& cell = tree_.cells[index];
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
    const bool as_cubes = depth > 0.0f && cube_size < epsilon * depth;
    // Drawn as cubes the cell stays inside its bounds; otherwise its triangles may reach out.
    if (options_.occlusion && occlusion_.hidden(as_cubes ? cell.bounds : cell.reach)) {
      ++cells_occluded_;
      continue;
    }
    if (as_cubes) {
      for (int face = 0; face < 6; ++face) {
        if (cell.faces_count[face] == 0) continue;
        const int a = face_axis(face);
        // Some cube of the cluster faces the eye only if the eye is past the cell's far plane.
        const bool facing = face_sign(face) > 0 ? eye[a] > cell.bounds.min[a] + cube_size
                                                : eye[a] < cell.bounds.max[a] - cube_size;
        if (!facing) continue;
        append(out, mesh_, cell.faces_begin[face], cell.faces_count[face]);
        cube_faces_drawn_ += cell.faces_count[face] / 6;  // two triangles a face
      }
      if (options_.occlusion) mark_occluders(index);
      continue;
    }
    if (cell.leaf()) {
      append(out, mesh_, cell.geometry_begin, cell.geometry_count);
      leaf_triangles_drawn_ += cell.geometry_count / 3;
      for (uint32_t k = 0; k < cell.scene_ranges_count; ++k) {
        const DrawRange& r = tree_.scene_ranges[cell.scene_ranges_begin + k];
        (scene_->materials[r.material].transparent() ? out.transparent : out.opaque).push_back(r);
        leaf_triangles_drawn_ += r.index_count / 3;
      }
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

// Which cubes of each cell have an opaque outline, read once from
// the proxy quads (cube_tree.cpp: four vertices a face, its first index its first corner, the
// corner at the cube's low u and v and on the face's side along its axis). A cube is outlined
// when each of its faces is drawn opaque or lies against an outlined neighbour of the
// cluster (the largest such set): a ray into the cube's outline then meets an opaque face at
// or before the cube, whichever way it comes. This covers the faces the bake dropped against
// solid neighbours. Translucent faces (colorcube.alpha=1) count as not drawn.
void ColorcubeTechnique::index_outlines() {
  const int c = int(tree_.stats.cluster), count = c * c * c;
  outlines_.clear();
  outline_first_.assign(tree_.cells.size() + 1, 0);
  const std::vector<ProxyVertex>& v = tree_.proxies.vertices;
  const std::vector<uint32_t>& indices = tree_.proxies.indices;
  std::vector<uint8_t> drawn(static_cast<size_t>(count)),
      in(static_cast<size_t>(count));  // face bits; the set
  for (size_t i = 0; i < tree_.cells.size(); ++i) {
    const CubeCell& cell = tree_.cells[i];
    const glm::vec3 step = cell.bounds.size() / float(c);
    std::fill(drawn.begin(), drawn.end(), 0);
    for (int face = 0; face < 6; ++face) {
      const int a = face_axis(face);
      for (uint32_t k = cell.faces_begin[face]; k < cell.faces_begin[face] + cell.faces_count[face];
           k += 6) {
        const ProxyVertex& corner = v[indices[k]];
        if ((corner.color >> 24) != 0xFF) continue;
        glm::vec3 lo = corner.position;
        if (face_sign(face) > 0) lo[a] -= step[a];
        const glm::ivec3 g = glm::clamp(glm::ivec3(glm::round((lo - cell.bounds.min) / step)),
                                        glm::ivec3(0), glm::ivec3(c - 1));
        drawn[size_t(g.x + c * (g.y + c * g.z))] |= uint8_t(1u << face);
      }
    }
    std::fill(in.begin(), in.end(), 1);
    for (bool changed = true; changed;) {
      changed = false;
      for (int b = 0; b < count; ++b) {
        if (!in[size_t(b)]) continue;
        const int g[3] = {b % c, b / c % c, b / (c * c)};
        for (int face = 0; face < 6 && in[size_t(b)]; ++face) {
          if (drawn[size_t(b)] >> face & 1) continue;
          int n[3] = {g[0], g[1], g[2]};
          n[face_axis(face)] += face_sign(face);
          const bool against = n[face_axis(face)] >= 0 && n[face_axis(face)] < c &&
                               in[size_t(n[0] + c * (n[1] + c * n[2]))];
          if (!against) {
            in[size_t(b)] = 0;
            changed = true;
          }
        }
      }
    }
    // Outlined cubes merged greedily into boxes (runs along X, grown along Y, then Z), so
    // that no margin is lost between neighbours and fewer outlines are drawn.
    outline_first_[i] = uint32_t(outlines_.size());
    for (int b = 0; b < count; ++b) {
      if (!in[size_t(b)]) continue;
      const int x0 = b % c, y0 = b / c % c, z0 = b / (c * c);
      auto taken = [&](int x, int y, int z) { return in[size_t(x + c * (y + c * z))] != 0; };
      int x1 = x0 + 1, y1 = y0 + 1, z1 = z0 + 1;
      while (x1 < c && taken(x1, y0, z0)) ++x1;
      auto row = [&](int y, int z) {
        for (int x = x0; x < x1; ++x)
          if (!taken(x, y, z)) return false;
        return true;
      };
      while (y1 < c && row(y1, z0)) ++y1;
      auto layer = [&](int z) {
        for (int y = y0; y < y1; ++y)
          if (!row(y, z)) return false;
        return true;
      };
      while (z1 < c && layer(z1)) ++z1;
      for (int z = z0; z < z1; ++z)
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) in[size_t(x + c * (y + c * z))] = 0;
      outlines_.push_back(
          {{uint8_t(x0), uint8_t(y0), uint8_t(z0)}, {uint8_t(x1), uint8_t(y1), uint8_t(z1)}});
    }
  }
  outline_first_.back() = uint32_t(outlines_.size());
}

// A cell's outlined boxes into the occlusion buffer.
void ColorcubeTechnique::mark_occluders(uint32_t cell_index) {
  const CubeCell& cell = tree_.cells[cell_index];
  const glm::vec3 step = cell.bounds.size() / float(tree_.stats.cluster);
  boxes_.clear();
  for (uint32_t k = outline_first_[cell_index]; k < outline_first_[cell_index + 1]; ++k) {
    const CubeOutline& o = outlines_[k];
    Bounds3 box;
    box.min = cell.bounds.min + step * glm::vec3(o.lo[0], o.lo[1], o.lo[2]);
    box.max = cell.bounds.min + step * glm::vec3(o.hi[0], o.hi[1], o.hi[2]);
    boxes_.push_back(box);
  }
  occlusion_.add_boxes(cell.bounds, boxes_);
}

std::vector<std::pair<std::string, double>> ColorcubeTechnique::figures() const {
  const CubeTreeStats& s = tree_.stats;  // paper 002, Table 1
  return {{"tree_cells", s.cells},
          {"leaves", s.leaves},
          {"levels", s.levels},
          {"clustering_factor", s.cluster},
          {"oversampling_factor", s.oversampling},
          {"cube_faces_in_model", double(s.cube_faces)},
          {"inner_faces_dropped", double(s.inner_faces_dropped)},
          {"leaf_triangles", double(s.geometry_triangles)},
          {"preprocessing_leaves_s", s.leaf_bake_s},
          {"preprocessing_hierarchy_s", s.hierarchy_s},
          // Per frame over the frames selected so far (bench: warm-up frames and the path).
          {"mean_cube_faces_drawn", frames_ ? double(cube_faces_drawn_) / double(frames_) : 0.0},
          {"mean_leaf_triangles_drawn",
           frames_ ? double(leaf_triangles_drawn_) / double(frames_) : 0.0},
          {"mean_cells_occluded", frames_ ? double(cells_occluded_) / double(frames_) : 0.0}};
}

std::string ColorcubeTechnique::describe() const {
  const CubeTreeStats& s = tree_.stats;
  char line[256];
  std::snprintf(line, sizeof(line),
                "%u cells (%u leaves), depth %u (%u levels with the root), cluster %ux%ux%u, "
                "oversampling %ux%u, %llu cube "
                "faces (%llu inner ones dropped), %llu leaf triangles, bake %.2f s + %.2f s",
                s.cells, s.leaves, s.levels - 1, s.levels, s.cluster, s.cluster, s.cluster,
                s.oversampling, s.oversampling, (unsigned long long)s.cube_faces,
                (unsigned long long)s.inner_faces_dropped, (unsigned long long)s.geometry_triangles,
                s.leaf_bake_s, s.hierarchy_s);
  return line;
}

}  // namespace farfield
