// Textured scene geometry through the renderer, against a CPU ray cast of the same quad.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "farfield/eval/image_metrics.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/lighting.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/texture_image.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// The view at `eye`, towards -Z (yaw -90) or +Z (90), width x height.
View view_at(glm::vec3 eye, float yaw_deg, int width, int height) {
  View view;
  view.width = width;
  view.height = height;
  view.pose.position = eye;
  view.pose.yaw_deg = yaw_deg;
  return view;
}

// The given objects of `scene` drawn opaque by a renderer of their own, nearest sampling.
Result<Image> draw_objects(const Scene& scene, const View& view,
                           std::initializer_list<int> objects) {
  auto renderer = gpu::Renderer::create(scene);
  if (!renderer) return renderer.error();
  (*renderer)->set_texture_filter(gpu::Renderer::TextureFilter::nearest);
  (*renderer)->set_offscreen(view.width, view.height);
  DrawList list;
  for (int i : objects) {
    const Object& o = scene.objects[size_t(i)];
    list.opaque.push_back({o.first_index, o.index_count, o.material});
  }
  (*renderer)->draw(view, list);
  return (*renderer)->capture();
}

// The quad of make_textured_scene (x in [-1, 1], y in [0, 2], z = 3, facing +Z, texture
// coordinates (0, 0) at its top-left corner) seen from in front, nearest sampling: every
// pixel is what a ray through its centre sees (the checker texel under the hit, lit as the
// shader lights a +Z face; the sky elsewhere), within one unit of rounding, except pixels
// whose centre lies within a pixel of a texel boundary or the quad's edge.
TEST(TextureGL, TexturedQuadMatchesARayCast) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  const Scene scene = test::make_textured_scene();
  const View view = view_at({0.1f, 1.05f, 5.0f}, -90.0f, 160, 120);
  auto drawn = draw_objects(scene, view, {1});
  ASSERT_TRUE(drawn) << drawn.error().message;
  const Image& image = *drawn;
  if (const char* dump = std::getenv("FARFIELD_DUMP")) (void)write_png(image, dump);

  auto texels = decode_texture(scene.textures[0]);
  ASSERT_TRUE(texels);
  const glm::mat4 inverse = glm::inverse(view.view_projection());
  const glm::vec3 lit = gpu::shade({0.0f, 0.0f, 1.0f}, glm::vec3(1.0f)) * 255.0f;
  int equal = 0, edges = 0, wrong = 0, textured = 0;
  for (int y = 0; y < view.height; ++y) {
    for (int x = 0; x < view.width; ++x) {
      // The ray through the pixel centre (rows from the top), hit with the plane z = 3.
      const glm::vec2 ndc((x + 0.5f) / view.width * 2.0f - 1.0f,
                          1.0f - (y + 0.5f) / view.height * 2.0f);
      glm::vec4 far = inverse * glm::vec4(ndc, 0.5f, 1.0f);
      const glm::vec3 through = glm::vec3(far) / far.w, eye = view.pose.position;
      const glm::vec3 d = glm::normalize(through - eye);
      const float t = (3.0f - eye.z) / d.z;
      const glm::vec3 hit = eye + t * d;
      const glm::vec2 uv((hit.x + 1.0f) / 2.0f, (2.0f - hit.y) / 2.0f);
      const bool inside = uv.x >= 0 && uv.x < 1 && uv.y >= 0 && uv.y < 1;
      glm::vec3 expected;
      if (inside) {
        ++textured;
        const uint8_t* texel = texels->texel(int(uv.x * 4), int(uv.y * 4));
        expected = texel[0] ? lit : glm::vec3(0.0f);
      } else {
        expected = glm::vec3(gpu::kSkyColor[0], gpu::kSkyColor[1], gpu::kSkyColor[2]) * 255.0f;
      }
      const uint8_t* got = image.pixel(x, y);
      bool same = true;
      for (int c = 0; c < 3; ++c) same = same && std::abs(got[c] - std::lround(expected[c])) <= 1;
      if (same) {
        ++equal;
        continue;
      }
      // Within a pixel (about 0.05 in texture coordinates here) of a boundary?
      const float pixel = 2.0f * t / view.width / 2.0f;
      const glm::vec2 cells = uv * 4.0f;
      const bool near_edge = std::abs(cells.x - std::round(cells.x)) < 4.0f * pixel ||
                             std::abs(cells.y - std::round(cells.y)) < 4.0f * pixel;
      (near_edge ? edges : wrong)++;
    }
  }
  EXPECT_GT(textured, view.width * view.height / 5);  // the quad fills a good part of the view
  EXPECT_GE(equal, int(0.99 * view.width * view.height)) << edges << " on edges, " << wrong;
  std::printf("%d of %d pixels equal to the ray cast, %d on edges\n", equal,
              view.width * view.height, edges);
  EXPECT_EQ(wrong, 0);
}

// Mask materials cut out where the texture's alpha is below the cutoff: the sky shows there.
TEST(TextureGL, MaskMaterialsCutOutTransparentTexels) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  Scene scene = test::make_textured_scene(AlphaMode::mask);
  RgbaImage half(2, 1);  // left texel opaque red, right texel transparent
  half.texel(0, 0)[0] = 255;
  half.texel(0, 0)[3] = 255;
  auto texture = texture_from_texels("half.png", half);
  ASSERT_TRUE(texture);
  scene.textures[0] = std::move(*texture);
  const View view = view_at({0.0f, 1.0f, 5.0f}, -90.0f, 64, 48);
  auto drawn = draw_objects(scene, view, {1});
  ASSERT_TRUE(drawn) << drawn.error().message;
  const Image& image = *drawn;
  const uint8_t* left = image.pixel(view.width / 2 - 6, view.height / 2);
  const uint8_t* right = image.pixel(view.width / 2 + 6, view.height / 2);
  EXPECT_GT(left[0], 100);
  EXPECT_LT(left[2], 10);                                          // red
  EXPECT_NEAR(right[2], std::lround(gpu::kSkyColor[2] * 255), 1);  // sky
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  EXPECT_GT((*renderer)->scene_texture_bytes(), 0u);
}

// A double-sided material shows its back (lit from the eye's side); a single-sided one is
// culled there, as before.
TEST(TextureGL, DoubleSidedMaterialsShowTheirBacks) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  // Behind the quad at z = 3, which faces +Z, looking towards +Z.
  const View view = view_at({0.0f, 1.0f, 1.0f}, 90.0f, 64, 48);
  const uint8_t sky = uint8_t(std::lround(gpu::kSkyColor[2] * 255));
  for (bool double_sided : {false, true}) {
    Scene scene = test::make_textured_scene();
    scene.materials[scene.objects[1].material].double_sided = double_sided;
    auto drawn = draw_objects(scene, view, {1, 0});
    ASSERT_TRUE(drawn) << drawn.error().message;
    const uint8_t* centre = drawn->pixel(view.width / 2, view.height / 2);
    if (double_sided)
      EXPECT_NE(centre[2], sky) << "the back of a double-sided quad must be drawn";
    else
      EXPECT_EQ(centre[2], sky) << "a single-sided quad is culled from behind";
  }
}

// Scene meshes (Device::create_scene_mesh: a technique's own geometry in the scene's format)
// are drawn as the scene's own buffers are: a copy of both objects, the textured quad and the
// untextured box, as one scene mesh gives the same pixels as the scene's ranges, textures,
// lighting and materials alike. A mesh without texture coordinates draws untextured ranges.
TEST(TextureGL, SceneMeshesDrawLikeTheScene) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  const Scene scene = test::make_textured_scene();
  const View view = view_at({0.6f, 1.0f, 6.0f}, -90.0f, 96, 72);
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  (*renderer)->set_offscreen(view.width, view.height);
  DrawList scene_ranges, mesh_ranges;
  std::vector<glm::vec2> uvs(scene.vertices.size());
  for (const Object& o : scene.objects) {
    scene_ranges.opaque.push_back({o.first_index, o.index_count, o.material});
    if (scene.textured(o))
      std::copy_n(scene.uvs.begin() + o.first_uv, o.vertex_count, uvs.begin() + o.first_vertex);
  }
  (*renderer)->draw(view, scene_ranges);
  const Image reference = (*renderer)->capture();
  auto mesh = (*renderer)->create_scene_mesh(scene.vertices, uvs, scene.indices);
  ASSERT_TRUE(mesh) << mesh.error().message;
  for (const Object& o : scene.objects)
    mesh_ranges.opaque.push_back({o.first_index, o.index_count, o.material, *mesh});
  EXPECT_EQ(mesh_ranges.mesh_triangle_count(), scene.triangle_count());
  EXPECT_EQ(mesh_ranges.triangle_count(), scene.triangle_count());  // counted once
  (*renderer)->draw(view, mesh_ranges);
  const ImageComparison same = compare_images(reference, (*renderer)->capture());
  EXPECT_TRUE(same.identical()) << same.differing_pixels << " pixels differ";
  // The box alone from a mesh without texture coordinates.
  auto box = (*renderer)->create_scene_mesh(scene.vertices, {}, scene.indices);
  ASSERT_TRUE(box);
  const Object& o = scene.objects[0];
  mesh_ranges.opaque = {{o.first_index, o.index_count, o.material, *box}};
  scene_ranges.opaque = {{o.first_index, o.index_count, o.material}};
  (*renderer)->draw(view, scene_ranges);
  const Image box_reference = (*renderer)->capture();
  (*renderer)->draw(view, mesh_ranges);
  EXPECT_TRUE(compare_images(box_reference, (*renderer)->capture()).identical());
  const uint64_t before = (*renderer)->resource_bytes();
  (*renderer)->free(*box);
  EXPECT_LT((*renderer)->resource_bytes(), before);
}

}  // namespace
}  // namespace farfield
