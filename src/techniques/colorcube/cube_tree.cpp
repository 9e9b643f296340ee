#include "farfield/techniques/colorcube/cube_tree.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>

#include "farfield/core/assert.hpp"
#include "farfield/core/parallel.hpp"
#include "farfield/gpu/lighting.hpp"
#include "farfield/spatial/octree.hpp"

namespace farfield {

namespace {

using Clock = std::chrono::steady_clock;

Bounds3 bounding_cube(const Bounds3& b) {
  const float half = 0.5f * std::max({b.size().x, b.size().y, b.size().z}) * 1.0001f + 1e-4f;
  Bounds3 cube;
  cube.min = b.center() - glm::vec3(half);
  cube.max = b.center() + glm::vec3(half);
  return cube;
}

// The fixed-depth octree of paper 002 (Sec. 4.1: each primitive goes to every leaf it lies
// in; empty cells are pruned), built by spatial/octree over the triangles' boxes; each leaf
// also owns, by centroid, the triangles it draws as geometry.
struct Subdivision {
  std::vector<uint32_t> items;                            // the octree's leaf items
  std::vector<std::span<const uint32_t>> leaf_triangles;  // overlapping, by leaf order
  std::vector<std::vector<uint32_t>> leaf_owned;          // centroid inside, by leaf order
  std::vector<uint32_t> leaf_cells;                       // cell of each leaf, depth first
};

Subdivision subdivide(const Scene& scene, int depth, CubeTree& tree) {
  std::vector<Bounds3> boxes(scene.triangle_count());
  for (size_t t = 0; t < boxes.size(); ++t)
    for (int k = 0; k < 3; ++k) boxes[t].expand(scene.vertices[scene.indices[t * 3 + k]].position);
  Octree octree = build_octree(boxes, {.max_depth = uint32_t(depth),
                                       .split_to_max_depth = true,
                                       .root = bounding_cube(scene.bounds)});
  boxes = {};
  tree.cells.resize(octree.nodes.size());
  for (size_t i = 0; i < octree.nodes.size(); ++i) {
    const OctreeNode& node = octree.nodes[i];
    CubeCell& cell = tree.cells[i];
    cell.bounds = node.bounds;
    cell.first_child = node.first_child;
    cell.child_count = node.child_count;
    for (uint32_t k = 0; k < node.child_count; ++k)
      tree.cells[node.first_child + k].level = cell.level + 1;
  }
  Subdivision out;
  out.items = std::move(octree.items);
  for (uint32_t i = 0; i < octree.nodes.size(); ++i)
    if (octree.nodes[i].leaf()) out.leaf_cells.push_back(i);
  // Depth-first leaf order: the order of their item ranges.
  std::sort(out.leaf_cells.begin(), out.leaf_cells.end(), [&](uint32_t a, uint32_t b) {
    return octree.nodes[a].items_begin < octree.nodes[b].items_begin;
  });
  for (uint32_t leaf : out.leaf_cells) {
    const OctreeNode& node = octree.nodes[leaf];
    const std::span<const uint32_t> triangles(out.items.data() + node.items_begin,
                                              node.items_end - node.items_begin);
    // Ownership by centroid, half-open per axis, so every triangle has exactly one owner.
    std::vector<uint32_t> owned;
    for (uint32_t t : triangles) {
      const uint32_t* idx = scene.indices.data() + size_t(t) * 3;
      const glm::vec3 c = (scene.vertices[idx[0]].position + scene.vertices[idx[1]].position +
                           scene.vertices[idx[2]].position) /
                          3.0f;
      if (c.x >= node.bounds.min.x && c.x < node.bounds.max.x && c.y >= node.bounds.min.y &&
          c.y < node.bounds.max.y && c.z >= node.bounds.min.z && c.z < node.bounds.max.z)
        owned.push_back(t);
    }
    out.leaf_triangles.push_back(triangles);
    out.leaf_owned.push_back(std::move(owned));
  }
  return out;
}

// Appends the quad of `face` of the box [lo, hi], counter-clockwise seen from outside.
void add_face_quad(ProxyMesh& mesh, const glm::vec3& lo, const glm::vec3& hi, int face,
                   uint32_t color) {
  const int a = face_axis(face), u = (a + 1) % 3, v = (a + 2) % 3;
  const bool positive = face_sign(face) > 0;
  glm::vec3 corner[4];
  const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // counter-clockwise seen from +a
  for (int i = 0; i < 4; ++i) {
    corner[i][a] = positive ? hi[a] : lo[a];
    corner[i][u] = uv[i][0] > 0 ? hi[u] : lo[u];
    corner[i][v] = uv[i][1] > 0 ? hi[v] : lo[v];
  }
  const uint32_t base = uint32_t(mesh.vertices.size());
  for (const glm::vec3& p : corner) mesh.vertices.push_back({p, color});
  if (positive)
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  else
    mesh.indices.insert(mesh.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
}

}  // namespace

uint64_t occupied_leaves(const Scene& scene, int depth) {
  const Bounds3 cube = bounding_cube(scene.bounds);
  const uint64_t n = scene.triangle_count();
  const uint32_t cells = 1u << depth;
  const glm::vec3 scale = glm::vec3(float(cells)) / cube.size();
  std::vector<uint64_t> keys(n);
  for (uint64_t t = 0; t < n; ++t) {
    const uint32_t* idx = scene.indices.data() + t * 3;
    const glm::vec3 c = (scene.vertices[idx[0]].position + scene.vertices[idx[1]].position +
                         scene.vertices[idx[2]].position) /
                        3.0f;
    const glm::uvec3 g =
        glm::clamp(glm::uvec3((c - cube.min) * scale), glm::uvec3(0), glm::uvec3(cells - 1));
    keys[t] = (uint64_t(g.x) << 42) | (uint64_t(g.y) << 21) | g.z;
  }
  std::sort(keys.begin(), keys.end());
  return uint64_t(std::unique(keys.begin(), keys.end()) - keys.begin());
}

double leaf_cube_side(const Scene& scene, int depth, int cluster) {
  return double(bounding_cube(scene.bounds).size().x) / double(1u << depth) / cluster;
}

ResolvedDepth resolve_depth(const Scene& scene, const CubeTreeOptions& o) {
  ResolvedDepth r;
  if (o.depth > 0) {  // as given
    r.depth = r.detail_depth = o.depth;
    return r;
  }
  // Leaf cubes no smaller than the scene's typical triangle: finer ones cost memory and
  // stand for less than a triangle each; coarser ones shrink below the tolerance only
  // farther away, so more of the scene is drawn as triangles.
  const double detail = median_triangle_edge(scene);
  const double side = leaf_cube_side(scene, 0, o.leaf.cluster);
  r.detail_depth = detail > 0.0 ? std::clamp(int(std::floor(std::log2(side / detail))), 1, 12) : 1;
  if (o.depth_rule == DepthRule::density) {
    // paper 002, Sec. 6.4: depth from primitive density. Deepen while the occupied cells of
    // the level (counted by triangle centroid) hold more than the target on average.
    r.depth = 10;
    for (int depth = 1; depth <= 10; ++depth) {
      const uint64_t occupied = occupied_leaves(scene, depth);
      if (occupied == 0 || scene.triangle_count() / occupied <= uint64_t(o.triangles_per_leaf)) {
        r.depth = depth;
        break;
      }
    }
  } else {
    r.depth = r.detail_depth;
  }
  while (r.depth > 1 && occupied_leaves(scene, r.depth) > o.max_leaves) {
    --r.depth;
    r.limited_by_leaves = true;
  }
  return r;
}

Result<CubeTree> build_cube_tree(const Scene& scene, const CubeTreeOptions& o, Progress& progress) {
  if (o.depth < 0 || o.depth > 12)
    return make_error("depth must be within 0..12 (got ", std::to_string(o.depth), ")");
  if (o.leaf.oversampling < 1 || o.leaf.oversampling > 5)
    return make_error("oversampling must be within 1..5 (got ", std::to_string(o.leaf.oversampling),
                      ")");
  if (o.leaf.cluster < 1 || o.leaf.cluster > 32)
    return make_error("cluster must be within 1..32 (got ", std::to_string(o.leaf.cluster), ")");
  if (!(o.coverage_threshold >= 0.0f && o.coverage_threshold < 1.0f))
    return make_error("coverage threshold must be within [0, 1)");
  if (scene.triangle_count() == 0) return make_error("the scene has no triangles");

  const auto start = Clock::now();
  CubeTree tree;
  const int depth = resolve_depth(scene, o).depth;
  Subdivision split = subdivide(scene, depth, tree);

  // Phase I (paper 002, Sec. 5.1): render every leaf, on every core.
  const int c = o.leaf.cluster, per_cell = c * c * c;
  std::vector<ColorCube> cubes(tree.cells.size() * size_t(per_cell));
  const std::vector<uint32_t> materials = triangle_materials(scene);
  auto textures = leaf_textures(scene);
  if (!textures) return textures.error();
  const size_t leaves = split.leaf_cells.size();
  parallel_for(leaves, o.threads, progress, "bake colour-cube leaves", [&](size_t i) {
    const uint32_t cell = split.leaf_cells[i];
    std::vector<ColorCube> baked = bake_leaf(scene, materials, split.leaf_triangles[i],
                                             tree.cells[cell].bounds, o.leaf, *textures);
    std::copy(baked.begin(), baked.end(), cubes.begin() + size_t(cell) * per_cell);
  });
  split.leaf_triangles = {};
  split.items = {};
  tree.stats.leaf_bake_s = std::chrono::duration<double>(Clock::now() - start).count();

  // Phase II: parents from children, deepest first (children follow their parent in `cells`).
  const auto phase2 = Clock::now();
  for (size_t i = tree.cells.size(); i-- > 0;) {
    const CubeCell& cell = tree.cells[i];
    if (cell.leaf()) continue;
    std::array<int, 8> child_of_octant;
    child_of_octant.fill(-1);
    for (uint32_t k = 0; k < cell.child_count; ++k) {
      const CubeCell& child = tree.cells[cell.first_child + k];
      const glm::vec3 d = child.bounds.center() - cell.bounds.center();
      child_of_octant[(d.x > 0) | (d.y > 0) << 1 | (d.z > 0) << 2] = int(cell.first_child + k);
    }
    // Parent cube p of the cluster covers cubes 2p .. 2p+1 of a grid 2c wide over the children.
    for (int pz = 0; pz < c; ++pz)
      for (int py = 0; py < c; ++py)
        for (int px = 0; px < c; ++px) {
          std::array<ColorCube, 8> parts{};
          for (int sub = 0; sub < 8; ++sub) {
            const int g[3] = {2 * px + (sub & 1), 2 * py + ((sub >> 1) & 1),
                              2 * pz + ((sub >> 2) & 1)};
            const int oct = (g[0] / c) | (g[1] / c) << 1 | (g[2] / c) << 2;
            if (child_of_octant[oct] < 0) continue;
            const int l[3] = {g[0] % c, g[1] % c, g[2] % c};
            parts[sub] =
                cubes[size_t(child_of_octant[oct]) * per_cell + l[0] + c * (l[1] + c * l[2])];
          }
          cubes[i * per_cell + px + c * (py + c * pz)] = combine(parts);
        }
  }

  // Proxy quads, six batches per cell (paper 002, Sec. 4.2).
  const auto drawn = [&](const FaceColor& f) { return f.coverage > o.coverage_threshold; };
  // A cube every face of which is drawn opaque hides whatever lies behind it in its box.
  const auto solid = [&](const ColorCube& cube) {
    return std::all_of(cube.faces.begin(), cube.faces.end(), [&](const FaceColor& f) {
      return drawn(f) && (!o.coverage_as_alpha || f.coverage >= 1.0f);
    });
  };
  uint64_t hidden = 0, proxied_triangles = 0;
  for (size_t i = 0; i < tree.cells.size(); ++i) {
    CubeCell& cell = tree.cells[i];
    const glm::vec3 step = cell.bounds.size() / float(c);
    const ColorCube* cluster = cubes.data() + i * per_cell;
    for (int face = 0; face < 6; ++face) {
      cell.faces_begin[face] = uint32_t(tree.proxies.indices.size());
      const int a = face_axis(face), sign = face_sign(face);
      for (int z = 0; z < c; ++z)
        for (int y = 0; y < c; ++y)
          for (int x = 0; x < c; ++x) {
            const FaceColor& f = cluster[x + c * (y + c * z)].faces[face];
            if (!drawn(f)) continue;
            // Not in the paper: a face against a solid neighbour of the same cluster is
            // hidden, since a ray reaching it crosses the neighbour, whose faces towards the
            // eye are drawn in the same batch set (only a pixel centre exactly on the face's
            // edge may differ, by the renderer's tie-breaking). Dropping it turns the cost of
            // a solid cluster from its volume to its surface.
            if (o.drop_inner_faces) {
              int n[3] = {x, y, z};
              n[a] += sign;
              if (n[a] >= 0 && n[a] < c && solid(cluster[n[0] + c * (n[1] + c * n[2])])) {
                ++hidden;
                continue;
              }
            }
            const glm::vec3 lo = cell.bounds.min + step * glm::vec3(x, y, z);
            add_face_quad(tree.proxies, lo, lo + step, face,
                          pack_color(glm::vec4(f.rgb, o.coverage_as_alpha ? f.coverage : 1.0f)));
          }
      cell.faces_count[face] = uint32_t(tree.proxies.indices.size()) - cell.faces_begin[face];
    }
  }
  // The leaves' own triangles: untextured ones lit per vertex (gpu/lighting.hpp), vertices
  // shared per leaf; textured ones drawn from the scene's own buffers (they need its texture
  // coordinates and the textured program), as runs of consecutive triangles.
  std::vector<uint32_t> local, proxied, textured;
  for (size_t l = 0; l < leaves; ++l) {
    CubeCell& cell = tree.cells[split.leaf_cells[l]];
    proxied.clear();
    textured.clear();
    for (uint32_t t : split.leaf_owned[l])
      (scene.materials[materials[t]].textured() ? textured : proxied).push_back(t);
    cell.scene_ranges_begin = uint32_t(tree.scene_ranges.size());
    std::sort(textured.begin(), textured.end());
    for (size_t i = 0; i < textured.size();) {
      size_t j = i + 1;
      while (j < textured.size() && textured[j] == textured[j - 1] + 1 &&
             materials[textured[j]] == materials[textured[i]])
        ++j;
      tree.scene_ranges.push_back({textured[i] * 3, uint32_t(j - i) * 3, materials[textured[i]]});
      i = j;
    }
    cell.scene_ranges_count = uint32_t(tree.scene_ranges.size()) - cell.scene_ranges_begin;
    cell.geometry_begin = uint32_t(tree.proxies.indices.size());
    local.clear();
    for (uint32_t t : proxied)
      for (int k = 0; k < 3; ++k) local.push_back(scene.indices[size_t(t) * 3 + k]);
    std::sort(local.begin(), local.end());
    local.erase(std::unique(local.begin(), local.end()), local.end());
    const uint32_t base = uint32_t(tree.proxies.vertices.size());
    // A vertex's material is its triangles' (objects do not share vertices).
    std::vector<int32_t> material_of(local.size(), -1);
    for (uint32_t t : proxied)
      for (int k = 0; k < 3; ++k) {
        const size_t at =
            size_t(std::lower_bound(local.begin(), local.end(), scene.indices[size_t(t) * 3 + k]) -
                   local.begin());
        material_of[at] = int32_t(materials[t]);
      }
    for (size_t i = 0; i < local.size(); ++i) {
      const Vertex& v = scene.vertices[local[i]];
      const glm::vec4 tint = scene.materials[uint32_t(material_of[i])].base_color;
      const glm::vec3 lit =
          gpu::shade(unpack_normal(v.normal), glm::vec3(unpack_color(v.color)) * glm::vec3(tint));
      tree.proxies.vertices.push_back({v.position, pack_color(glm::vec4(lit, tint.a))});
    }
    for (uint32_t t : proxied)
      for (int k = 0; k < 3; ++k)
        tree.proxies.indices.push_back(base +
                                       uint32_t(std::lower_bound(local.begin(), local.end(),
                                                                 scene.indices[size_t(t) * 3 + k]) -
                                                local.begin()));
    cell.geometry_count = uint32_t(tree.proxies.indices.size()) - cell.geometry_begin;
    cell.reach = cell.bounds;
    for (uint32_t t : split.leaf_owned[l])
      for (int k = 0; k < 3; ++k)
        cell.reach.expand(scene.vertices[scene.indices[size_t(t) * 3 + k]].position);
    proxied_triangles += proxied.size();
    tree.stats.geometry_triangles += split.leaf_owned[l].size();
    split.leaf_owned[l] = {};
  }
  // Parents reach as far as their children (children follow their parent in `cells`).
  for (size_t i = tree.cells.size(); i-- > 0;) {
    CubeCell& cell = tree.cells[i];
    if (cell.leaf()) continue;
    cell.reach = cell.bounds;
    for (uint32_t k = 0; k < cell.child_count; ++k)
      cell.reach.expand(tree.cells[cell.first_child + k].reach);
  }
  if (tree.proxies.vertices.size() >= UINT32_MAX)
    return make_error(
        "the colour-cube model needs more than 2^32 proxy vertices; lower the depth or cluster");
  tree.stats.hierarchy_s = std::chrono::duration<double>(Clock::now() - phase2).count();
  tree.stats.cells = uint32_t(tree.cells.size());
  tree.stats.leaves = uint32_t(leaves);
  tree.stats.levels = uint32_t(depth + 1);
  tree.stats.cluster = uint32_t(c);
  tree.stats.oversampling = uint32_t(o.leaf.oversampling);
  tree.stats.cube_faces = (tree.proxies.indices.size() - 3 * proxied_triangles) / 6;
  tree.stats.inner_faces_dropped = hidden;
  return tree;
}

}  // namespace farfield
