// Which occluders clusters culls with (clusters.occluders): the objects' own triangles hide at
// least what boxes inside them hide, and auto takes them without a budget.
#include <gtest/gtest.h>

#include "farfield/scene/city_generator.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

uint64_t street_triangles(const Scene& city, std::initializer_list<const char*> settings) {
  auto clusters = make_technique("clusters", test::settings_of(settings));
  EXPECT_TRUE(clusters) << clusters.error().message;
  EXPECT_TRUE(test::load_technique(**clusters, city));
  View view;
  view.width = 256;
  view.height = 192;
  view.pose = {{8.0f, 1.9f, 8.0f}, 0.0f, 0.0f};  // at the first crossing, along the street
  DrawList list;
  test::select_view(**clusters, view, list);
  EXPECT_TRUE(settings.size() == 1 || list.occlusion_ms >= 0.0);
  return list.triangle_count();
}

TEST(ClustersOccluders, MeshesHideMoreThanBoxesAndAutoTakesThemWithoutABudget) {
  CityOptions options;
  options.blocks_x = options.blocks_z = 2;
  Progress quiet(true);
  auto city = generate_city(options, quiet);
  ASSERT_TRUE(city);
  const uint64_t none = street_triangles(*city, {"clusters.occlusion=0"});
  const uint64_t boxes =
      street_triangles(*city, {"clusters.occlusion=1", "clusters.occluders=boxes"});
  const uint64_t meshes =
      street_triangles(*city, {"clusters.occlusion=1", "clusters.occluders=meshes"});
  const uint64_t automatic =
      street_triangles(*city, {"clusters.occlusion=1", "clusters.occluders=auto"});
  EXPECT_LT(boxes, none);
  EXPECT_LT(meshes, boxes);
  EXPECT_EQ(automatic, meshes);
}

}  // namespace
}  // namespace farfield
