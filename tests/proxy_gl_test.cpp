// Technique meshes (DrawList::meshes) by handle: proxy meshes drawn unlit with their own
// colour, textured meshes with colour x texture, both depth-tested against the scene, back
// faces culled; several meshes side by side. GL, headless; skipped without a context.
#include <gtest/gtest.h>

#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// A quad facing -Z at depth z, covering x, y in [-1, 1].
ProxyMesh quad(float z, uint32_t color) {
  ProxyMesh m;
  m.vertices = {{{-1, -1, z}, color}, {{-1, 1, z}, color}, {{1, 1, z}, color}, {{1, -1, z}, color}};
  m.indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise seen from -Z
  return m;
}

TEST(ProxyGL, DrawnUnlitDepthTestedAndCulled) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  const Scene scene = test::make_box_row(1);  // a unit cube at [0,1]^3, opaque red
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  View view;
  view.width = 64;
  view.height = 48;
  view.pose.position = {0.5f, 0.5f, -6.0f};
  view.pose.yaw_deg = 90;  // looking along +Z
  (*renderer)->set_offscreen(view.width, view.height);

  const uint32_t green = pack_color({0.0f, 1.0f, 0.0f, 1.0f});
  const ProxyMesh in_front = quad(-2.0f, green), behind = quad(3.0f, green);
  auto front_mesh = (*renderer)->create_mesh(in_front.vertices, in_front.indices);
  auto back_mesh = (*renderer)->create_mesh(behind.vertices, behind.indices);
  ASSERT_TRUE(front_mesh && back_mesh);
  DrawList list;
  list.meshes.push_back({*front_mesh, 0, 6, {}});
  auto stats = (*renderer)->draw(view, list);
  EXPECT_EQ(stats.triangles, 2u);
  Image image = (*renderer)->capture();
  const uint8_t* centre = image.pixel(32, 24);
  EXPECT_EQ(centre[0], 0);
  EXPECT_EQ(centre[1], 255);  // exactly its colour: no lighting
  EXPECT_EQ(centre[2], 0);

  // Behind the cube: the cube's pixels win the depth test.
  list.meshes = {{*back_mesh, 0, 6, {}}};
  list.opaque.push_back({0, 36, 0});
  (*renderer)->draw(view, list);
  image = (*renderer)->capture();
  EXPECT_NE(image.pixel(32, 24)[1], 255);
  EXPECT_GT(image.pixel(32, 24)[0], 100);  // red cube

  // Seen from behind, the quad is culled.
  view.pose.position = {0.5f, 0.5f, 6.0f};
  view.pose.yaw_deg = -90;
  list.opaque.clear();
  list.meshes = {{*front_mesh, 0, 6, {}}};
  (*renderer)->draw(view, list);
  image = (*renderer)->capture();
  EXPECT_NE(image.pixel(32, 24)[1], 255);
  (*renderer)->free(*front_mesh);
  (*renderer)->free(*back_mesh);
}

// A textured quad: colour x texture per texel, depth-tested; texels of alpha 0 are cut out
// (the scene behind shows through and no depth is written there).
TEST(ProxyGL, TexturedMeshesShowTheirTextureAndCutOutClearTexels) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  const Scene scene = test::make_box_row(1);
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  View view;
  view.width = 64;
  view.height = 48;
  view.pose.position = {0.5f, 0.5f, -6.0f};
  view.pose.yaw_deg = 90;
  (*renderer)->set_offscreen(view.width, view.height);
  // A 4x1 texture: two opaque blue texels, then two clear ones (filtering between the clear
  // texels leaves them clear).
  const uint8_t texels[16] = {0, 0, 255, 255, 0, 0, 255, 255, 255, 255, 255, 0, 255, 255, 255, 0};
  const uint32_t white = pack_color(glm::vec4(1.0f));
  const std::vector<TexturedVertex> vertices = {{{-1, -1, -2}, {0, 1}, white},
                                                {{-1, 2, -2}, {0, 0}, white},
                                                {{1.4f, 2, -2}, {1, 0}, white},
                                                {{1.4f, -1, -2}, {1, 1}, white}};
  const std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3};
  auto mesh = (*renderer)->create_textured_mesh(vertices, indices);
  ASSERT_TRUE(mesh);
  const TextureHandle texture = (*renderer)->create_texture();
  DrawList list;
  list.opaque.push_back({0, 36, 0});
  list.uploads.push_back({texture, 4, 1, 4, texels, nullptr});
  list.meshes.push_back({*mesh, 0, 6, texture});
  (*renderer)->draw(view, list);
  const Image image = (*renderer)->capture();
  // The quad spans x in [-1, 1.4] at z = -2 (u = (x + 1) / 2.4); the unit cube behind it
  // spans [0, 1], seen through x in [-0.17, 0.83] of the quad.
  auto at_world_x = [&](float x) {
    const glm::vec4 clip = view.view_projection() * glm::vec4(x, 0.5f, -2.0f, 1.0f);
    const int px = int((clip.x / clip.w * 0.5f + 0.5f) * float(view.width));
    return image.pixel(px, 24);
  };
  const uint8_t* left = at_world_x(-0.6f);  // a blue texel, nothing behind
  EXPECT_EQ(left[0], 0);
  EXPECT_EQ(left[2], 255);
  const uint8_t* right = at_world_x(0.7f);  // between the clear texels, over the red cube
  EXPECT_GT(right[0], 100);
  EXPECT_LT(right[2], 100);
  EXPECT_GT((*renderer)->resource_bytes(), 0u);
  (*renderer)->free(*mesh);
  (*renderer)->free(texture);
}

TEST(ProxyGL, ManyRangesDrawTheSameAsOne) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  const Scene scene = test::make_box_row(1);
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  // A 10 x 10 checkerboard of small quads, each its own range (more than one call's worth).
  ProxyMesh mesh;
  for (int i = 0; i < 100; ++i) {
    const float x = -1.0f + 0.2f * float(i % 10), y = -1.0f + 0.2f * float(i / 10);
    const uint32_t color = pack_color(i % 2 ? glm::vec4(1, 1, 0, 1) : glm::vec4(0, 0, 1, 1));
    const uint32_t base = uint32_t(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), {{{x, y, 0}, color},
                                               {{x, y + 0.2f, 0}, color},
                                               {{x + 0.2f, y + 0.2f, 0}, color},
                                               {{x + 0.2f, y, 0}, color}});
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  auto handle = (*renderer)->create_mesh(mesh.vertices, mesh.indices);
  ASSERT_TRUE(handle);
  View view;
  view.width = 64;
  view.height = 48;
  view.pose.position = {0.0f, 0.0f, -3.0f};
  view.pose.yaw_deg = 90;
  (*renderer)->set_offscreen(view.width, view.height);
  DrawList one, many;
  one.meshes.push_back({*handle, 0, uint32_t(mesh.indices.size()), {}});
  for (uint32_t i = 0; i < 100; ++i) many.meshes.push_back({*handle, 6 * i, 6, {}});
  (*renderer)->draw(view, one);
  const Image a = (*renderer)->capture();
  (*renderer)->draw(view, many);
  const Image b = (*renderer)->capture();
  EXPECT_EQ(a.rgb, b.rgb);
  // More ranges of one mesh than one call's worth are gathered into one draw.
  EXPECT_EQ((*renderer)->draw(view, many).draw_calls, 1u);
  EXPECT_EQ((*renderer)->draw(view, one).draw_calls, 1u);
}

}  // namespace
}  // namespace farfield
