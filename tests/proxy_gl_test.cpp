// Proxy geometry (DrawList::proxies): drawn unlit with its own colour, depth-tested against the
// scene, back faces culled. GL, headless; skipped without a context.
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
  ASSERT_TRUE((*renderer)->set_proxies(quad(-2.0f, green)));  // in front of the cube
  DrawList list;
  list.proxies.push_back({0, 6, 0});
  auto stats = (*renderer)->draw(view, list);
  EXPECT_EQ(stats.triangles, 2u);
  Image image = (*renderer)->capture();
  const uint8_t* centre = image.pixel(32, 24);
  EXPECT_EQ(centre[0], 0);
  EXPECT_EQ(centre[1], 255);  // exactly its colour: no lighting
  EXPECT_EQ(centre[2], 0);

  // Behind the cube: the cube's pixels win the depth test.
  ASSERT_TRUE((*renderer)->set_proxies(quad(3.0f, green)));
  list.opaque.push_back({0, 36, 0});
  (*renderer)->draw(view, list);
  image = (*renderer)->capture();
  EXPECT_NE(image.pixel(32, 24)[1], 255);
  EXPECT_GT(image.pixel(32, 24)[0], 100);  // red cube

  // Seen from behind, the quad is culled.
  view.pose.position = {0.5f, 0.5f, 6.0f};
  view.pose.yaw_deg = -90;
  list.opaque.clear();
  ASSERT_TRUE((*renderer)->set_proxies(quad(-2.0f, green)));
  (*renderer)->draw(view, list);
  image = (*renderer)->capture();
  EXPECT_NE(image.pixel(32, 24)[1], 255);
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
    mesh.vertices.insert(mesh.vertices.end(), {{{x, y, 0}, color}, {{x, y + 0.2f, 0}, color},
                                               {{x + 0.2f, y + 0.2f, 0}, color},
                                               {{x + 0.2f, y, 0}, color}});
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  ASSERT_TRUE((*renderer)->set_proxies(mesh));
  View view;
  view.width = 64;
  view.height = 48;
  view.pose.position = {0.0f, 0.0f, -3.0f};
  view.pose.yaw_deg = 90;
  (*renderer)->set_offscreen(view.width, view.height);
  DrawList one, many;
  one.proxies.push_back({0, uint32_t(mesh.indices.size()), 0});
  for (uint32_t i = 0; i < 100; ++i) many.proxies.push_back({6 * i, 6, 0});
  (*renderer)->draw(view, one);
  const Image a = (*renderer)->capture();
  (*renderer)->draw(view, many);
  const Image b = (*renderer)->capture();
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_EQ((*renderer)->draw(view, many).draw_calls, 100u);
}

}  // namespace
}  // namespace farfield
