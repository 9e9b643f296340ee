// The colour-cube octree (paper 002, Sec. 4) and the colorcube technique's traversal.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "farfield/eval/image_metrics.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/lighting.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/field_generator.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/scene/tree_generator.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/colorcube/cube_tree.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// A grid of n x n unit boxes, 3 m apart, on the ground.
Scene box_field(int n) {
  Scene scene;
  const Scene box = test::make_box_row(1);
  SceneBuilder b(scene);
  const uint32_t m = b.add_material(Material{{0.8f, 0.2f, 0.1f, 1.0f}});
  for (int i = 0; i < n * n; ++i) {
    b.begin_object("box" + std::to_string(i), ObjectKind::mesh, m);
    const glm::vec3 offset(3.0f * float(i % n), 0.0f, 3.0f * float(i / n));
    for (const Vertex& v : box.vertices)
      b.add_vertex(v.position + offset, unpack_normal(v.normal), v.color);
    for (size_t k = 0; k < box.indices.size(); k += 3)
      b.add_triangle(box.indices[k], box.indices[k + 1], box.indices[k + 2]);
    b.end_object();
  }
  return scene;
}

TEST(CubeTree, BuildsPrunedLevelsWithLeafTrianglesAndFaceBatches) {
  const Scene scene = box_field(4);
  Progress quiet(true);
  CubeTreeOptions options;
  options.depth = 3;
  options.leaf.cluster = 2;
  auto tree = build_cube_tree(scene, options, quiet);
  ASSERT_TRUE(tree) << tree.error().message;
  EXPECT_EQ(tree->stats.levels, 4u);
  EXPECT_LT(tree->stats.cells, 1u + 8u + 64u + 512u);  // empty cells pruned
  uint32_t leaves = 0;
  uint64_t geometry = 0;
  for (const CubeCell& cell : tree->cells) {
    if (!cell.leaf()) continue;
    ++leaves;
    EXPECT_EQ(cell.level, 3u);
    geometry += cell.geometry_count / 3;
  }
  EXPECT_EQ(leaves, tree->stats.leaves);
  EXPECT_EQ(geometry, scene.triangle_count());  // every triangle owned by exactly one leaf
  // Every face batch lies inside the proxy mesh, six indices per quad.
  uint64_t faces = 0;
  for (const CubeCell& cell : tree->cells) {
    for (int f = 0; f < 6; ++f) {
      EXPECT_EQ(cell.faces_count[f] % 6, 0u);
      EXPECT_LE(cell.faces_begin[f] + cell.faces_count[f], tree->proxies.indices.size());
      faces += cell.faces_count[f] / 6;
    }
  }
  EXPECT_EQ(faces, tree->stats.cube_faces);
  EXPECT_EQ(tree->proxies.indices.size(), 6 * faces + 3 * geometry);
  // The root's top faces (seen from +Y) are the boxes' lit tops.
  const CubeCell& root = tree->cells[0];
  ASSERT_GT(root.faces_count[2], 0u);
  const ProxyVertex& v = tree->proxies.vertices[tree->proxies.indices[root.faces_begin[2]]];
  const glm::vec3 top = gpu::shade({0, 1, 0}, {0.8f, 0.2f, 0.1f});
  const glm::vec4 drawn = unpack_color(v.color);
  EXPECT_NEAR(drawn.r, top.r, 0.01f);
  EXPECT_NEAR(drawn.g, top.g, 0.01f);
}

TEST(CubeTree, RefusesBadOptions) {
  const Scene scene = box_field(2);
  Progress quiet(true);
  CubeTreeOptions o;
  o.leaf.oversampling = 6;
  EXPECT_FALSE(build_cube_tree(scene, o, quiet));
  o = {};
  o.depth = 40;
  EXPECT_FALSE(build_cube_tree(scene, o, quiet));
  EXPECT_FALSE(build_cube_tree(Scene{}, CubeTreeOptions{}, quiet));
  TechniqueSettings settings;
  ASSERT_TRUE(settings.add("colorcube.warp=9"));
  auto t = make_technique("colorcube", settings);
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().message.find("warp"), std::string::npos);
  EXPECT_FALSE(settings.add("depth=3"));  // no technique name
}

// Depth 0 puts leaf cubes at the scene's triangle size (no smaller, less than twice as
// large), follows paper 002's density target under depth_rule=density, and is lowered to
// stay under max_leaves; an explicit depth is kept.
TEST(CubeTree, DerivedDepthFollowsTheSceneDetail) {
  Progress quiet(true);
  auto tree = generate_tree({}, quiet);
  ASSERT_TRUE(tree);
  auto field = generate_field(*tree, {.count = 16, .spacing = 40.0}, quiet);
  ASSERT_TRUE(field);
  const double edge = median_triangle_edge(*field);
  CubeTreeOptions o;
  const ResolvedDepth detail = resolve_depth(*field, o);
  EXPECT_FALSE(detail.limited_by_leaves);
  EXPECT_EQ(detail.depth, detail.detail_depth);
  const double cube = leaf_cube_side(*field, detail.depth, o.leaf.cluster);
  EXPECT_GE(cube, edge);
  EXPECT_LT(cube, 2.0 * edge);

  o.depth_rule = DepthRule::density;
  const int dense = resolve_depth(*field, o).depth;
  EXPECT_LE(field->triangle_count() / occupied_leaves(*field, dense), 4000u);
  EXPECT_GT(field->triangle_count() / occupied_leaves(*field, dense - 1), 4000u);

  o.depth_rule = DepthRule::detail;
  o.max_leaves = occupied_leaves(*field, detail.depth) - 1;
  const ResolvedDepth capped = resolve_depth(*field, o);
  EXPECT_TRUE(capped.limited_by_leaves);
  EXPECT_EQ(capped.depth, detail.depth - 1);
  EXPECT_LE(occupied_leaves(*field, capped.depth), o.max_leaves);

  o.depth = 3;
  EXPECT_EQ(resolve_depth(*field, o).depth, 3);
}

TEST(ColorcubeGL, FarCubesStandInAndNearGeometryIsExact) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  const Scene scene = box_field(16);
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  TechniqueSettings settings;
  ASSERT_TRUE(settings.add("colorcube.depth=4"));
  ASSERT_TRUE(settings.add("colorcube.cluster=2"));
  auto brute = make_technique("brute");
  auto cubes = make_technique("colorcube", settings);
  ASSERT_TRUE(cubes) << cubes.error().message;
  ASSERT_TRUE(test::load_technique(**brute, scene, renderer->get()));
  ASSERT_TRUE(test::load_technique(**cubes, scene, renderer->get()));

  View far;
  far.width = 160;
  far.height = 120;
  far.pose = {{22.0f, 150.0f, -120.0f}, 90.0f, -50.0f};  // high above, looking at the field
  (*renderer)->set_offscreen(far.width, far.height);
  DrawList all, selected;
  test::select_view(**brute, far, all);
  (*renderer)->draw(far, all);
  const Image reference = (*renderer)->capture();
  test::select_view(**cubes, far, selected);
  EXPECT_GT(selected.meshes.size(), 0u);
  EXPECT_LT(selected.triangle_count(), all.triangle_count());
  (*renderer)->draw(far, selected);
  const ImageComparison c = compare_images(reference, (*renderer)->capture());
  EXPECT_GT(c.psnr_db, 20.0) << c.differing_pixels << " pixels differ";

  // Close to the boxes, the near leaves draw their triangles: the picture matches brute force
  // where geometry is drawn (lighting per vertex on flat faces equals per pixel).
  View near = far;
  near.pose = {{1.5f, 0.5f, -2.0f}, 90.0f, 0.0f};
  test::select_view(**brute, near, all);
  (*renderer)->draw(near, all);
  const Image near_reference = (*renderer)->capture();
  test::select_view(**cubes, near, selected);
  (*renderer)->draw(near, selected);
  EXPECT_GT(compare_images(near_reference, (*renderer)->capture()).psnr_db, 30.0);
}

}  // namespace
}  // namespace farfield

namespace farfield {
namespace {

TEST(ColorcubeGL, ALargeTriangleIsDrawnWhereverItReaches) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  // A 200 m ground square and a field of boxes on it; the camera stands near one edge of the
  // square looking outwards, so the square's triangles have their centroids behind the eye.
  Scene scene = box_field(8);
  {
    SceneBuilder b(scene);
    const uint32_t m = b.add_material(Material{{0.3f, 0.6f, 0.2f, 1.0f}});
    b.begin_object("ground", ObjectKind::ground, m);
    const uint32_t c = pack_color(glm::vec4(1.0f));
    b.add_vertex({-100, 0, -100}, {0, 1, 0}, c);
    b.add_vertex({-100, 0, 100}, {0, 1, 0}, c);
    b.add_vertex({100, 0, 100}, {0, 1, 0}, c);
    b.add_vertex({100, 0, -100}, {0, 1, 0}, c);
    b.add_triangle(0, 1, 2);
    b.add_triangle(0, 2, 3);
    b.end_object();
  }
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  TechniqueSettings settings;
  ASSERT_TRUE(settings.add("colorcube.depth=5"));
  auto brute = make_technique("brute");
  auto cubes = make_technique("colorcube", settings);
  ASSERT_TRUE(test::load_technique(**brute, scene, renderer->get()));
  ASSERT_TRUE(test::load_technique(**cubes, scene, renderer->get()));
  View view;
  view.width = 160;
  view.height = 120;
  view.pose = {{90.0f, 2.0f, 90.0f}, 45.0f, -10.0f};  // at a corner, looking out over the edge
  (*renderer)->set_offscreen(view.width, view.height);
  DrawList list;
  test::select_view(**brute, view, list);
  (*renderer)->draw(view, list);
  const Image reference = (*renderer)->capture();
  test::select_view(**cubes, view, list);
  (*renderer)->draw(view, list);
  const ImageComparison c = compare_images(reference, (*renderer)->capture());
  EXPECT_TRUE(c.identical()) << c.differing_pixels << " pixels differ";
}

}  // namespace
}  // namespace farfield

namespace farfield {
namespace {

TEST(CubeTree, BakeIntoAStoreAndLoadItBack) {
  test::TempDir dir;
  const Scene scene = box_field(4);
  Progress quiet(true);
  CubeTreeOptions options;
  options.depth = 3;
  auto tree = build_cube_tree(scene, options, quiet);
  ASSERT_TRUE(tree);
  {
    auto store = Store::open(dir.file("p.ffpack"), Store::Mode::kReadWrite);
    ASSERT_TRUE(store) << store.error().message;
    ASSERT_TRUE(save_cube_tree(*tree, *store));
  }
  auto store = Store::open(dir.file("p.ffpack"), Store::Mode::kRead);
  ASSERT_TRUE(store);
  auto back = load_cube_tree(*store, scene);
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(back->cells.size(), tree->cells.size());
  EXPECT_EQ(back->proxies.indices, tree->proxies.indices);
  EXPECT_EQ(back->stats.cube_faces, tree->stats.cube_faces);
  // A pack without one is refused (another scene's bake is the bake record's to refuse:
  // RefusalGL.PacksOfAnotherSceneOrFormatAreRefused).
  auto empty = Store::open(dir.file("empty.ffpack"), Store::Mode::kReadWrite);
  ASSERT_TRUE(empty);
  EXPECT_FALSE(load_cube_tree(*empty, scene));
}

TEST(CubeTree, BakeCommandWritesAPackInfoDescribes) {
  test::TempDir dir;
  ASSERT_TRUE(write_scene(box_field(3), dir.file("s.ffscene")));
  // Seen whole, the small field's leaf cubes never shrink below a pixel: the bake says so and
  // writes nothing, unless forced.
  auto r =
      test::run_farfield("bake " + dir.file("s.ffscene") +
                         " -t colorcube -q --set colorcube.depth=3 --out " + dir.file("s.ffpack"));
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_NE(r.output.find("no cube would be drawn"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("s.ffpack")));
  r = test::run_farfield("bake " + dir.file("s.ffscene") +
                         " -t colorcube -q --set colorcube.depth=3 --set colorcube.force=1 --out " +
                         dir.file("s.ffpack"));
  ASSERT_EQ(r.exit_status, 0) << r.output;
  auto info = test::run_farfield("info " + dir.file("s.ffpack"));
  EXPECT_EQ(info.exit_status, 0);
  EXPECT_NE(info.output.find("colorcube/table1"), std::string::npos) << info.output;
  // A technique without a bake refuses and leaves no pack behind.
  auto octree = test::run_farfield("bake " + dir.file("s.ffscene") + " -t octree --out " +
                                   dir.file("o.ffpack"));
  EXPECT_EQ(octree.exit_status, 1);
  EXPECT_NE(octree.output.find("nothing to bake"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir.file("o.ffpack")));
}

}  // namespace
}  // namespace farfield

namespace farfield {
namespace {

// Occlusion culling must not change a pixel, and dropping the faces against solid neighbours
// may change only pixels whose centres fall exactly on a dropped face's edge (the renderer's
// tie-breaking rule then gives them to the dropped face): views across a field of 3 x 3 trees
// low over the ground, where near crowns hide far ones.
TEST(ColorcubeGL, OcclusionAndDroppedInnerFacesLeaveTheImageUnchanged) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  Progress quiet(true);
  auto tree = generate_tree({}, quiet);
  ASSERT_TRUE(tree);
  auto field = generate_field(*tree, {.count = 9, .spacing = 15.0}, quiet);
  ASSERT_TRUE(field);
  const Scene& scene = *field;
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  auto make = [&](const char* occlusion, const char* inner) {
    TechniqueSettings settings;
    EXPECT_TRUE(settings.add("colorcube.depth=6"));
    EXPECT_TRUE(settings.add(std::string("colorcube.occlusion=") + occlusion));
    EXPECT_TRUE(settings.add(std::string("colorcube.inner_faces=") + inner));
    auto t = make_technique("colorcube", settings);
    EXPECT_TRUE(t) << t.error().message;
    EXPECT_TRUE(test::load_technique(**t, scene, renderer->get()));
    return std::move(*t);
  };
  auto paper = make("0", "keep"), occluded = make("1", "keep"), culled = make("1", "drop");
  auto figure = [](const Technique& t, const char* name) {
    for (const auto& [key, value] : t.figures())
      if (key == name) return value;
    return -1.0;
  };
  EXPECT_GT(figure(*culled, "inner_faces_dropped"), 0.0);
  EXPECT_EQ(figure(*paper, "inner_faces_dropped"), 0.0);
  EXPECT_LT(figure(*culled, "cube_faces_in_model"), figure(*paper, "cube_faces_in_model"));

  View view;
  view.width = 320;
  view.height = 240;
  (*renderer)->set_offscreen(view.width, view.height);
  DrawList list;
  uint64_t paper_triangles = 0, occluded_triangles = 0, culled_triangles = 0;
  for (int k = 0; k < 12; ++k) {
    // Around the field (42 m wide, centred on the origin), 60-170 m out, 1-6 m up.
    const float angle = 0.52f * float(k), distance = 60.0f + 10.0f * float(k);
    const glm::vec3 centre(0.0f, 5.0f, 0.0f);
    view.pose.position = centre + glm::vec3(distance * std::cos(angle), 1.0f + 0.4f * float(k),
                                            distance * std::sin(angle));
    const glm::vec3 to = glm::normalize(centre - view.pose.position);
    view.pose.yaw_deg = glm::degrees(std::atan2(to.z, to.x));
    view.pose.pitch_deg = glm::degrees(std::asin(to.y));
    test::select_view(*paper, view, list);
    paper_triangles += list.mesh_triangle_count();
    (*renderer)->draw(view, list);
    const Image reference = (*renderer)->capture();
    test::select_view(*occluded, view, list);
    occluded_triangles += list.mesh_triangle_count();
    (*renderer)->draw(view, list);
    EXPECT_EQ(compare_images(reference, (*renderer)->capture()).differing_pixels, 0u)
        << "view " << k;
    test::select_view(*culled, view, list);
    culled_triangles += list.mesh_triangle_count();
    (*renderer)->draw(view, list);
    EXPECT_LE(compare_images(reference, (*renderer)->capture()).differing_pixels, 4u)
        << "view " << k;
  }
  EXPECT_LT(occluded_triangles, paper_triangles);
  EXPECT_LT(culled_triangles, occluded_triangles);
  EXPECT_GT(figure(*occluded, "mean_cells_occluded"), 0.0);
}

TEST(ColorcubeSettings, RefusesUnknownInnerFacesValues) {
  TechniqueSettings settings;
  ASSERT_TRUE(settings.add("colorcube.inner_faces=sometimes"));
  auto t = make_technique("colorcube", settings);
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().message.find("colorcube.inner_faces"), std::string::npos)
      << t.error().message;
}

}  // namespace
}  // namespace farfield

namespace farfield {
namespace {

// Near leaves draw textured triangles from the scene's own buffers, so they are textured as
// brute force draws them (a proxy mesh has no texture coordinates); the untextured box beside
// stays in the proxy mesh.
TEST(ColorcubeGL, NearTexturedTrianglesAreDrawnTextured) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  const Scene scene = test::make_textured_scene();
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  auto brute = make_technique("brute");
  auto cubes = make_technique("colorcube", test::settings_of({"colorcube.depth=2"}));
  ASSERT_TRUE(test::load_technique(**brute, scene, renderer->get()));
  ASSERT_TRUE(test::load_technique(**cubes, scene, renderer->get()));
  Progress quiet(true);
  auto tree = build_cube_tree(scene, {.depth = 2}, quiet);
  ASSERT_TRUE(tree);
  uint32_t textured = 0;  // the quad's two triangles (in one leaf or two)
  for (const DrawRange& r : tree->scene_ranges) {
    EXPECT_EQ(r.material, scene.objects[1].material);
    textured += r.index_count / 3;
  }
  EXPECT_EQ(textured, 2u);
  EXPECT_EQ(tree->stats.geometry_triangles, 14u);
  EXPECT_EQ(tree->proxies.vertices.size() % 4, 0u);
  View view;
  view.width = 160;
  view.height = 120;
  view.pose = {{0.6f, 1.0f, 6.0f}, -90.0f, -5.0f};  // in front of the quad, the box behind it
  (*renderer)->set_offscreen(view.width, view.height);
  DrawList list;
  test::select_view(**brute, view, list);
  (*renderer)->draw(view, list);
  const Image reference = (*renderer)->capture();
  test::select_view(**cubes, view, list);
  EXPECT_FALSE(list.opaque.empty());
  (*renderer)->draw(view, list);
  const ImageComparison c = compare_images(reference, (*renderer)->capture());
  EXPECT_TRUE(c.identical()) << c.differing_pixels << " pixels differ";
}

}  // namespace
}  // namespace farfield
