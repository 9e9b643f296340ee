// The cluster hierarchy (paper 001, Sec. 4.4) and the selection over it (Sec. 4.5), without
// GL: where objects lie, clusters' errors against measured distances, the pack, and the
// choices by error and under a budget on a small city.
#include "farfield/techniques/clusters/cluster_tree.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <glm/trigonometric.hpp>
#include <numeric>

#include "farfield/core/assert.hpp"
#include "farfield/core/progress.hpp"
#include "farfield/scene/city_generator.hpp"
#include "farfield/scene/simplify.hpp"
#include "farfield/spatial/occluders.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/clusters/cluster_selection.hpp"
#include "farfield/techniques/clusters/switch_fades.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// A city of 3 x 3 blocks (some hundred objects), made once.
const Scene& small_city() {
  static const Scene city = [] {
    Progress quiet(true);
    CityOptions o;
    o.blocks_x = o.blocks_z = 3;
    auto scene = generate_city(o, quiet);
    FF_ASSERT(scene.ok(), "city");
    return std::move(*scene);
  }();
  return city;
}

ClusterTreeOptions small_leaves() {
  ClusterTreeOptions o;
  o.leaf_objects = 6;
  return o;
}

// The hierarchy with its meshes, and the LODs under it, made once; and a hierarchy whose
// clusters of more than 5,000 triangles are made from the levels.
struct Baked {
  LodSet lods;
  ClusterTree tree, from_levels;
};
const Baked& baked() {
  static const Baked b = [] {
    Progress quiet(true);
    Baked out;
    auto lods = build_lod_set(small_city(), {}, quiet);
    FF_ASSERT(lods.ok(), "lods");
    out.lods = std::move(*lods);
    auto tree = build_cluster_tree(small_city(), small_leaves(), quiet);
    FF_ASSERT(tree.ok(), "tree");
    out.tree = std::move(*tree);
    ClusterTreeOptions bounded = small_leaves();
    bounded.input_triangles = 5000;
    auto from_levels =
        build_cluster_tree(small_city(), bounded, quiet, nullptr, nullptr, &out.lods);
    FF_ASSERT(from_levels.ok(), "tree from levels");
    out.from_levels = std::move(*from_levels);
    return out;
  }();
  return b;
}

bool within(const Bounds3& inner, const Bounds3& outer) {
  return glm::all(glm::greaterThanEqual(inner.min, outer.min)) &&
         glm::all(glm::lessThanEqual(inner.max, outer.max));
}

// The node each object lies at, and each node's parent.
std::vector<uint32_t> node_of_objects(const ClusterTree& tree, size_t objects) {
  std::vector<uint32_t> out(objects, UINT32_MAX);
  for (uint32_t n = 0; n < tree.nodes.size(); ++n)
    for (uint32_t k = tree.nodes[n].objects_begin; k < tree.nodes[n].own_end; ++k)
      out[tree.objects[k]] = n;
  return out;
}
std::vector<uint32_t> parents(const ClusterTree& tree) {
  std::vector<uint32_t> out(tree.nodes.size(), UINT32_MAX);
  for (uint32_t n = 0; n < tree.nodes.size(); ++n)
    for (uint32_t c = 0; c < tree.nodes[n].child_count; ++c) out[tree.nodes[n].first_child + c] = n;
  return out;
}

// Every object at one node, inside its bounds; a node's range holds its children's; a cell is
// split only when it holds more than leaf_objects; nodes with one child and nothing of their
// own do not exist.
TEST(ClusterTree, EveryObjectOnceInsideItsNode) {
  const Scene& scene = small_city();
  const ClusterTree tree = build_cluster_cells(scene, small_leaves());
  ASSERT_GT(tree.nodes.size(), 8u);
  std::vector<uint32_t> sorted = tree.objects;
  std::sort(sorted.begin(), sorted.end());
  std::vector<uint32_t> all(scene.objects.size());
  std::iota(all.begin(), all.end(), 0u);
  EXPECT_EQ(sorted, all);
  EXPECT_EQ(tree.nodes[0].objects_begin, 0u);
  EXPECT_EQ(tree.nodes[0].objects_end, scene.objects.size());
  size_t inner_with_own = 0;
  for (uint32_t n = 0; n < tree.nodes.size(); ++n) {
    const ClusterNode& node = tree.nodes[n];
    for (uint32_t k = node.objects_begin; k < node.own_end; ++k)
      EXPECT_TRUE(within(scene.objects[tree.objects[k]].bounds, node.bounds));
    if (node.leaf()) {
      EXPECT_EQ(node.own_end, node.objects_end);
      continue;
    }
    EXPECT_GT(node.objects_end - node.objects_begin, 6u);
    EXPECT_FALSE(node.child_count == 1 && node.own_end == node.objects_begin) << n;
    inner_with_own += node.own_end > node.objects_begin;
    uint32_t next = node.own_end;
    for (uint32_t c = 0; c < node.child_count; ++c) {
      const ClusterNode& child = tree.nodes[node.first_child + c];
      EXPECT_TRUE(within(child.bounds, node.bounds));
      EXPECT_EQ(child.objects_begin, next);  // depth first: the children's ranges in a row
      next = child.objects_end;
    }
    EXPECT_EQ(next, node.objects_end);
  }
  EXPECT_GT(inner_with_own, 0u);  // streets and curbs across cells stay higher up
}

// A loose octree keeps fewer objects up in the hierarchy than the paper's exact cells, which
// keep every object across a cell's middle in that cell (the city's streets across its middle
// lines at the root), and the paper's rule stays reachable.
TEST(ClusterTree, LooseCellsHoldFewerObjectsHighUp) {
  const Scene& scene = small_city();
  auto own_above_leaves = [&](float loose) {
    ClusterTreeOptions o = small_leaves();
    o.loose = loose;
    const ClusterTree tree = build_cluster_cells(scene, o);
    size_t own = 0;
    for (const ClusterNode& node : tree.nodes)
      if (!node.leaf()) own += node.own_end - node.objects_begin;
    return own;
  };
  const size_t paper = own_above_leaves(0.0f), loose = own_above_leaves(0.5f);
  EXPECT_GT(paper, 0u);
  EXPECT_LT(loose, paper / 2);
}

// A cluster's stored error bounds the distance between its mesh and its objects both ways
// (measured at random points) and never falls below its children's; its mesh has at most
// clusters_triangles and half of its objects' triangles (a little more where the simplifier
// misses its target, never as many as its objects); clusters only where two objects lie
// inside. The same where the largest clusters are made from the levels (their error then
// includes the levels').
void expect_clusters_bound_their_distance(const ClusterTree& tree) {
  const Scene& scene = small_city();
  size_t clusters = 0;
  for (uint32_t n = 0; n < tree.nodes.size(); ++n) {
    const ClusterNode& node = tree.nodes[n];
    if (!node.clustered()) continue;
    ++clusters;
    EXPECT_GE(node.objects_end - node.objects_begin, 2u);
    uint64_t full = 0;
    for (uint32_t k = node.objects_begin; k < node.objects_end; ++k)
      full += scene.objects[tree.objects[k]].index_count / 3;
    EXPECT_LE(node.triangles, 1.25 * std::min<double>(2048.0, double(full) / 2) + 2) << n;
    EXPECT_LT(node.triangles, full);
    for (uint32_t c = 0; c < node.child_count; ++c)
      EXPECT_GE(node.error_m, tree.nodes[node.first_child + c].error_m);
    if (n % 5 != 0) continue;  // distances on a fifth of the clusters: enough, and fast
    const std::span<const uint32_t> objects(tree.objects.data() + node.objects_begin,
                                            node.objects_end - node.objects_begin);
    for (uint32_t p = node.parts_begin; p < node.parts_end; ++p) {
      const ClusterPart& part = tree.parts[p];
      const MeshPart full = gather_part(scene, objects, part.material);
      MeshPart mesh;
      mesh.vertices = tree.vertices;
      mesh.indices.assign(tree.indices.begin() + part.first_index,
                          tree.indices.begin() + part.first_index + part.index_count);
      const float slack = 1e-3f * (1.0f + node.error_m);
      EXPECT_LE(farthest_distance(test::random_surface_points(mesh, 500, n), full),
                node.error_m + slack);
      EXPECT_LE(farthest_distance(test::random_surface_points(full, 500, n + 1), mesh),
                node.error_m + slack);
    }
  }
  EXPECT_GT(clusters, 4u);
}

TEST(ClusterTree, ClusterErrorsBoundTheirDistanceAndGrowUpwards) {
  expect_clusters_bound_their_distance(baked().tree);
}

TEST(ClusterTree, ClustersFromTheLevelsBoundTheirDistanceToo) {
  const Baked& b = baked();
  expect_clusters_bound_their_distance(b.from_levels);
  // The largest clusters differ (they come from other triangles); the smaller are the same.
  size_t differ = 0, same = 0;
  ASSERT_EQ(b.from_levels.nodes.size(), b.tree.nodes.size());
  for (uint32_t n = 0; n < b.tree.nodes.size(); ++n) {
    const ClusterNode &full = b.tree.nodes[n], &levels = b.from_levels.nodes[n];
    if (!full.clustered()) continue;
    uint64_t triangles = 0;
    for (uint32_t k = full.objects_begin; k < full.objects_end; ++k)
      triangles += small_city().objects[b.tree.objects[k]].index_count / 3;
    if (triangles > 5000)
      differ += levels.error_m != full.error_m || levels.triangles != full.triangles;
    else
      same += levels.error_m == full.error_m && levels.triangles == full.triangles;
  }
  EXPECT_GT(differ, 0u);
  EXPECT_GT(same, 0u);
}

TEST(ClusterTree, KeptInAPackAndRefusedWhenDamaged) {
  const Scene& scene = small_city();
  const ClusterTree& tree = baked().tree;
  test::TempDir dir;
  {
    auto store = Store::open(dir.file("p.ffpack"), Store::Mode::kReadWrite);
    ASSERT_TRUE(store);
    ASSERT_TRUE(save_cluster_tree(tree, *store));
  }
  auto store = Store::open(dir.file("p.ffpack"), Store::Mode::kReadWrite);
  ASSERT_TRUE(store);
  auto back = load_cluster_tree(*store, scene);
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_TRUE(test::same_bytes(back->nodes, tree.nodes));
  EXPECT_EQ(back->objects, tree.objects);
  EXPECT_TRUE(test::same_bytes(back->parts, tree.parts));
  EXPECT_EQ(back->indices, tree.indices);
  EXPECT_EQ(back->node_page, tree.node_page);
  ASSERT_EQ(back->pages.size(), tree.pages.size());
  // Page 0 the root's cluster, then each node's children's, breadth first.
  uint32_t pages = 1;
  EXPECT_EQ(tree.node_page[0], 0u);
  for (const ClusterNode& node : tree.nodes)
    if (node.child_count > 0) {
      for (uint32_t c = 0; c < node.child_count; ++c)
        EXPECT_EQ(tree.node_page[node.first_child + c], pages);
      ++pages;
    }
  EXPECT_EQ(pages, tree.pages.size());
  for (size_t n = 0; n < tree.nodes.size(); ++n)
    for (uint32_t p = tree.nodes[n].parts_begin; p < tree.nodes[n].parts_end; ++p)
      EXPECT_TRUE(tree.pages[tree.node_page[n]].holds(tree.parts[p].first_index,
                                                      tree.parts[p].index_count));
  EXPECT_FALSE(load_cluster_tree(*store, test::make_box_row(2)));  // another scene's
  auto refused = [&](const char* blob, auto records, const char* why) {
    ASSERT_TRUE(store->put(blob, std::as_bytes(std::span(records))));
    auto damaged = load_cluster_tree(*store, scene);
    ASSERT_FALSE(damaged) << why;
    EXPECT_NE(damaged.error().message.find("p.ffpack"), std::string::npos);
    EXPECT_NE(damaged.error().message.find(why), std::string::npos) << damaged.error().message;
    ASSERT_TRUE(save_cluster_tree(tree, *store));
  };
  std::vector<ClusterNode> nodes = tree.nodes;
  nodes[1].first_child = 0;  // a cycle
  nodes[1].child_count = 1;
  refused("clusters/tree_nodes", nodes, "children");
  nodes = tree.nodes;
  nodes.push_back(nodes.back());  // a second parent's children: drawn twice
  nodes.back().first_child = nodes[0].first_child;
  nodes.back().child_count = 1;
  refused("clusters/tree_nodes", nodes, "children");
  std::vector<uint32_t> objects = tree.objects;
  objects[1] = objects[0];
  refused("clusters/tree_objects", objects, "each of the scene once");
  std::vector<ClusterPart> parts = tree.parts;
  parts[0].material = uint32_t(scene.materials.size());
  refused("clusters/tree_parts", parts, "a cluster's mesh");
  // A root's mesh moved into the last page: outside its own.
  parts = tree.parts;
  ASSERT_TRUE(tree.nodes[0].clustered() && tree.pages.size() > 2);
  parts[tree.nodes[0].parts_begin].first_index = tree.pages.back().first_index;
  parts[tree.nodes[0].parts_begin].index_count = 3;
  refused("clusters/tree_parts", parts, "outside its page");
}

// A view of the small city from a corner, looking in along its diagonal.
View corner_view(float height) {
  const Bounds3& b = small_city().bounds;
  View v;
  v.pose.position = glm::vec3(b.min.x - 10.0f, height, b.min.z - 10.0f);
  v.pose.yaw_deg = 45.0f;
  v.pose.pitch_deg = height > 50.0f ? -20.0f : 0.0f;
  return v;
}

float pixel_of(const View& v) {
  return 2.0f * std::tan(glm::radians(v.hfov_deg) * 0.5f) / float(v.width);
}

// Every object the frustum sees is drawn exactly once: itself (a level or whole) or by the
// cluster of one node above it; nothing out of view is drawn on its own. With an occlusion
// map: nothing it hides is drawn, what it hides is covered at most once; returns the objects
// in view that it hides.
int expect_complete(const std::vector<Choice>& choices, const Frustum& frustum,
                    const OcclusionMap* map = nullptr, const BoxSet* boxes = nullptr) {
  const Scene& scene = small_city();
  const Baked& b = baked();
  const std::vector<uint32_t> at = node_of_objects(b.tree, scene.objects.size());
  const std::vector<uint32_t> up = parents(b.tree);
  auto hidden = [&](const Bounds3& box) { return map && map->hidden(box); };
  std::vector<int> drawn(scene.objects.size(), 0);
  std::vector<bool> cluster_drawn(b.tree.nodes.size(), false);
  std::vector<uint32_t> box_node, box_object;  // what each box stands for
  if (boxes) {
    box_node.assign(boxes->boxes.size(), UINT32_MAX);
    box_object.assign(boxes->boxes.size(), UINT32_MAX);
    for (uint32_t n = 0; n < boxes->node_box.size(); ++n)
      if (boxes->node_box[n] != BoxSet::kNone) box_node[boxes->node_box[n]] = n;
    for (uint32_t o = 0; o < boxes->object_box.size(); ++o)
      if (boxes->object_box[o] != BoxSet::kNone) box_object[boxes->object_box[o]] = o;
  }
  for (const Choice& c : choices) {
    uint32_t node = c.kind == Choice::Kind::cluster ? c.index : UINT32_MAX;
    const bool box = c.kind == Choice::Kind::box || c.kind == Choice::Kind::average;
    if (box) {
      EXPECT_TRUE(boxes) << "a box chosen where there are none";
      if (!boxes) continue;
      node = box_node[c.index];
    }
    if (node != UINT32_MAX) {
      EXPECT_FALSE(hidden(b.tree.nodes[node].bounds)) << "node " << node;
      EXPECT_FALSE(cluster_drawn[node]) << "node " << node << " twice";
      cluster_drawn[node] = true;
      continue;
    }
    const uint32_t o = c.kind == Choice::Kind::whole ? c.index
                       : box                         ? box_object[c.index]
                                                     : b.lods.lods[c.index].object;
    EXPECT_FALSE(hidden(scene.objects[o].bounds)) << "object " << o;
    ++drawn[o];
  }
  int behind = 0;
  for (uint32_t o = 0; o < scene.objects.size(); ++o) {
    int covered = drawn[o];
    for (uint32_t n = at[o]; n != UINT32_MAX; n = up[n]) covered += cluster_drawn[n];
    if (frustum.classify(scene.objects[o].bounds) == Visibility::none) {
      EXPECT_EQ(drawn[o], 0) << o;
    } else if (hidden(scene.objects[o].bounds)) {
      ++behind;
      EXPECT_LE(covered, 1) << "object " << o;
    } else {
      EXPECT_EQ(covered, 1) << "object " << o;
    }
  }
  return behind;
}

// By error: the choices cover what is seen once each, and their errors stay under the pixels
// asked; a looser error draws fewer triangles. Both traversals choose the same, the paper's
// looking at every node and object.
TEST(ClusterSelection, ByErrorCompleteWithinTheErrorAndTheTraversalsAgree) {
  const Scene& scene = small_city();
  const Baked& b = baked();
  ClusterSelection selection(scene, b.tree, b.lods);
  for (float height : {2.0f, 300.0f}) {
    const View view = corner_view(height);
    const Frustum frustum(view);
    uint64_t previous = UINT64_MAX;
    for (float error_px : {0.5f, 2.0f, 8.0f, 64.0f}) {
      SCOPED_TRACE(testing::Message() << height << " m, " << error_px << " px");
      SelectionView sv{&frustum, view.pose.position, pixel_of(view), std::nullopt, error_px, -1.0};
      std::vector<Choice> refined, paper;
      const SelectionStats r = selection.select(sv, ClusterTraversal::refined, refined);
      const SelectionStats p = selection.select(sv, ClusterTraversal::paper, paper);
      expect_complete(refined, frustum);
      EXPECT_LE(r.largest_error_px, error_px);
      EXPECT_LE(r.triangles, previous);
      previous = r.triangles;
      ASSERT_EQ(refined.size(), paper.size());
      for (size_t i = 0; i < refined.size(); ++i) {
        EXPECT_EQ(refined[i].kind, paper[i].kind);
        EXPECT_EQ(refined[i].index, paper[i].index);
      }
      EXPECT_EQ(p.nodes_visited, b.tree.nodes.size() + scene.objects.size());
      EXPECT_LE(r.nodes_visited, p.nodes_visited);
      if (error_px >= 8.0f) {
        EXPECT_LT(r.nodes_visited, p.nodes_visited);  // clusters stop the walk early
      }
    }
  }
}

// Under a budget of triangles: complete at every budget, within it wherever the root's
// cluster fits (refinements that cost nothing are taken even over it), never less accurate
// (largest projected error) with a larger budget, and everything whole once the budget
// affords it.
TEST(ClusterSelection, UnderABudgetCompleteWithinItAndBetterWithMore) {
  const Scene& scene = small_city();
  const Baked& b = baked();
  ClusterSelection selection(scene, b.tree, b.lods);
  const View view = corner_view(2.0f);
  const Frustum frustum(view);
  SelectionView sv{&frustum, view.pose.position, pixel_of(view), std::nullopt, 1.0f, 0.0};
  std::vector<Choice> choices;
  const uint64_t cheapest = selection.select(sv, ClusterTraversal::refined, choices).triangles;
  expect_complete(choices, frustum);
  EXPECT_LE(cheapest, b.tree.nodes[0].triangles);
  float previous_error = INFINITY;
  for (double budget : {1e3, 5e3, 2e4, 5e4, 1e5, 1e7}) {
    SCOPED_TRACE(testing::Message() << budget << " triangles");
    sv.max_triangles = budget;
    const SelectionStats s = selection.select(sv, ClusterTraversal::refined, choices);
    expect_complete(choices, frustum);
    EXPECT_LE(double(s.triangles), std::max(budget, double(b.tree.nodes[0].triangles)));
    EXPECT_LE(s.largest_error_px, previous_error);
    std::vector<Choice> paper;
    EXPECT_EQ(selection.select(sv, ClusterTraversal::paper, paper).triangles, s.triangles);
    previous_error = s.largest_error_px;
  }
  EXPECT_EQ(previous_error, 0.0f);  // 10^7 triangles: every object in view whole
}

// Boxes with an error of a twentieth of their size for every cluster and every object of 32
// triangles or more (selection reads no pixels): 12 triangles each.
BoxSet synthetic_boxes(const Scene& scene, const ClusterTree& tree) {
  BoxSet set;
  set.object_box.assign(scene.objects.size(), BoxSet::kNone);
  set.node_box.assign(tree.nodes.size(), BoxSet::kNone);
  auto add = [&](const Bounds3& bounds) {
    TexturedBox box;
    box.bounds = bounds;
    const glm::vec3 s = bounds.size();
    box.error_m = 0.05f * std::max({s.x, s.y, s.z});
    for (BoxSide& side : box.sides) side = {0, 0, 4, 4};
    set.boxes.push_back(box);
    return uint32_t(set.boxes.size() - 1);
  };
  for (uint32_t n = 0; n < tree.nodes.size(); ++n)
    if (tree.nodes[n].clustered()) set.node_box[n] = add(tree.nodes[n].bounds);
  for (uint32_t o = 0; o < scene.objects.size(); ++o)
    if (scene.objects[o].index_count / 3 >= 32) set.object_box[o] = add(scene.objects[o].bounds);
  return set;
}

// Boxes are a node's and an object's coarsest representation: by error the choices stay
// complete and within the error, boxes drawn where their error allows, and fewer triangles
// than without them; under a budget complete at every budget, a tight one met with boxes, and
// everything whole once the budget affords it.
TEST(ClusterSelection, BoxesStandForTheirNodesAndObjects) {
  const Scene& scene = small_city();
  const Baked& b = baked();
  const BoxSet boxes = synthetic_boxes(scene, b.tree);
  ClusterSelection with(scene, b.tree, b.lods, &boxes), without(scene, b.tree, b.lods);
  auto count_boxes = [](const std::vector<Choice>& choices) {
    return std::count_if(choices.begin(), choices.end(),
                         [](const Choice& c) { return c.kind == Choice::Kind::box; });
  };
  for (float height : {2.0f, 300.0f}) {
    const View view = corner_view(height);
    const Frustum frustum(view);
    for (float error_px : {2.0f, 64.0f}) {
      SCOPED_TRACE(testing::Message() << height << " m, " << error_px << " px");
      SelectionView sv{&frustum, view.pose.position, pixel_of(view), std::nullopt, error_px, -1.0};
      std::vector<Choice> a, c;
      const SelectionStats s = with.select(sv, ClusterTraversal::refined, a);
      expect_complete(a, frustum, nullptr, &boxes);
      EXPECT_LE(s.largest_error_px, error_px);
      EXPECT_LE(s.triangles, without.select(sv, ClusterTraversal::refined, c).triangles);
      if (error_px == 64.0f) {
        EXPECT_GT(count_boxes(a), 0);
      }
      std::vector<Choice> paper;
      EXPECT_EQ(with.select(sv, ClusterTraversal::paper, paper).triangles, s.triangles);
    }
    SelectionView sv{&frustum, view.pose.position, pixel_of(view), std::nullopt, 1.0f, 0.0};
    for (double budget : {3e2, 5e3, 5e4, 1e7}) {
      SCOPED_TRACE(testing::Message() << height << " m, " << budget << " triangles");
      sv.max_triangles = budget;
      std::vector<Choice> choices;
      const SelectionStats s = with.select(sv, ClusterTraversal::refined, choices);
      expect_complete(choices, frustum, nullptr, &boxes);
      if (budget == 3e2) {
        EXPECT_GT(count_boxes(choices), 0);
        std::vector<Choice> plain;
        EXPECT_LE(s.triangles, without.select(sv, ClusterTraversal::refined, plain).triangles);
      }
      if (budget == 1e7) {
        EXPECT_EQ(count_boxes(choices), 0);
        EXPECT_EQ(s.largest_error_px, 0.0f);
      }
    }
  }
}

// Average-colour boxes take the place of the boxes whose subjects project below average_px
// (by error, below error_px too, so that the error stays within it); nothing else changes:
// the same triangles, still complete. average_px 0, or a selection told there are none: none.
TEST(ClusterSelection, AverageBoxesStandForBoxesOfFewPixels) {
  const Scene& scene = small_city();
  const Baked& b = baked();
  const BoxSet boxes = synthetic_boxes(scene, b.tree);
  ClusterSelection with(scene, b.tree, b.lods, &boxes, true), plain(scene, b.tree, b.lods, &boxes);
  const View view = corner_view(300.0f);
  const Frustum frustum(view);
  const float pixel = pixel_of(view);
  auto across_px = [&](uint32_t box) {
    const Bounds3& bounds = boxes.boxes[box].bounds;
    return glm::length(bounds.size()) /
           (std::max(distance_to(bounds, view.pose.position), 1e-3f) * pixel);
  };
  int64_t most = 0;
  for (double budget : {-1.0, 3e2, 5e3}) {
    for (float average_px : {0.0f, 8.0f, 1e4f}) {
      SCOPED_TRACE(testing::Message() << budget << " triangles, " << average_px << " px");
      SelectionView sv{&frustum, view.pose.position, pixel, std::nullopt, 64.0f, budget};
      sv.average_px = average_px;
      std::vector<Choice> a, p;
      const SelectionStats s = with.select(sv, ClusterTraversal::refined, a);
      const SelectionStats ps = plain.select(sv, ClusterTraversal::refined, p);
      expect_complete(a, frustum, nullptr, &boxes);
      EXPECT_EQ(s.triangles, ps.triangles);
      ASSERT_EQ(a.size(), p.size());
      const float limit = budget < 0 ? std::min(average_px, 64.0f) : average_px;
      int64_t averages = 0;
      for (size_t i = 0; i < a.size(); ++i) {
        EXPECT_NE(p[i].kind, Choice::Kind::average);
        if (p[i].kind != Choice::Kind::box) {
          EXPECT_EQ(a[i].kind, p[i].kind);
          continue;
        }
        EXPECT_EQ(a[i].index, p[i].index);
        const bool small = across_px(p[i].index) <= limit;
        EXPECT_EQ(a[i].kind, small ? Choice::Kind::average : Choice::Kind::box) << i;
        averages += small;
      }
      if (budget < 0) {
        EXPECT_LE(s.largest_error_px, 64.0f);
      }
      most = std::max(most, averages);
    }
  }
  EXPECT_GT(most, 10);
}

// Blended switches: a node refined fades its cluster out and what is drawn beneath it in,
// a share a frame; a node coarsened fades what was drawn beneath it out; a switch above a
// fading node ends its fade; choices elsewhere are drawn whole.
TEST(SwitchFades, AFadeMovesTheOldToTheNewAShareAFrame) {
  const Scene& scene = small_city();
  const Baked& b = baked();
  const BoxSet boxes = synthetic_boxes(scene, b.tree);
  // A clustered child of the root with objects of its own.
  uint32_t node = UINT32_MAX;
  const ClusterNode& root = b.tree.nodes[0];
  for (uint32_t c = root.first_child; c < root.first_child + root.child_count; ++c)
    if (b.tree.nodes[c].clustered() && b.tree.nodes[c].own_end > b.tree.nodes[c].objects_begin)
      node = c;
  ASSERT_NE(node, UINT32_MAX);
  const ClusterNode& n = b.tree.nodes[node];
  const uint32_t other = b.tree.nodes[root.first_child].clustered() && root.first_child != node
                             ? root.first_child
                             : root.first_child + 1;
  const Choice elsewhere{Choice::Kind::cluster, other};
  std::vector<Choice> coarse = {{Choice::Kind::cluster, node}, elsewhere}, fine = {elsewhere};
  for (uint32_t k = n.objects_begin; k < n.own_end; ++k)
    fine.push_back({Choice::Kind::whole, b.tree.objects[k]});
  for (uint32_t c = n.first_child; c < n.first_child + n.child_count; ++c)
    fine.push_back({Choice::Kind::cluster, c});
  constexpr int kFrames = 3;
  SwitchFades fades(b.tree, b.lods, boxes, scene.objects.size(), kFrames);
  fades.update({}, coarse);
  EXPECT_EQ(fades.active(), 0u);
  EXPECT_EQ(fades.coverage(coarse[0]), 1.0f);
  const ClusterSelection::NodeSwitch refined[] = {{node, true}};
  fades.update(refined, fine);
  for (int step = 1; step <= kFrames; ++step) {
    SCOPED_TRACE(step);
    const float share = float(step) / float(kFrames + 1);
    ASSERT_EQ(fades.fading_out().size(), 1u);
    EXPECT_EQ(fades.fading_out()[0].choice.index, node);
    EXPECT_FLOAT_EQ(fades.fading_out()[0].coverage, share);
    for (size_t i = 1; i < fine.size(); ++i) EXPECT_FLOAT_EQ(fades.coverage(fine[i]), share);
    EXPECT_EQ(fades.coverage(elsewhere), 1.0f);
    fades.update({}, fine);
  }
  EXPECT_EQ(fades.active(), 0u);
  EXPECT_TRUE(fades.fading_out().empty());
  EXPECT_EQ(fades.coverage(fine[1]), 1.0f);
  // Back to the cluster: everything drawn beneath it fades out.
  const ClusterSelection::NodeSwitch coarsened[] = {{node, false}};
  fades.update(coarsened, coarse);
  EXPECT_EQ(fades.fading_out().size(), fine.size() - 1);
  EXPECT_FLOAT_EQ(fades.coverage(coarse[0]), 1.0f / (kFrames + 1));
  // The root refined (a switch above the fading node) ends that fade and starts its own.
  const ClusterSelection::NodeSwitch root_refined[] = {{0, true}};
  fades.update(root_refined, coarse);
  EXPECT_EQ(fades.active(), 1u);
  EXPECT_EQ(fades.fading_out().size(), coarse.size());  // the root's last choices: all
}

// With accuracy tables, a representation's error is the one of the direction it is seen
// from: a table of no error towards the corner view and a huge one away from it draws the
// root's cluster alone (and, where errors below the tables' finest texel give way to the
// geometric ones, what the geometric errors draw); the same table turned round draws every
// object in view whole.
TEST(ClusterSelection, ImageErrorsAreThoseOfTheDirectionSeenFrom) {
  const Scene& scene = small_city();
  const Baked& b = baked();
  ClusterSelection selection(scene, b.tree, b.lods);
  const View view = corner_view(2.0f);
  const Frustum frustum(view);
  for (bool towards : {true, false}) {
    SCOPED_TRACE(towards ? "exact towards the eye" : "exact away from it");
    AccuracyTable table;
    table.directions = {glm::normalize(glm::vec3(-1, 0, -1)), glm::normalize(glm::vec3(1, 0, 1))};
    auto fill = [&](std::vector<float>& errors, size_t count) {
      for (size_t i = 0; i < count; ++i) {
        errors.push_back(towards ? 0.0f : 1e6f);
        errors.push_back(towards ? 1e6f : 0.0f);
      }
    };
    fill(table.lod_error, b.lods.lods.size());
    fill(table.node_error, b.tree.nodes.size());
    SelectionView sv{&frustum, view.pose.position, pixel_of(view), std::nullopt, 1.0f, -1.0};
    sv.accuracy = &table;
    std::vector<Choice> choices;
    selection.select(sv, ClusterTraversal::refined, choices);
    expect_complete(choices, frustum);
    if (towards) {
      ASSERT_EQ(choices.size(), 1u);
      EXPECT_EQ(choices[0].kind, Choice::Kind::cluster);
      // Errors of 0 lie below any texel of the tables' finest comparison: told that it had
      // 64 texels across each subject, the selection takes the geometric errors instead,
      // the same as without the table.
      sv.accuracy_finest_px = 64.0f;
      std::vector<Choice> below, geometric;
      selection.select(sv, ClusterTraversal::refined, below);
      sv.accuracy = nullptr;
      selection.select(sv, ClusterTraversal::refined, geometric);
      EXPECT_GT(below.size(), 1u);
      ASSERT_EQ(below.size(), geometric.size());
      for (size_t i = 0; i < below.size(); ++i) EXPECT_EQ(below[i].index, geometric[i].index);
    } else {
      for (const Choice& c : choices) EXPECT_EQ(c.kind, Choice::Kind::whole);
    }
  }
}

// The benefit (paper 001, Sec. 3.1) orders refinements: weighted to the focus, a tight budget
// spends more of its triangles near the line of sight than the projected error alone does,
// the choices stay complete and the largest error reported is still the projected one.
TEST(ClusterSelection, TheBenefitSpendsTheBudgetNearTheLineOfSight) {
  const Scene& scene = small_city();
  const Baked& b = baked();
  ClusterSelection selection(scene, b.tree, b.lods);
  const View view = corner_view(300.0f);
  const Frustum frustum(view);
  const glm::vec3 forward = view.pose.forward();
  auto central = [&](const std::vector<Choice>& choices) {
    uint64_t triangles = 0;
    for (const Choice& c : choices) {
      if (c.kind == Choice::Kind::cluster) continue;
      const uint32_t o = c.kind == Choice::Kind::whole ? c.index : b.lods.lods[c.index].object;
      const glm::vec3 to = glm::normalize(scene.objects[o].bounds.center() - view.pose.position);
      if (glm::dot(to, forward) > std::cos(glm::radians(15.0f)))
        triangles += c.kind == Choice::Kind::whole ? scene.objects[o].index_count / 3
                                                   : b.lods.lods[c.index].index_count / 3;
    }
    return triangles;
  };
  int more = 0;
  for (double budget : {5e3, 2e4, 5e4}) {
    SCOPED_TRACE(testing::Message() << budget << " triangles");
    SelectionView sv{&frustum, view.pose.position, pixel_of(view), std::nullopt, 1.0f, budget};
    sv.forward = forward;
    sv.width_px = float(view.width);
    std::vector<Choice> plain, focused;
    selection.select(sv, ClusterTraversal::refined, plain);
    sv.benefit.focus = 1.0f;
    const SelectionStats s = selection.select(sv, ClusterTraversal::refined, focused);
    expect_complete(focused, frustum);
    EXPECT_GE(central(focused), central(plain));
    more += central(focused) > central(plain);
    EXPECT_GT(s.largest_error_px, 0.0f);
  }
  EXPECT_GT(more, 0);
}

// Temporal coherence (paper 001, Sec. 4.6): a budget that swings every frame between two
// values flips clusters into their children and back every frame without hysteresis, never
// with the paper's rule, under half as often with the default one (only flips wait); the first
// frame (a jump: nothing drawn before) refines at once, as without.
TEST(ClusterSelection, HysteresisHoldsRefinementsBackForFramesInARow) {
  const Scene& scene = small_city();
  const Baked& b = baked();
  const View view = corner_view(2.0f);
  const Frustum frustum(view);
  auto play = [&](int hysteresis, const std::vector<double>& budgets, uint64_t* switches,
                  HysteresisRule rule = HysteresisRule::paper) {
    ClusterSelection selection(scene, b.tree, b.lods);
    SelectionView sv{&frustum, view.pose.position, pixel_of(view), std::nullopt, 1.0f, 0.0};
    sv.hysteresis = hysteresis;
    sv.hysteresis_rule = rule;
    std::vector<std::vector<Choice>> frames;
    *switches = 0;
    for (double budget : budgets) {
      sv.max_triangles = budget;
      frames.emplace_back();
      *switches += selection.select(sv, ClusterTraversal::refined, frames.back()).switches;
    }
    return frames;
  };
  std::vector<double> swinging;
  for (int f = 0; f < 12; ++f) swinging.push_back(f % 2 ? 2e4 : 3e3);
  uint64_t without = 0, with = 0;
  play(0, swinging, &without);
  const auto held = play(3, swinging, &with);
  EXPECT_GE(without, 10u);
  EXPECT_EQ(with, 0u);
  for (const auto& frame : held) EXPECT_EQ(frame.size(), held[0].size());
  // The default rule lets a first refinement through and holds the flip back for 3 frames.
  uint64_t flips = 0;
  play(3, swinging, &flips, HysteresisRule::flips);
  EXPECT_GT(flips, 0u);
  EXPECT_LE(2 * flips, without);

  const std::vector<double> steady(4, 2e4);
  uint64_t s0 = 0, s3 = 0;
  const auto at_once = play(0, steady, &s0);
  const auto held_too = play(3, steady, &s3);
  EXPECT_EQ(s0, 0u);  // one complete choice from the first frame on
  EXPECT_EQ(s3, 0u);
  ASSERT_EQ(held_too[0].size(), at_once[0].size());
  for (size_t i = 0; i < at_once[0].size(); ++i)
    EXPECT_EQ(held_too[0][i].index, at_once[0][i].index);
}

// For a near region (composed under another technique's far field) only what meets the
// region is drawn, and a cluster only where its node lies inside it.
// With an occlusion map: nothing drawn that the map hides, and everything else seen still
// drawn once; fewer triangles than without.
TEST(ClusterSelection, WhatTheOcclusionMapHidesIsNotDrawn) {
  const Scene& scene = small_city();
  const Baked& b = baked();
  ClusterSelection selection(scene, b.tree, b.lods);
  const View view = corner_view(2.0f);
  const Frustum frustum(view);
  Occluders occluders(scene);
  OcclusionMap map;
  occluders.fill(map, view, frustum);
  ASSERT_GT(map.occluders(), 0u);
  SelectionView sv{&frustum, view.pose.position, pixel_of(view), std::nullopt, 0.5f, -1.0};
  std::vector<Choice> open, occluded;
  const uint64_t all = selection.select(sv, ClusterTraversal::refined, open).triangles;
  sv.occlusion = &map;
  const uint64_t some = selection.select(sv, ClusterTraversal::refined, occluded).triangles;
  EXPECT_LT(some, all);
  EXPECT_GT(expect_complete(occluded, frustum, &map), 0);
}

TEST(ClusterSelection, ANearRegionDrawsWhatMeetsIt) {
  const Scene& scene = small_city();
  const Baked& b = baked();
  ClusterSelection selection(scene, b.tree, b.lods);
  const View view = corner_view(300.0f);
  const Frustum frustum(view);
  Bounds3 region = scene.bounds;
  region.max.x = region.min.x + 0.5f * (region.max.x - region.min.x);
  for (float error_px : {1.0f, 1000.0f}) {
    SelectionView sv{&frustum, view.pose.position, pixel_of(view), region, error_px, -1.0};
    std::vector<Choice> choices;
    selection.select(sv, ClusterTraversal::refined, choices);
    ASSERT_FALSE(choices.empty());
    for (const Choice& c : choices) {
      if (c.kind == Choice::Kind::cluster)
        EXPECT_TRUE(within(b.tree.nodes[c.index].bounds, region));
      else
        EXPECT_TRUE(meet(
            scene.objects[c.kind == Choice::Kind::whole ? c.index : b.lods.lods[c.index].object]
                .bounds,
            region));
    }
  }
}

}  // namespace
}  // namespace farfield
