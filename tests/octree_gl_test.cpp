// The octree technique is conservative: on random views of a generated city its frames equal
// brute force's pixel for pixel (GL, headless; skipped without a context).
#include <gtest/gtest.h>

#include <random>

#include "farfield/eval/image_metrics.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/city_generator.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// Draws random views of a small city with brute and with `octree` made with `settings`:
// every frame must be identical; returns the share of brute's triangles the octree drew.
double octree_against_brute(std::initializer_list<const char*> settings) {
  auto context = gpu::create_headless_context();
  if (!context) return -1.0;
  CityOptions options;
  options.blocks_x = options.blocks_z = 3;
  Progress quiet(true);
  auto city = generate_city(options, quiet);
  EXPECT_TRUE(city) << city.error().message;
  auto renderer = gpu::Renderer::create(*city);
  EXPECT_TRUE(renderer) << renderer.error().message;
  auto brute = make_technique("brute");
  auto octree = make_technique("octree", test::settings_of(settings));
  EXPECT_TRUE(test::load_technique(**brute, *city, renderer->get()));
  EXPECT_TRUE(test::load_technique(**octree, *city, renderer->get()));

  const Bounds3 b = city->bounds;
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> x(b.min.x, b.max.x), z(b.min.z, b.max.z), yaw(0.0f, 360.0f),
      street_pitch(-20.0f, 30.0f), air_pitch(-80.0f, -10.0f), air_height(b.max.y, 3.0f * b.max.y);
  DrawList all, culled;
  uint64_t culled_triangles = 0, all_triangles = 0;
  const int views = 60;
  for (int i = 0; i < views; ++i) {
    View view;
    view.width = 256;
    view.height = 192;
    // Two thirds at street level (eye height above the street), a third from the air.
    const bool street = i % 3 != 2;
    view.pose = {{x(rng), street ? 1.9f : air_height(rng), z(rng)},
                 yaw(rng),
                 street ? street_pitch(rng) : air_pitch(rng)};
    (*renderer)->set_offscreen(view.width, view.height);
    test::select_view(**brute, view, all);
    (*renderer)->draw(view, all);
    const Image reference = (*renderer)->capture();
    test::select_view(**octree, view, culled);
    (*renderer)->draw(view, culled);
    const Image image = (*renderer)->capture();
    const ImageComparison c = compare_images(reference, image);
    EXPECT_TRUE(c.identical()) << "view " << i << ": " << c.differing_pixels
                               << " pixels differ, PSNR " << c.psnr_db;
    culled_triangles += culled.triangle_count();
    all_triangles += all.triangle_count();
  }
  return double(culled_triangles) / double(all_triangles);
}

TEST(OctreeGL, FramesEqualBruteOnRandomCityViews) {
  const double share = octree_against_brute({});
  if (share < 0) GTEST_SKIP() << "no GL context";
  // The views are not trivially everything: culling removed a good share.
  EXPECT_LT(share, 0.8);
}

TEST(OctreeGL, OcclusionKeepsTheFramesOfBrute) {
  const double frustum_only = octree_against_brute({});
  if (frustum_only < 0) GTEST_SKIP() << "no GL context";
  // Occluders hid something that the frustum let through, the objects' own triangles more than
  // the boxes inside them.
  const double meshes = octree_against_brute({"octree.occlusion=1"});
  const double boxes = octree_against_brute({"octree.occlusion=1", "octree.occluders=boxes"});
  EXPECT_LT(boxes, 0.95 * frustum_only);
  EXPECT_LT(meshes, boxes);
}

}  // namespace
}  // namespace farfield
