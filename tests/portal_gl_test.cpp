// Portal rendering is conservative on a generated building: along its interior path and from
// random places in its rooms, corridors and stairwell, `portal` and `portal-paper` frames
// equal brute force's pixel for pixel (GL, headless; skipped without a context).
#include <gtest/gtest.h>

#include <random>

#include "farfield/eval/image_metrics.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/building_generator.hpp"
#include "farfield/spatial/interior_path.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

TEST(PortalGL, FramesOfABuildingEqualBruteForce) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  BuildingOptions options;
  options.floors = 3;
  options.rooms_per_side = 8;
  options.segment_rooms = 2;
  options.books = 20;
  Progress quiet(true);
  auto scene = generate_building(options, quiet);
  ASSERT_TRUE(scene) << scene.error().message;
  auto renderer = gpu::Renderer::create(*scene);
  ASSERT_TRUE(renderer) << renderer.error().message;
  auto brute = make_technique("brute");
  auto portal = make_technique("portal");
  auto paper = make_technique("portal-paper");
  for (auto* t : {&brute, &portal, &paper})
    ASSERT_TRUE(test::load_technique(***t, *scene, renderer->get()));

  PathOptions walk;
  walk.kind = "interior";
  walk.frames = 400;
  auto path = interior_path(*scene, walk);
  ASSERT_TRUE(path) << path.error().message;
  std::vector<View> views;
  for (size_t i = 0; i < path->frames.size(); i += 8) views.push_back({path->frames[i]});
  std::mt19937 rng(7);
  std::uniform_int_distribution<uint32_t> cell(1, uint32_t(scene->cells.size() - 1));
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), yaw(0.0f, 360.0f), pitch(-40.0f, 40.0f);
  for (int i = 0; i < 30; ++i) {
    const Bounds3 b = scene->cells[cell(rng)].bounds;
    const glm::vec3 inner = b.min + glm::vec3(0.4f, 0.0f, 0.4f);
    const glm::vec3 span = b.size() - glm::vec3(0.8f, 0.0f, 0.8f);
    const float y = b.min.y + 0.5f + unit(rng) * std::min(2.4f, b.size().y - 0.9f);
    views.push_back(
        {{{inner.x + unit(rng) * span.x, y, inner.z + unit(rng) * span.z}, yaw(rng), pitch(rng)}});
  }
  DrawList list;
  uint64_t drawn = 0, all = 0;
  for (size_t i = 0; i < views.size(); ++i) {
    View view = views[i];
    view.width = 256;
    view.height = 192;
    (*renderer)->set_offscreen(view.width, view.height);
    test::select_view(**brute, view, list);
    all += list.triangle_count();
    (*renderer)->draw(view, list);
    const Image reference = (*renderer)->capture();
    for (auto* t : {&portal, &paper}) {
      test::select_view(***t, view, list);
      if (t == &portal) drawn += list.triangle_count();
      (*renderer)->draw(view, list);
      const ImageComparison c = compare_images(reference, (*renderer)->capture());
      EXPECT_TRUE(c.identical()) << (**t)->name() << " view " << i << ": " << c.differing_pixels
                                 << " pixels differ";
    }
  }
  EXPECT_LT(double(drawn), 0.2 * double(all));  // the portals hid most of the building
}

}  // namespace
}  // namespace farfield
