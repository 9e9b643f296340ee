// Billboards (paper 001, Sec. 4.1.2): the side chosen from where the eye is, the quad through
// the box's centre turned to face it, and, drawn, a cone (a tree's shape) seen obliquely
// looking more like its billboard than like its box.
#include "farfield/techniques/clusters/billboards.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "farfield/core/assert.hpp"
#include "farfield/core/image.hpp"
#include "farfield/eval/image_metrics.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// A 2 x 4 x 2 m box standing on the ground, each side's image 8 x 16 texels (the top 8 x 8).
TexturedBox standing_box() {
  TexturedBox box;
  box.bounds = {{-1, 0, -1}, {1, 4, 1}};
  for (int side = 0; side < 6; ++side)
    box.sides[side] = {uint16_t(side * 10), 0, 8, uint16_t(side == 2 || side == 3 ? 8 : 16)};
  return box;
}

TEST(Billboards, TheSideFacingTheEyeStandsThroughTheCentreTurnedToIt) {
  TexturedBox box = standing_box();
  EXPECT_EQ(billboard_side(box, {10, 2, 0}), 0);
  EXPECT_EQ(billboard_side(box, {-10, 3, 1}), 1);
  EXPECT_EQ(billboard_side(box, {1, 2, -10}), 5);
  EXPECT_EQ(billboard_side(box, {0.5f, 50, 0}), 2);  // from above: the top
  EXPECT_EQ(billboard_side(box, {0.5f, -50, 0}), 3);
  const glm::vec3 eye(10, 2, 7);
  TexturedMesh mesh;
  append_billboard(box, 64, eye, mesh);
  ASSERT_EQ(mesh.vertices.size(), 4u);
  ASSERT_EQ(mesh.indices.size(), 6u);
  const glm::vec3 centre = box.bounds.center();
  const glm::vec3 towards =
      glm::normalize(glm::vec3(eye.x, 0, eye.z) - glm::vec3(centre.x, 0, centre.z));
  float low = INFINITY, high = -INFINITY;
  for (const TexturedVertex& v : mesh.vertices) {
    EXPECT_NEAR(glm::dot(v.position - centre, towards), 0.0f, 1e-5f);  // through the centre
    EXPECT_NEAR(glm::length(glm::vec2(v.position.x, v.position.z)), 1.0f, 1e-5f);  // half 2 m
    low = std::min(low, v.position.y);
    high = std::max(high, v.position.y);
  }
  EXPECT_FLOAT_EQ(low, 0.0f);
  EXPECT_FLOAT_EQ(high, 4.0f);
  const glm::vec3 p0 = mesh.vertices[0].position, p1 = mesh.vertices[1].position,
                  p2 = mesh.vertices[2].position;
  EXPECT_GT(glm::dot(glm::cross(p1 - p0, p2 - p0), eye - centre), 0.0f);  // its front
  // The +x side's image: texels [0, 8) x [0, 16) of a 64-texel texture.
  EXPECT_FLOAT_EQ(mesh.vertices[0].uv.x, 0.0f);
  EXPECT_FLOAT_EQ(mesh.vertices[2].uv.x, 8.0f / 64.0f);
  EXPECT_FLOAT_EQ(mesh.vertices[2].uv.y, 16.0f / 64.0f);
  // From above the top lies flat through the centre.
  mesh = {};
  append_billboard(box, 64, {0.5f, 50, 0}, mesh);
  ASSERT_EQ(mesh.vertices.size(), 4u);
  for (const TexturedVertex& v : mesh.vertices) EXPECT_FLOAT_EQ(v.position.y, 2.0f);
  // An empty side gives way to the next best; with every side empty, nothing.
  box.sides[0].w = 0;
  EXPECT_EQ(billboard_side(box, {10, 2, 0.5f}), 4);
  for (BoxSide& s : box.sides) s.w = 0;
  EXPECT_EQ(billboard_side(box, {10, 2, 0}), -1);
  mesh = {};
  append_billboard(box, 64, {10, 2, 0}, mesh);
  EXPECT_TRUE(mesh.vertices.empty());
}

// A green cone of radius 1 and height 4, standing at the origin.
Scene cone() {
  Scene scene;
  SceneBuilder b(scene);
  const uint32_t green = b.add_material(Material{{0.2f, 0.6f, 0.2f, 1.0f}});
  b.begin_object("cone", ObjectKind::tree, green);
  constexpr int kSegments = 32;
  const uint32_t apex = b.add_vertex({0, 4, 0}, {0, 1, 0}, 0xffffffffu);
  for (int k = 0; k <= kSegments; ++k) {
    const float a = 2.0f * float(M_PI) * float(k) / kSegments;
    const glm::vec3 out(std::cos(a), 0.25f, std::sin(a));
    b.add_vertex({std::cos(a), 0, std::sin(a)}, glm::normalize(out), 0xffffffffu);
  }
  for (int k = 0; k < kSegments; ++k)
    b.add_triangle(apex, apex + 2 + uint32_t(k), apex + 1 + uint32_t(k));
  b.end_object();
  return scene;
}

TEST(BillboardsGL, AConeSeenObliquelyLooksMoreLikeItsBillboardThanItsBox) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  const Scene scene = cone();
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  Progress quiet(true);
  const ClusterTree tree = build_cluster_cells(scene, {});
  BoxSetOptions options;
  options.min_triangles = 1;
  options.page_px = 512;
  options.max_side_px = 128;
  auto boxes = bake_box_set(scene, tree, **renderer, options, quiet);
  ASSERT_TRUE(boxes) << boxes.error().message;
  ASSERT_EQ(boxes->boxes.size(), 1u);
  const TexturedBox& box = boxes->boxes[0];
  View view;
  view.width = 160;
  view.height = 120;
  view.hfov_deg = 40.0f;
  view.pose.position = {7.0f, 2.0f, 7.0f};  // 45 degrees between the +x and +z sides
  view.pose.yaw_deg = -135.0f;              // towards the cone
  view.pose.pitch_deg = 0.0f;
  (*renderer)->set_offscreen(view.width, view.height);
  DrawList list;
  list.opaque.push_back(
      {scene.objects[0].first_index, scene.objects[0].index_count, scene.objects[0].material, {}});
  (*renderer)->draw(view, list);
  const Image reference = (*renderer)->capture();
  const TextureHandle texture = (*renderer)->create_texture();
  auto frame_of = [&](const TexturedMesh& mesh) {
    auto handle = (*renderer)->create_textured_mesh(mesh.vertices, mesh.indices);
    FF_ASSERT(handle.ok(), "mesh");
    list.clear();
    list.uploads.push_back(
        {texture, boxes->page_px, boxes->page_px, 4, boxes->pages[0].data(), nullptr, true});
    list.meshes.push_back({*handle, 0, uint32_t(mesh.indices.size()), texture});
    (*renderer)->draw(view, list);
    return (*renderer)->capture();
  };
  const BoxMeshes box_mesh = box_meshes(*boxes);
  TexturedMesh billboard;
  append_billboard(box, boxes->page_px, view.pose.position, billboard);
  const Image box_frame = frame_of(box_mesh.pages[0]), billboard_frame = frame_of(billboard);
  const ImageComparison as_box = compare_images(reference, box_frame);
  const ImageComparison as_billboard = compare_images(reference, billboard_frame);
  ASSERT_GT(reference.width, 0);
  EXPECT_GT(as_billboard.psnr_db, as_box.psnr_db + 3.0)
      << "box " << as_box.differing_pixels << " pixels differ, billboard "
      << as_billboard.differing_pixels;
  // Their shading differs (a side's image is lit as seen from that side); their outlines:
  // pixels where one shows the cone and the other the sky.
  auto outline_misses = [&](const Image& drawn) {
    int misses = 0;
    auto sky = [&](const Image& im, int x, int y) {
      return std::equal(im.pixel(x, y), im.pixel(x, y) + 3, reference.pixel(0, 0));
    };
    for (int y = 0; y < view.height; ++y)
      for (int x = 0; x < view.width; ++x) misses += sky(reference, x, y) != sky(drawn, x, y);
    return misses;
  };
  EXPECT_LT(outline_misses(billboard_frame), outline_misses(box_frame) / 2);
}

}  // namespace
}  // namespace farfield
