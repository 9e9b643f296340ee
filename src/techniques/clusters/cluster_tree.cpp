#include "farfield/techniques/clusters/cluster_tree.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "farfield/core/text.hpp"
#include "farfield/scene/instances.hpp"
#include "farfield/scene/simplify.hpp"
#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/clusters/bake_work.hpp"

namespace farfield {

namespace {

constexpr const char* kNodes = "clusters/tree_nodes";
constexpr const char* kObjects = "clusters/tree_objects";
constexpr const char* kParts = "clusters/tree_parts";

// A cell being split: its cube and the objects wholly inside it.
struct OctantCell {
  Bounds3 cube;
  std::vector<uint32_t> objects;
  int depth = 0;
};

Bounds3 cube_around(const Bounds3& b) {
  const glm::vec3 centre = (b.min + b.max) * 0.5f;
  const glm::vec3 size = b.size();
  const float half = std::max({size.x, size.y, size.z, 1e-6f}) * 0.5f;
  return {centre - glm::vec3(half), centre + glm::vec3(half)};
}

// The octant of `cube` that holds `b`, or -1 where none does. `loose` = 0 (paper 001, Sec.
// 4.4): the octant wholly containing `b`; anything across the middle stays in the cell.
// Otherwise (a loose octree): the octant holding b's centre, if b fits in that octant grown
// by `loose` of its size on every side.
int octant_of(const Bounds3& cube, const Bounds3& b, float loose) {
  const glm::vec3 centre = (cube.min + cube.max) * 0.5f;
  const glm::vec3 margin = (cube.max - cube.min) * 0.5f * loose;
  const glm::vec3 middle = b.center();
  int octant = 0;
  for (int a = 0; a < 3; ++a) {
    const bool high = loose > 0.0f ? middle[a] >= centre[a] : b.min[a] >= centre[a];
    const float lo = (high ? centre[a] : cube.min[a]) - margin[a];
    const float hi = (high ? cube.max[a] : centre[a]) + margin[a];
    if (b.min[a] < lo || b.max[a] > hi) return -1;
    octant |= int(high) << a;
  }
  return octant;
}

Bounds3 octant_cube(const Bounds3& cube, int octant) {
  const glm::vec3 centre = (cube.min + cube.max) * 0.5f;
  Bounds3 out;
  for (int a = 0; a < 3; ++a) {
    const bool high = (octant >> a) & 1;
    out.min[a] = high ? centre[a] : cube.min[a];
    out.max[a] = high ? cube.max[a] : centre[a];
  }
  return out;
}

// The objects of a cell split into those across its middle and its octants' (non-empty ones);
// a cell whose objects all fall in one octant is replaced by that octant, so that no node
// has one child and nothing of its own.
void split(OctantCell& cell, const Scene& scene, const ClusterTreeOptions& o,
           std::vector<uint32_t>& own, std::vector<OctantCell>& children) {
  for (;;) {
    own.clear();
    children.clear();
    if (cell.objects.size() <= o.leaf_objects || cell.depth >= o.max_depth) {
      own = std::move(cell.objects);
      return;
    }
    OctantCell octants[8];
    for (uint32_t object : cell.objects) {
      const int k = octant_of(cell.cube, scene.objects[object].bounds, o.loose);
      (k < 0 ? own : octants[k].objects).push_back(object);
    }
    for (int k = 0; k < 8; ++k) {
      if (octants[k].objects.empty()) continue;
      octants[k].cube = octant_cube(cell.cube, k);
      octants[k].depth = cell.depth + 1;
      children.push_back(std::move(octants[k]));
    }
    if (own.empty() && children.size() == 1) {
      cell = std::move(children[0]);
      continue;
    }
    return;
  }
}

uint64_t triangles_of(const Scene& scene, const uint32_t* begin, const uint32_t* end) {
  uint64_t sum = 0;
  for (const uint32_t* p = begin; p != end; ++p) sum += scene.objects[*p].index_count / 3;
  return sum;
}

// An object at `level` of detail: 0 its full geometry, k its k-th level (its coarsest where it
// has fewer); its triangles and error.
struct AtLevel {
  const Lod* lod = nullptr;  // null: the full geometry
  uint64_t triangles = 0;
  float error_m = 0;
};
AtLevel at_level(const Scene& scene, const LodSet* lods, uint32_t object, uint32_t level) {
  const uint32_t levels = lods ? lods->first_lod[object + 1] - lods->first_lod[object] : 0;
  if (level == 0 || levels == 0) return {nullptr, scene.objects[object].index_count / 3, 0.0f};
  const Lod& lod = lods->lods[lods->first_lod[object] + std::min(level, levels) - 1];
  return {&lod, lod.index_count / 3, lod.error_m};
}

// The level the objects beneath a node are simplified from (ClusterTreeOptions::input_triangles):
// the finest whose triangles are no more than `budget`, else the coarsest.
uint32_t input_level(const Scene& scene, const LodSet* lods, std::span<const uint32_t> objects,
                     uint64_t budget) {
  if (!lods || budget == 0) return 0;
  uint32_t deepest = 0;
  for (uint32_t object : objects)
    deepest = std::max(deepest, lods->first_lod[object + 1] - lods->first_lod[object]);
  for (uint32_t level = 0;; ++level) {
    uint64_t triangles = 0;
    for (uint32_t object : objects) triangles += at_level(scene, lods, object, level).triangles;
    if (triangles <= budget || level >= deepest) return level;
  }
}

// The triangles of `objects` that have `material`, each at `level` (at_level), as one part.
MeshPart gather_at_level(const Scene& scene, const LodSet* lods, std::span<const uint32_t> objects,
                         uint32_t material, uint32_t level) {
  if (level == 0) return gather_part(scene, objects, material);
  MeshPart part;
  part.material = material;
  const bool textured = scene.materials[material].textured();
  std::vector<uint32_t> full;
  for (uint32_t object : objects) {
    if (scene.objects[object].material != material) continue;
    const AtLevel at = at_level(scene, lods, object, level);
    if (!at.lod) {
      full.push_back(object);  // no levels: as it is
      continue;
    }
    // A level's vertices are one run of the set's (lod_set.cpp lays each out whole); an
    // instance's are its prototype's, moved.
    const auto first = lods->indices.begin() + at.lod->first_index;
    const auto [low, high] = std::minmax_element(first, first + at.lod->index_count);
    const uint32_t base = uint32_t(part.vertices.size());
    part.vertices.insert(part.vertices.end(), lods->vertices.begin() + *low,
                         lods->vertices.begin() + *high + 1);
    if (const uint32_t k = lods->instance_of(object); k != kNoInstance) {
      const InstanceTransform move(scene.instances[k]);
      for (auto v = part.vertices.begin() + base; v != part.vertices.end(); ++v) *v = move(*v);
    }
    if (textured)
      part.uvs.insert(part.uvs.end(), lods->uvs.begin() + *low, lods->uvs.begin() + *high + 1);
    for (auto it = first; it != first + at.lod->index_count; ++it)
      part.indices.push_back(*it - *low + base);
  }
  if (!full.empty()) {
    const MeshPart whole = gather_part(scene, full, material);
    const uint32_t base = uint32_t(part.vertices.size());
    part.vertices.insert(part.vertices.end(), whole.vertices.begin(), whole.vertices.end());
    part.uvs.insert(part.uvs.end(), whole.uvs.begin(), whole.uvs.end());
    for (uint32_t i : whole.indices) part.indices.push_back(i + base);
  }
  return part;
}

// One cluster's mesh: its objects (at `level`) merged per material, each part simplified to
// the share of the target that its triangles are; the levels' error added to each part's.
std::vector<SimplifiedPart> cluster_mesh(const Scene& scene, const LodSet* lods,
                                         std::span<const uint32_t> objects, uint64_t target,
                                         uint32_t level) {
  std::vector<uint32_t> materials;
  for (uint32_t object : objects) materials.push_back(scene.objects[object].material);
  std::sort(materials.begin(), materials.end());
  materials.erase(std::unique(materials.begin(), materials.end()), materials.end());
  uint64_t total = 0;
  float level_error = 0.0f;
  for (uint32_t object : objects) {
    const AtLevel at = at_level(scene, lods, object, level);
    total += at.triangles;
    level_error = std::max(level_error, at.error_m);
  }
  const double ratio = total > 0 ? double(target) / double(total) : 0.0;
  std::vector<SimplifiedPart> out;
  for (uint32_t material : materials) {
    const MeshPart part = gather_at_level(scene, lods, objects, material, level);
    if (part.indices.empty()) continue;
    SimplifiedPart simplified = simplify_part(part, {.target_ratio = ratio});
    simplified.error_m += level_error;
    if (!simplified.mesh.indices.empty() || simplified.error_m > 0)
      out.push_back(std::move(simplified));
  }
  return out;
}

// Per node the page holding its cluster (ClusterTree's comment), and per page its first
// node; empty where the children are not each a run of nodes after their parent's group.
struct NodePages {
  std::vector<uint32_t> node_page, first_node;
};
NodePages node_pages(std::span<const ClusterNode> nodes) {
  NodePages out;
  if (nodes.empty()) return out;
  out.node_page.assign(nodes.size(), UINT32_MAX);
  out.node_page[0] = 0;
  out.first_node.push_back(0);
  uint32_t next = 1;  // the first node not yet in a page
  for (size_t n = 0; n < nodes.size(); ++n) {
    const ClusterNode& node = nodes[n];
    if (node.child_count == 0) continue;
    if (node.first_child != next || uint64_t(next) + node.child_count > nodes.size()) return {};
    for (uint32_t c = 0; c < node.child_count; ++c)
      out.node_page[next + c] = uint32_t(out.first_node.size());
    out.first_node.push_back(next);
    next += node.child_count;
  }
  if (next != nodes.size()) return {};
  return out;
}

}  // namespace

ClusterTree build_cluster_cells(const Scene& scene, const ClusterTreeOptions& o) {
  ClusterTree tree;
  const uint32_t count = uint32_t(scene.objects.size());
  if (count == 0) return tree;
  Bounds3 all;
  for (const Object& object : scene.objects) all.expand(object.bounds);
  // Breadth first, so that children are consecutive; each node's own objects kept aside.
  std::vector<OctantCell> queue(1);
  queue[0].cube = cube_around(all);
  queue[0].objects.resize(count);
  std::iota(queue[0].objects.begin(), queue[0].objects.end(), 0u);
  std::vector<std::vector<uint32_t>> own;
  std::vector<uint32_t> here;
  std::vector<OctantCell> children;
  tree.nodes.resize(1);
  for (size_t i = 0; i < queue.size(); ++i) {
    split(queue[i], scene, o, here, children);
    own.push_back(here);
    tree.nodes[i].first_child = uint32_t(tree.nodes.size());
    tree.nodes[i].child_count = uint32_t(children.size());
    for (OctantCell& child : children) {
      queue.push_back(std::move(child));
      tree.nodes.emplace_back();
    }
    queue[i].objects = {};
  }
  // Objects laid out depth first, so that every node's objects beneath it are one range;
  // bounds from the leaves up (children come after their parent).
  tree.objects.reserve(count);
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const uint32_t n = stack.back();
    stack.pop_back();
    ClusterNode& node = tree.nodes[n];
    node.objects_begin = uint32_t(tree.objects.size());
    tree.objects.insert(tree.objects.end(), own[n].begin(), own[n].end());
    node.own_end = uint32_t(tree.objects.size());
    for (uint32_t c = node.child_count; c-- > 0;) stack.push_back(node.first_child + c);
  }
  for (size_t n = tree.nodes.size(); n-- > 0;) {
    ClusterNode& node = tree.nodes[n];
    node.objects_end = node.own_end;
    for (uint32_t k = node.objects_begin; k < node.own_end; ++k)
      node.bounds.expand(scene.objects[tree.objects[k]].bounds);
    for (uint32_t c = 0; c < node.child_count; ++c) {
      const ClusterNode& child = tree.nodes[node.first_child + c];
      node.bounds.expand(child.bounds);
      node.objects_end = std::max(node.objects_end, child.objects_end);
    }
  }
  return tree;
}

Result<ClusterTree> build_cluster_tree(const Scene& scene, const ClusterTreeOptions& o,
                                       Progress& progress, Store* keep, const BakeShards* shards,
                                       const LodSet* lods) {
  if (o.leaf_objects < 1 || o.cluster_triangles < 1 || o.max_depth < 0 || !(o.loose >= 0.0f))
    return make_error("cluster hierarchy options out of range");
  const auto start = std::chrono::steady_clock::now();
  ClusterTree tree = build_cluster_cells(scene, o);
  const size_t node_count = tree.nodes.size();
  // Every cluster about the same number of triangles, as the tiles of 3D Tiles: a parent
  // covers about four times its children's area and is drawn from twice as far, so its
  // triangles stay as dense on screen; at most half of its objects' own.
  std::vector<uint64_t> full(node_count), target(node_count, 0);
  for (size_t n = 0; n < node_count; ++n) {
    const ClusterNode& node = tree.nodes[n];
    full[n] = triangles_of(scene, tree.objects.data() + node.objects_begin,
                           tree.objects.data() + node.objects_end);
    // Paper 001, Sec. 4.4: a cluster where more than one object lies wholly inside.
    if (node.objects_end - node.objects_begin >= 2)
      target[n] = std::min<uint64_t>(o.cluster_triangles, full[n] / 2);
  }
  // The largest clusters first, so that the last to finish are small.
  std::vector<uint32_t> order(node_count);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t l, uint32_t r) { return full[l] > full[r]; });
  // Clusters of more than input_triangles come from the levels: those first in `order`.
  const uint64_t budget = lods ? o.input_triangles : 0;
  // The first items of `order` that take in every one from the levels: rank 0's, found alike
  // on every rank (from the objects' triangles: other ranks hold only their share of levels).
  std::vector<uint32_t> level(node_count, 0);
  size_t from_levels = 0;
  for (size_t k = 0; k < node_count; ++k) {
    const uint32_t n = order[k];
    const ClusterNode& node = tree.nodes[n];
    if (target[n] < 1 || budget == 0 || full[n] <= budget) continue;
    level[n] = input_level(scene, lods,
                           {tree.objects.data() + node.objects_begin,
                            node.objects_end - node.objects_begin},
                           budget);
    from_levels = k + 1;
  }
  // The plan names what the meshes depend on: the scene, the cells, the targets, and the
  // levels the largest come from.
  uint64_t digest = scene_fingerprint(scene);
  for (size_t n = 0; n < node_count; ++n)
    digest = digest * 1099511628211ull ^ (uint64_t(tree.nodes[n].objects_end) << 32 ^ target[n]);
  for (size_t n = 0; n < node_count; ++n)
    if (level[n] > 0)
      digest = digest * 1099511628211ull ^ (uint64_t(level[n]) << 32 ^ n ^
                                            lods->triangle_count() << 40);
  auto work = BakeWork::open(keep, "clusters",
                             formatted("scene %016llx, %zu nodes, targets %016llx",
                                       (unsigned long long)scene_fingerprint(scene), node_count,
                                       (unsigned long long)digest),
                             shards);
  if (!work) return work.error();
  constexpr size_t kBatch = 8;
  auto meshes = work->run(
      "simplify clusters", "clusters", node_count, order, kBatch, o.threads, progress,
      [&](uint32_t n) -> PartList {
        const ClusterNode& node = tree.nodes[n];
        if (target[n] < 1) return {};
        return cluster_mesh(scene, lods,
                            {tree.objects.data() + node.objects_begin,
                             node.objects_end - node.objects_begin},
                            target[n], level[n]);
      },
      (from_levels + kBatch - 1) / kBatch);
  if (!meshes) return meshes.error();

  // A cluster the simplifier could not reduce below its objects' triangles is no use.
  for (size_t n = 0; n < node_count; ++n) {
    uint64_t triangles = 0;
    for (const SimplifiedPart& part : (*meshes)[n]) triangles += part.mesh.triangle_count();
    if (triangles == 0 || triangles >= full[n]) (*meshes)[n].clear();
  }
  const bool textured = !scene.uvs.empty();
  // Reserved whole: the meshes and the tree together stay about one tree's size.
  const PartSizes sizes = sizes_of(*meshes);
  if (!sizes.fit_uint32())
    return make_error("the scene's clusters need more than 2^32 vertices or indices");
  tree.vertices.reserve(sizes.vertices);
  if (textured) tree.uvs.reserve(sizes.vertices);
  tree.indices.reserve(sizes.indices);
  for (size_t n = 0; n < node_count; ++n) {
    ClusterNode& node = tree.nodes[n];
    node.parts_begin = uint32_t(tree.parts.size());
    float error = 0.0f;
    uint64_t triangles = 0;
    for (SimplifiedPart& part : (*meshes)[n]) {
      const uint32_t base = uint32_t(tree.vertices.size());
      error = std::max(error, part.error_m);
      if (part.mesh.indices.empty()) continue;  // simplified away: its error stands
      tree.parts.push_back({uint32_t(tree.indices.size()), uint32_t(part.mesh.indices.size()),
                            part.mesh.material, 0});
      triangles += part.mesh.triangle_count();
      tree.vertices.insert(tree.vertices.end(), part.mesh.vertices.begin(),
                           part.mesh.vertices.end());
      if (textured) {
        if (part.mesh.uvs.empty())
          tree.uvs.resize(tree.vertices.size());
        else
          tree.uvs.insert(tree.uvs.end(), part.mesh.uvs.begin(), part.mesh.uvs.end());
      }
      for (uint32_t v : part.mesh.indices) tree.indices.push_back(base + v);
    }
    (*meshes)[n] = {};
    node.parts_end = uint32_t(tree.parts.size());
    node.triangles = uint32_t(triangles);
    node.error_m = node.clustered() ? error : 0.0f;
  }
  // Errors made non-decreasing upwards (children come after their parent).
  for (size_t n = node_count; n-- > 0;) {
    ClusterNode& node = tree.nodes[n];
    if (!node.clustered()) continue;
    for (uint32_t c = 0; c < node.child_count; ++c)
      node.error_m = std::max(node.error_m, tree.nodes[node.first_child + c].error_m);
  }
  // The meshes were appended node by node: each page's nodes are a run of them.
  const NodePages paged = node_pages(tree.nodes);
  std::vector<uint32_t> index_ends;
  for (size_t p = 0; p < paged.first_node.size(); ++p) {
    const uint32_t end_node =
        p + 1 < paged.first_node.size() ? paged.first_node[p + 1] : uint32_t(node_count);
    uint32_t end = index_ends.empty() ? 0 : index_ends.back();
    for (uint32_t n = paged.first_node[p]; n < end_node; ++n)
      if (tree.nodes[n].clustered()) {
        const ClusterPart& last = tree.parts[tree.nodes[n].parts_end - 1];
        end = last.first_index + last.index_count;
      }
    index_ends.push_back(end);
  }
  tree.pages = pages_of_runs(tree.indices, uint32_t(tree.vertices.size()), index_ends);
  tree.node_page = paged.node_page;
  tree.bake_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return tree;
}

Result<void> save_cluster_tree(const ClusterTree& tree, Store& store) {
  auto transaction = store.begin();
  if (!transaction) return transaction.error();
  if (auto ok = store.put(kNodes, bytes_of(tree.nodes)); !ok) return ok;
  if (auto ok = store.put(kObjects, bytes_of(tree.objects)); !ok) return ok;
  if (auto ok = store.put(kParts, bytes_of(tree.parts)); !ok) return ok;
  if (auto erased = store.erase(std::string(kTreePagePrefix) + "_page"); !erased)
    return erased.error();
  if (auto ok = save_mesh_pages(store, kTreePagePrefix, tree.vertices, tree.uvs, tree.indices,
                                tree.pages);
      !ok)
    return ok;
  return transaction->commit();
}

Result<ClusterTree> load_cluster_tree(const Store& store, const Scene& scene,
                                      GeometryLoad geometry) {
  ClusterTree tree;
  auto nodes = read_array<ClusterNode>(store, kNodes);
  if (!nodes) return nodes.error();
  auto objects = read_array<uint32_t>(store, kObjects);
  if (!objects) return objects.error();
  auto parts = read_array<ClusterPart>(store, kParts);
  if (!parts) return parts.error();
  auto pages = load_mesh_page_table(store, kTreePagePrefix);
  if (!pages) return pages.error();
  auto inconsistent = [&](const char* what) {
    return make_error(store.path(), ": clusters bake is inconsistent (", what, ")");
  };
  if (objects->size() != scene.objects.size())
    return inconsistent("the hierarchy does not hold every object of the scene");
  std::vector<bool> seen(scene.objects.size(), false);
  for (uint32_t object : *objects) {
    if (object >= scene.objects.size() || seen[object])
      return inconsistent("the hierarchy's objects are not each of the scene once");
    seen[object] = true;
  }
  if (nodes->empty() != scene.objects.empty()) return inconsistent("no hierarchy");
  for (const ClusterPart& part : *parts)
    if (part.first_index % 3 != 0 || part.index_count % 3 != 0 || part.index_count == 0 ||
        part.material >= scene.materials.size())
      return inconsistent("a cluster's mesh");
  // Children after their parent, each node the child of one: the walk from the root ends
  // and meets every node once.
  std::vector<uint8_t> parents(nodes->size(), 0);
  for (size_t n = 0; n < nodes->size(); ++n) {
    const ClusterNode& node = (*nodes)[n];
    const bool children_ok =
        node.child_count == 0 ||
        (node.first_child > n && uint64_t(node.first_child) + node.child_count <= nodes->size());
    if (!children_ok) return inconsistent("a node's children");
    for (uint32_t c = 0; c < node.child_count; ++c)
      if (parents[node.first_child + c]++ > 0) return inconsistent("a node of two parents");
    if (node.objects_begin > node.own_end || node.own_end > node.objects_end ||
        node.objects_end > objects->size())
      return inconsistent("a node's objects");
    if (node.parts_begin > node.parts_end || node.parts_end > parts->size())
      return inconsistent("a node's parts");
    if (!(node.error_m >= 0.0f)) return inconsistent("a node's error");
  }
  NodePages paged = node_pages(*nodes);
  if (paged.first_node.size() != pages->size()) return inconsistent("the meshes' pages");
  for (size_t n = 0; n < nodes->size(); ++n) {
    const MeshPage& page = (*pages)[paged.node_page[n]];
    for (uint32_t p = (*nodes)[n].parts_begin; p < (*nodes)[n].parts_end; ++p)
      if (!page.holds((*parts)[p].first_index, (*parts)[p].index_count))
        return inconsistent("a cluster's mesh outside its page");
  }
  if (geometry == GeometryLoad::whole)
    if (auto read = read_mesh_pages(store, kTreePagePrefix, *pages, tree.vertices, tree.uvs,
                                    tree.indices);
        !read)
      return read.error();
  tree.nodes = std::move(*nodes);
  tree.objects = std::move(*objects);
  tree.parts = std::move(*parts);
  tree.pages = std::move(*pages);
  tree.node_page = std::move(paged.node_page);
  return tree;
}

}  // namespace farfield
