// The clusters bake's occluder boxes (techniques/clusters/occluder_boxes.hpp): each object's
// inscribed box, kept in a pack and read back; a damaged table is named; occluders given the
// boxes fill the same map as occluders that find them.
#include <gtest/gtest.h>

#include "farfield/core/frustum.hpp"
#include "farfield/scene/city_generator.hpp"
#include "farfield/spatial/occluders.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/clusters/occluder_boxes.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

Scene small_city() {
  CityOptions options;
  options.blocks_x = options.blocks_z = 2;
  Progress quiet(true);
  auto city = generate_city(options, quiet);
  EXPECT_TRUE(city) << city.error().message;
  return std::move(*city);
}

TEST(OccluderBoxes, FoundKeptAndReadBack) {
  const Scene city = small_city();
  Progress quiet(true);
  const std::vector<Bounds3> boxes = find_occluder_boxes(city, 0, quiet);
  ASSERT_EQ(boxes.size(), city.objects.size());
  size_t found = 0;
  for (uint32_t i = 0; i < boxes.size(); ++i) {
    const std::optional<Bounds3> box = inscribed_box(city, i);
    ASSERT_EQ(box.has_value(), !boxes[i].empty()) << "object " << i;
    if (box) {
      EXPECT_EQ(box->min, boxes[i].min);
      EXPECT_EQ(box->max, boxes[i].max);
      ++found;
    }
  }
  EXPECT_GT(found, boxes.size() / 4) << "the buildings have boxes inside";
  test::TempDir dir;
  auto store = Store::open(dir.file("p.ffpack"), Store::Mode::kReadWrite);
  ASSERT_TRUE(store);
  ASSERT_TRUE(save_occluder_boxes(boxes, *store));
  auto back = load_occluder_boxes(*store, city);
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_TRUE(test::same_bytes(*back, boxes));

  // The same map from the given boxes as from those found on the way.
  View view;
  view.width = 256;
  view.height = 192;
  view.pose = {{8.0f, 1.9f, 8.0f}, 0.0f, 0.0f};
  const Frustum frustum(view);
  OcclusionMap given_map, found_map;
  Occluders given(city, {}, boxes), finding(city);
  given.fill(given_map, view, frustum);
  finding.fill(found_map, view, frustum);
  ASSERT_GT(given_map.occluders(), 0u);
  EXPECT_EQ(given_map.occluders(), found_map.occluders());
  for (uint32_t i = 0; i < city.objects.size(); ++i)
    EXPECT_EQ(given_map.hidden(city.objects[i].bounds), found_map.hidden(city.objects[i].bounds));
}

TEST(OccluderBoxes, ADamagedTableIsNamed) {
  const Scene city = small_city();
  Progress quiet(true);
  std::vector<Bounds3> boxes = find_occluder_boxes(city, 0, quiet);
  test::TempDir dir;
  auto store = Store::open(dir.file("p.ffpack"), Store::Mode::kReadWrite);
  ASSERT_TRUE(store);
  auto refused = [&](const std::vector<Bounds3>& saved) {
    EXPECT_TRUE(save_occluder_boxes(saved, *store));
    auto back = load_occluder_boxes(*store, city);
    EXPECT_FALSE(back);
    return back ? std::string() : back.error().message;
  };
  std::vector<Bounds3> fewer(boxes.begin(), boxes.end() - 1);
  std::string message = refused(fewer);
  EXPECT_NE(message.find("p.ffpack"), std::string::npos) << message;
  EXPECT_NE(message.find("clusters/occluder_boxes"), std::string::npos) << message;
  EXPECT_NE(message.find("one box per object"), std::string::npos) << message;
  std::vector<Bounds3> outside = boxes;
  outside[0] = city.objects[0].bounds;
  outside[0].max.y += 50.0f;
  message = refused(outside);
  EXPECT_NE(message.find("outside its object"), std::string::npos) << message;
  std::vector<Bounds3> not_a_number = boxes;
  not_a_number[0].min.x = std::nanf("");
  not_a_number[0].max = not_a_number[0].min;
  message = refused(not_a_number);
  EXPECT_NE(message.find("outside its object"), std::string::npos) << message;
}

}  // namespace
}  // namespace farfield
