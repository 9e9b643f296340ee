// Frustum tests, the octree and the octree technique, without GL.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "farfield/core/frustum.hpp"
#include "farfield/spatial/octree.hpp"
#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

View looking_along_x() {
  View v;
  v.pose.position = {0, 0, 0};
  v.pose.yaw_deg = 0;
  return v;
}

Bounds3 box(glm::vec3 lo, glm::vec3 hi) {
  Bounds3 b;
  b.min = lo;
  b.max = hi;
  return b;
}

// True when some point of the box is in front of the near plane and projects on screen.
bool any_point_visible(const View& view, const Bounds3& b, std::mt19937& rng) {
  const glm::mat4 vp = view.view_projection();
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 400; ++i) {
    glm::vec3 t(u(rng), u(rng), u(rng));
    if (i < 8) t = glm::vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1);
    const glm::vec3 p = b.min + t * (b.max - b.min);
    const glm::vec4 c = vp * glm::vec4(p, 1.0f);
    if (c.w > view.near_m && std::abs(c.x) <= c.w && std::abs(c.y) <= c.w) return true;
  }
  return false;
}

TEST(Frustum, ClassifiesBoxesInsideOutsideAndAcross) {
  const Frustum f(looking_along_x());
  EXPECT_EQ(f.classify(box({10, -1, -1}, {12, 1, 1})), Visibility::full);
  EXPECT_EQ(f.classify(box({-12, -1, -1}, {-10, 1, 1})), Visibility::none);        // behind
  EXPECT_EQ(f.classify(box({10, -1, 30}, {12, 1, 32})), Visibility::none);         // far right
  EXPECT_EQ(f.classify(box({10, -1, 5}, {12, 1, 15})), Visibility::partial);       // on the edge
  EXPECT_EQ(f.classify(box({-1, -1, -1}, {1, 1, 1})), Visibility::partial);        // around the eye
  EXPECT_EQ(f.classify(box({1e6f, -1, -1}, {1e6f + 1, 1, 1})), Visibility::full);  // no far plane
}

TEST(Frustum, PlaneTestIsConservativeOnRandomBoxesAndViews) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> pos(-50, 50), size(0.1f, 20), angle(-180, 180),
      pitch(-80, 80);
  int none = 0, full = 0;
  for (int i = 0; i < 3000; ++i) {
    View v;
    v.pose = {{pos(rng), pos(rng), pos(rng)}, angle(rng), pitch(rng)};
    const glm::vec3 lo(pos(rng), pos(rng), pos(rng));
    const Bounds3 b = box(lo, lo + glm::vec3(size(rng), size(rng), size(rng)));
    const Visibility vis = Frustum(v).classify(b);
    if (vis == Visibility::none) {
      ++none;
      EXPECT_FALSE(any_point_visible(v, b, rng)) << i;
    }
    if (vis == Visibility::full) ++full;
  }
  EXPECT_GT(none, 1000);  // the test saw plenty of each case
  EXPECT_GT(full, 50);
}

TEST(Frustum, PaperTestMissesABeamAcrossTheView) {
  // A stated approximation of paper 004's test: a thin beam across the middle of the view,
  // its corners off screen left and right, no screen corner on it. The plane test keeps it.
  const View v = looking_along_x();
  const Bounds3 beam = box({20, -0.1f, -100}, {20.2f, 0.1f, 100});
  const Frustum f(v);
  EXPECT_EQ(f.classify(beam), Visibility::partial);
  EXPECT_EQ(f.classify_paper004(beam), Visibility::none);
  // Where it is right: a box fully on screen, one behind, one covering a screen corner.
  EXPECT_EQ(f.classify_paper004(box({10, -1, -1}, {12, 1, 1})), Visibility::full);
  EXPECT_EQ(f.classify_paper004(box({-12, -1, -1}, {-10, 1, 1})), Visibility::none);
  EXPECT_EQ(f.classify_paper004(box({5, -100, -100}, {6, 100, 100})), Visibility::partial);
}

TEST(Octree, EveryObjectIsInEveryLeafItOverlapsAndRangesNest) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> pos(0, 1000), size(0.5f, 60);
  std::vector<Bounds3> objects(2000);
  for (auto& b : objects) {
    const glm::vec3 lo(pos(rng), pos(rng) * 0.05f, pos(rng));
    b = box(lo, lo + glm::vec3(size(rng), size(rng), size(rng)));
  }
  const Octree tree = build_octree(objects, {.max_depth = 10, .objects_per_leaf = 8});
  ASSERT_FALSE(tree.nodes.empty());
  EXPECT_GT(tree.depth, 3u);
  std::set<uint32_t> seen(tree.items.begin(), tree.items.end());
  EXPECT_EQ(seen.size(), objects.size());
  for (const OctreeNode& n : tree.nodes) {
    ASSERT_LE(n.items_begin, n.items_end);
    if (n.leaf()) {
      for (uint32_t i = n.items_begin; i < n.items_end; ++i) {
        const Bounds3& o = objects[tree.items[i]];
        EXPECT_TRUE(o.min.x <= n.bounds.max.x && o.max.x >= n.bounds.min.x);
      }
      continue;
    }
    const OctreeNode& first = tree.nodes[n.first_child];
    const OctreeNode& last = tree.nodes[n.first_child + n.child_count - 1];
    EXPECT_EQ(first.items_begin, n.items_begin);
    EXPECT_EQ(last.items_end, n.items_end);
    for (uint32_t c = 0; c < n.child_count; ++c)
      EXPECT_GT(tree.nodes[n.first_child + c].items_end, tree.nodes[n.first_child + c].items_begin);
  }
  // Leaves hold few objects unless the depth limit stopped them.
  size_t over = 0;
  for (const OctreeNode& n : tree.nodes) over += n.leaf() && n.items_end - n.items_begin > 8;
  EXPECT_LT(over, tree.leaves / 4);
}

TEST(Octree, ObjectsThatAllStraddleTheCentreStopTheSplit) {
  std::vector<Bounds3> objects(50, box({-1, -1, -1}, {1, 1, 1}));
  const Octree tree = build_octree(objects, {.max_depth = 10, .objects_per_leaf = 4});
  EXPECT_EQ(tree.nodes.size(), 1u);
  EXPECT_EQ(tree.items.size(), 50u);
}

TEST(Octree, FixedDepthSplitsEveryNodeInsideTheGivenRoot) {
  // Paper 002's colour-cube tree: every occupied cell split down to the depth, however few
  // items it holds, over a root cube the caller chooses.
  const Bounds3 root = box({0, 0, 0}, {8, 8, 8});
  std::vector<Bounds3> items = {box({0.5f, 0.5f, 0.5f}, {0.6f, 0.6f, 0.6f}),
                                box({4, 4, 4}, {5, 5, 5}),         // touches the centre from above
                                box({20, 20, 20}, {21, 21, 21})};  // outside the root: skipped
  const Octree tree =
      build_octree(items, {.max_depth = 3, .split_to_max_depth = true, .root = root});
  ASSERT_FALSE(tree.nodes.empty());
  EXPECT_EQ(tree.nodes[0].bounds.min, root.min);
  EXPECT_EQ(tree.nodes[0].bounds.max, root.max);
  EXPECT_EQ(tree.depth, 3u);
  // Item 0 sits in one cell a level. Item 1 starts on the root's centre, so it is only in the
  // upper octant there; it ends on the centre of [4, 6]^3, so it is in both halves there.
  size_t leaves_of[3] = {0, 0, 0};
  for (const OctreeNode& n : tree.nodes) {
    if (!n.leaf()) continue;
    EXPECT_FLOAT_EQ(n.bounds.size().x, 1.0f);  // every leaf at depth 3
    for (uint32_t i = n.items_begin; i < n.items_end; ++i) leaves_of[tree.items[i]]++;
  }
  EXPECT_EQ(leaves_of[0], 1u);
  EXPECT_EQ(leaves_of[1], 8u);
  EXPECT_EQ(leaves_of[2], 0u);
  EXPECT_EQ(tree.nodes[0].child_count, 2u);
}

TEST(ObjectSet, EmitsInSceneOrderAndMergesNeighbours) {
  const Scene scene = test::make_box_row(6);  // materials alternate opaque / transparent
  ObjectSet set(scene);
  set.insert(4);
  set.insert(0);
  set.insert(2);
  set.insert(2);
  set.insert(3);
  DrawList list;
  set.emit(list);
  ASSERT_EQ(list.opaque.size(), 3u);  // 0, 2, 4 are opaque and not neighbours
  EXPECT_EQ(list.opaque[0].first_index, 0u);
  EXPECT_EQ(list.opaque[2].first_index, 4 * 36u);
  ASSERT_EQ(list.transparent.size(), 1u);
  EXPECT_EQ(list.triangle_count(), 4 * 12u);

  // Same material side by side merges.
  Scene same = test::make_box_row(4);
  for (auto& o : same.objects) o.material = 0;
  ObjectSet all(same);
  all.insert_all();
  DrawList merged;
  all.emit(merged);
  ASSERT_EQ(merged.opaque.size(), 1u);
  EXPECT_EQ(merged.opaque[0].index_count, same.indices.size());
}

TEST(Techniques, UnknownNameListsTheKnownOnes) {
  auto t = make_technique("warp-drive");
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().message.find("brute"), std::string::npos);
  EXPECT_NE(t.error().message.find("octree"), std::string::npos);
}

TEST(Techniques, OctreeKeepsEveryVisibleObjectAndDropsMostHiddenOnes) {
  // A 30 x 30 grid of unit boxes; views from inside the grid.
  Scene scene;
  {
    Scene row = test::make_box_row(1);
    SceneBuilder b(scene);
    const uint32_t m = b.add_material(Material{});
    for (int i = 0; i < 900; ++i) {
      b.begin_object("b" + std::to_string(i), ObjectKind::mesh, m);
      const glm::vec3 o(3.0f * (i % 30), 0, 3.0f * (i / 30));
      for (const Vertex& v : row.vertices)
        b.add_vertex(v.position + o, unpack_normal(v.normal), v.color);
      for (size_t k = 0; k < row.indices.size(); k += 3)
        b.add_triangle(row.indices[k], row.indices[k + 1], row.indices[k + 2]);
      b.end_object();
    }
  }
  auto brute = make_technique("brute");
  auto octree = make_technique("octree");
  ASSERT_TRUE(brute && octree);
  ASSERT_TRUE(test::load_technique(**brute, scene));
  ASSERT_TRUE(test::load_technique(**octree, scene));
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> pos(0, 90), angle(-180, 180), pitch(-30, 30);
  DrawList all, culled;
  double kept = 0;
  for (int i = 0; i < 100; ++i) {
    View v;
    v.pose = {{pos(rng), 0.5f, pos(rng)}, angle(rng), pitch(rng)};
    test::select_view(**brute, v, all);
    test::select_view(**octree, v, culled);
    EXPECT_EQ(all.triangle_count(), scene.triangle_count());
    EXPECT_LE(culled.triangle_count(), all.triangle_count());
    // Every object with a visible point is selected.
    std::set<uint32_t> selected;
    for (const DrawRange& r : culled.opaque)
      for (uint32_t k = r.first_index; k < r.first_index + r.index_count; k += 36)
        selected.insert(k / 36);
    for (uint32_t o = 0; o < scene.objects.size(); ++o) {
      if (any_point_visible(v, scene.objects[o].bounds, rng)) {
        ASSERT_TRUE(selected.count(o)) << "view " << i << " dropped visible object " << o;
      }
    }
    kept += double(culled.triangle_count()) / double(all.triangle_count());
  }
  EXPECT_LT(kept / 100, 0.5);  // a 90 degree view sees about a quarter of the grid
}

}  // namespace
}  // namespace farfield
