// Textured boxes (paper 001, Sec. 5.1): the shelf packer of their atlas pages, the sides
// rendered at bake (coverage, the error from the depth behind a side), the frame they draw,
// and the pack that keeps them.
#include "farfield/techniques/clusters/box_set.hpp"

#include <gtest/gtest.h>

#include "farfield/core/assert.hpp"
#include "farfield/core/image.hpp"
#include "farfield/core/progress.hpp"
#include "farfield/core/shelf_packer.hpp"
#include "farfield/eval/image_metrics.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/device.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/city_generator.hpp"
#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/clusters/average_boxes.hpp"
#include "farfield/techniques/clusters/pseudo_maps.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

TEST(ShelfPacker, PlacesGroupsApartOnThePageOrNotAtAll) {
  ShelfPacker packer(64, 1);
  std::vector<std::pair<glm::ivec2, glm::ivec2>> placed;  // corner, size
  const std::vector<glm::ivec2> group = {{20, 10}, {10, 20}, {30, 5}};
  for (int round = 0; round < 100; ++round) {
    auto at = packer.place(group);
    if (!at) break;
    for (size_t k = 0; k < group.size(); ++k) placed.push_back({(*at)[k], group[k]});
  }
  ASSERT_GE(placed.size(), 9u);
  for (size_t i = 0; i < placed.size(); ++i) {
    const auto& [p, s] = placed[i];
    EXPECT_GE(p.x, 0);
    EXPECT_GE(p.y, 0);
    EXPECT_LE(p.x + s.x, 64);
    EXPECT_LE(p.y + s.y, 64);
    for (size_t j = 0; j < i; ++j) {
      const auto& [q, t] = placed[j];
      const bool apart = p.x + s.x + 1 <= q.x || q.x + t.x + 1 <= p.x || p.y + s.y + 1 <= q.y ||
                         q.y + t.y + 1 <= p.y;
      EXPECT_TRUE(apart) << i << " meets " << j;
    }
  }
  // A group that does not fit leaves the page as it was: a small one still fits after it.
  EXPECT_FALSE(packer.place({{64, 64}}));
  packer.next_page();
  EXPECT_EQ(packer.page(), 1);
  EXPECT_TRUE(packer.place({{63, 63}}));
}

// Object 0: a 2 x 1 x 1 m cube; object 1: an L of a 2 x 1 x 1 m block and a 1 x 1 x 2 m one
// behind it, so that looking at its +Z side shows the block's face 2 m behind the side.
Scene two_shapes() {
  Scene scene;
  SceneBuilder b(scene);
  const uint32_t red = b.add_material(Material{{0.8f, 0.2f, 0.1f, 1.0f}});
  b.begin_object("cube", ObjectKind::building, red);
  test::add_cuboid(b, {0, 0, 0}, {2, 1, 1});
  b.end_object();
  b.begin_object("ell", ObjectKind::building, red);
  test::add_cuboid(b, {10, 0, 0}, {12, 1, 1});
  test::add_cuboid(b, {10, 0, 1}, {11, 1, 3});
  b.end_object();
  return scene;
}

BoxSetOptions every_object() {
  BoxSetOptions o;
  o.min_triangles = 1;
  o.clusters = true;
  o.page_px = 512;
  o.max_side_px = 64;
  return o;
}

// The two shapes, a renderer of them and their boxes; `ok` false where there is no GL here.
struct Bench {
  Scene scene = two_shapes();
  std::unique_ptr<gpu::Context> context;
  std::unique_ptr<gpu::Renderer> renderer;
  ClusterTree tree;
  BoxSet boxes;
  std::string skip;
  bool ok() const { return skip.empty(); }
};
Bench baked_shapes() {
  Bench b;
  auto context = gpu::create_headless_context();
  if (!context) {
    b.skip = context.error().message;
    return b;
  }
  b.context = std::move(*context);
  auto renderer = gpu::Renderer::create(b.scene);
  FF_ASSERT(renderer.ok(), "renderer");
  b.renderer = std::move(*renderer);
  Progress quiet(true);
  b.tree = build_cluster_cells(b.scene, {});
  auto boxes = bake_box_set(b.scene, b.tree, *b.renderer, every_object(), quiet);
  FF_ASSERT(boxes.ok(), "boxes");
  b.boxes = std::move(*boxes);
  return b;
}

// A cube is its own box: every side covered wholly, an error within a texel; the L's error is
// the depth of the face its +Z side shows behind it.
TEST(BoxSetGL, SidesCoverTheObjectAndTheErrorIsTheDepthBehindThem) {
  Bench b = baked_shapes();
  if (!b.ok()) GTEST_SKIP() << b.skip;
  ASSERT_EQ(b.boxes.object_box.size(), 2u);
  ASSERT_NE(b.boxes.object_box[0], BoxSet::kNone);
  ASSERT_NE(b.boxes.object_box[1], BoxSet::kNone);
  const TexturedBox& cube = b.boxes.boxes[b.boxes.object_box[0]];
  const TexturedBox& ell = b.boxes.boxes[b.boxes.object_box[1]];
  const float texel = 2.0f / 64.0f;  // the longest edge at max_side_px
  EXPECT_LE(cube.error_m, 2 * texel);
  EXPECT_NEAR(ell.error_m, 2.0f, 2 * texel);
  EXPECT_EQ(cube.side_count(), 6u);
  const std::vector<uint8_t>& page = b.boxes.pages[cube.page];
  for (const BoxSide& s : cube.sides) {
    uint64_t covered = 0;
    for (int y = s.y; y < s.y + s.h; ++y)
      for (int x = s.x; x < s.x + s.w; ++x)
        covered += page[(size_t(y) * size_t(b.boxes.page_px) + size_t(x)) * 4 + 3] > 0;
    EXPECT_EQ(covered, uint64_t(s.w) * s.h);
  }
  // The L's +Z side: the 1 m wide block in front, the rest 2 m behind, nothing empty.
  EXPECT_GT(ell.sides[4].w, 0);
  // Meshes: two triangles a side drawn.
  const BoxMeshes meshes = box_meshes(b.boxes);
  EXPECT_EQ(meshes.index_count[b.boxes.object_box[0]], 36u);
}

// Drawn from afar, the cube's box looks like the cube (the sides were lit as the scene is).
TEST(BoxSetGL, TheBoxLooksLikeItsObject) {
  Bench b = baked_shapes();
  if (!b.ok()) GTEST_SKIP() << b.skip;
  const Scene& scene = b.scene;
  const BoxMeshes meshes = box_meshes(b.boxes);
  auto mesh = b.renderer->create_textured_mesh(meshes.pages[0].vertices, meshes.pages[0].indices);
  ASSERT_TRUE(mesh);
  const TextureHandle texture = b.renderer->create_texture();
  View view;
  view.width = 160;
  view.height = 120;
  view.hfov_deg = 30.0f;
  view.pose.position = {-3.0f, 3.0f, -6.0f};  // looking at the cube's centre
  view.pose.yaw_deg = 58.4f;
  view.pose.pitch_deg = -18.1f;
  b.renderer->set_offscreen(view.width, view.height);
  DrawList list;
  list.opaque.push_back(
      {scene.objects[0].first_index, scene.objects[0].index_count, scene.objects[0].material, {}});
  b.renderer->draw(view, list);
  const Image reference = b.renderer->capture();
  list.clear();
  const uint32_t box = b.boxes.object_box[0];
  list.uploads.push_back(
      {texture, b.boxes.page_px, b.boxes.page_px, 4, b.boxes.pages[0].data(), nullptr, true});
  list.meshes.push_back({*mesh, meshes.first_index[box], meshes.index_count[box], texture});
  b.renderer->draw(view, list);
  const Image drawn = b.renderer->capture();
  const ImageComparison c = compare_images(reference, drawn);
  EXPECT_GT(c.psnr_db, 25.0) << c.differing_pixels << " pixels differ";
  uint64_t sky = 0, reference_sky = 0;  // the cube is in view, and the box covers as much
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      reference_sky += reference.pixel(x, y)[0] == reference.pixel(0, 0)[0];
      sky += drawn.pixel(x, y)[0] == reference.pixel(0, 0)[0];
    }
  EXPECT_LT(reference_sky, uint64_t(view.width * view.height) * 95 / 100);
  EXPECT_NEAR(double(sky), double(reference_sky), 0.02 * view.width * view.height);
}

// The view of the cube the flat stand-ins are checked from.
View cube_view() {
  View view;
  view.width = 160;
  view.height = 120;
  view.hfov_deg = 30.0f;
  view.pose.position = {-3.0f, 3.0f, -6.0f};  // looking at the cube's centre
  view.pose.yaw_deg = 58.4f;
  view.pose.pitch_deg = -18.1f;
  return view;
}

// The cube's frame against the frame of `mesh` (vertex colours, a white texture).
ImageComparison cube_against(Bench& b, const TexturedMesh& mesh) {
  const View view = cube_view();
  auto handle = b.renderer->create_textured_mesh(mesh.vertices, mesh.indices);
  FF_ASSERT(handle.ok(), "mesh");
  const TextureHandle white = b.renderer->create_texture();
  static constexpr uint8_t kWhite[4] = {255, 255, 255, 255};
  b.renderer->set_offscreen(view.width, view.height);
  const Object& cube = b.scene.objects[0];
  DrawList list;
  list.opaque.push_back({cube.first_index, cube.index_count, cube.material, {}});
  b.renderer->draw(view, list);
  const Image reference = b.renderer->capture();
  list.clear();
  list.uploads.push_back({white, 1, 1, 4, kWhite, nullptr});
  list.meshes.push_back({*handle, 0, uint32_t(mesh.indices.size()), white});
  b.renderer->draw(view, list);
  return compare_images(reference, b.renderer->capture());
}

// The cube's average-colour box from afar: its sides are wholly covered and evenly lit, so
// that it looks like the cube as the textured box does.
TEST(BoxSetGL, TheAverageBoxLooksLikeItsObjectToo) {
  Bench b = baked_shapes();
  if (!b.ok()) GTEST_SKIP() << b.skip;
  const uint32_t box = b.boxes.object_box[0];
  const AverageBox average =
      average_box(b.boxes.boxes[box], b.boxes.pages[b.boxes.boxes[box].page], b.boxes.page_px);
  for (const AverageSide& side : average.sides) EXPECT_EQ(side.coverage, 255);
  TexturedMesh mesh;
  append_average_box(b.boxes.boxes[box], average, cube_view().pose.position, mesh);
  EXPECT_EQ(mesh.indices.size(), 18u);  // three sides face the eye
  const ImageComparison c = cube_against(b, mesh);
  EXPECT_GT(c.psnr_db, 25.0) << c.differing_pixels << " pixels differ";
}

// The cube's pseudo-texture box (its sides' images as quads of 8 x 8 texels at most): the
// cube, evenly lit, looks the same.
TEST(BoxSetGL, ThePseudoTextureBoxLooksLikeItsObjectToo) {
  Bench b = baked_shapes();
  if (!b.ok()) GTEST_SKIP() << b.skip;
  const PseudoMaps maps = pseudo_maps(b.boxes, 8);
  TexturedMesh mesh;
  append_pseudo_box(b.boxes, maps, b.boxes.object_box[0], cube_view().pose.position, mesh);
  EXPECT_GT(mesh.indices.size(), 3u * 6u * 16u);  // three sides of many texels
  const ImageComparison c = cube_against(b, mesh);
  EXPECT_GT(c.psnr_db, 25.0) << c.differing_pixels << " pixels differ";
}

// A small city's boxes on small pages: every side inside its page, no two sides (with their
// gutters) on one texel, and the pages but the last more than half full on average (the
// tallest packed first; 0.56 to 0.72 each, gutters counted as empty).
TEST(BoxSetGL, SidesPackedApartOnPagesMoreThanHalfFull) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  CityOptions city_options;
  city_options.blocks_x = city_options.blocks_z = 2;
  Progress quiet(true);
  auto city = generate_city(city_options, quiet);
  ASSERT_TRUE(city);
  auto renderer = gpu::Renderer::create(*city);
  ASSERT_TRUE(renderer);
  BoxSetOptions o;
  o.page_px = 256;
  o.max_side_px = 64;
  const ClusterTree tree = build_cluster_cells(*city, {});
  auto boxes = bake_box_set(*city, tree, **renderer, o, quiet);
  ASSERT_TRUE(boxes) << boxes.error().message;
  ASSERT_GE(boxes->pages.size(), 3u);
  std::vector<std::vector<uint8_t>> taken(boxes->pages.size(),
                                          std::vector<uint8_t>(size_t(o.page_px) * o.page_px));
  std::vector<uint64_t> texels(boxes->pages.size(), 0);
  for (const TexturedBox& box : boxes->boxes)
    for (const BoxSide& s : box.sides) {
      if (s.w == 0) continue;
      ASSERT_LE(s.x + s.w, o.page_px);
      ASSERT_LE(s.y + s.h, o.page_px);
      texels[box.page] += uint64_t(s.w) * s.h;
      for (int y = s.y; y < std::min(s.y + s.h + 2, o.page_px); ++y)
        for (int x = s.x; x < std::min(s.x + s.w + 2, o.page_px); ++x) {
          uint8_t& t = taken[box.page][size_t(y) * o.page_px + size_t(x)];
          ASSERT_EQ(t, 0) << "page " << box.page << " texel " << x << ", " << y;
          t = 1;
        }
    }
  uint64_t filled = 0;
  for (size_t p = 0; p + 1 < texels.size(); ++p) filled += texels[p];
  EXPECT_GT(double(filled), 0.5 * double(texels.size() - 1) * o.page_px * o.page_px);
}

TEST(BoxSetGL, KeptInAPackAndRefusedWhenDamaged) {
  Bench b = baked_shapes();
  if (!b.ok()) GTEST_SKIP() << b.skip;
  const Scene& scene = b.scene;
  test::TempDir dir;
  const std::string path = dir.file("boxes.ffpack");
  {
    auto store = Store::open(path, Store::Mode::kReadWrite);
    ASSERT_TRUE(store);
    // No boxes in a pack: none, no error.
    auto none = load_box_set(*store, scene, b.tree);
    ASSERT_TRUE(none) << none.error().message;
    EXPECT_TRUE(none->boxes.empty());
    ASSERT_TRUE(save_box_set(b.boxes, *store));
    auto back = load_box_set(*store, scene, b.tree);
    ASSERT_TRUE(back) << back.error().message;
    ASSERT_EQ(back->boxes.size(), b.boxes.boxes.size());
    EXPECT_EQ(back->pages, b.boxes.pages);
    EXPECT_EQ(back->object_box, b.boxes.object_box);
    EXPECT_EQ(back->boxes[1].error_m, b.boxes.boxes[1].error_m);

    auto refused = [&](const char* what) {
      auto loaded = load_box_set(*store, scene, b.tree);
      EXPECT_FALSE(loaded) << what;
      return loaded ? std::string() : loaded.error().message;
    };
    std::vector<TexturedBox> past = b.boxes.boxes;
    past[0].sides[0].x = uint16_t(b.boxes.page_px - 1);
    ASSERT_TRUE(store->put("clusters/boxes", bytes_of(past)));
    EXPECT_NE(refused("side past the page").find("past its page"), std::string::npos);
    ASSERT_TRUE(store->put("clusters/boxes", bytes_of(b.boxes.boxes)));
    const std::vector<uint8_t> short_page(102, 0);
    ASSERT_TRUE(store->put("clusters/box_page_0", bytes_of(short_page)));
    EXPECT_NE(refused("short page").find("box page 0"), std::string::npos);
    ASSERT_TRUE(store->erase("clusters/box_page_0"));
    EXPECT_NE(refused("missing page").find("box_page_0"), std::string::npos);
    ASSERT_TRUE(save_box_set(b.boxes, *store));
    const std::vector<uint32_t> wrong = {0, 1, 0};  // three objects
    ASSERT_TRUE(store->put("clusters/box_of_objects", bytes_of(wrong)));
    EXPECT_NE(refused("other scene").find("not of this scene"), std::string::npos);
  }
}

}  // namespace
}  // namespace farfield
