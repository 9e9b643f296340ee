// generate building: the default scene's size, determinism, closed rooms (portal rendering
// equals brute force, tests/portal_gl_test.cpp), its interior path, and bad options.
#include "farfield/scene/building_generator.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "farfield/spatial/interior_path.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

BuildingOptions small_building() {
  BuildingOptions o;
  o.floors = 3;
  o.rooms_per_side = 8;
  o.segment_rooms = 2;
  o.books = 20;
  return o;
}

size_t rooms_of(const Scene& scene) {
  return size_t(std::count_if(scene.cells.begin(), scene.cells.end(), [&](const Cell& c) {
    return scene.cell_name(c).find("/room_") != std::string_view::npos;
  }));
}

TEST(BuildingGenerator, TheDefaultHasMillionsOfTrianglesAndAThousandRooms) {
  Progress quiet(true);
  auto scene = generate_building({}, quiet);
  ASSERT_TRUE(scene) << scene.error().message;
  EXPECT_GE(scene->triangle_count(), 5'000'000u);
  EXPECT_GE(rooms_of(*scene), 1000u);
  // A door and two windows a room, an open portal between corridor segments, two stairwell
  // doors a floor.
  const BuildingOptions o;
  const size_t segments = (o.rooms_per_side + o.segment_rooms - 1) / o.segment_rooms;
  EXPECT_EQ(scene->portals.size(), 3 * rooms_of(*scene) + o.floors * (segments - 1 + 2));
}

TEST(BuildingGenerator, IsDeterministicAndValid) {
  Progress quiet(true);
  auto a = generate_building(small_building(), quiet);
  auto b = generate_building(small_building(), quiet);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(scene_fingerprint(*a), scene_fingerprint(*b));
  EXPECT_EQ(validate_scene(*a), "");
  EXPECT_EQ(rooms_of(*a), 3u * (2 * 8 - 2));
  BuildingOptions other = small_building();
  other.seed = 2;
  auto c = generate_building(other, quiet);
  ASSERT_TRUE(c);
  EXPECT_NE(scene_fingerprint(*a), scene_fingerprint(*c));
  // Every object is seen from some cell.
  std::vector<bool> listed(a->objects.size(), false);
  for (uint32_t o : a->cell_objects) listed[o] = true;
  EXPECT_TRUE(std::all_of(listed.begin(), listed.end(), [](bool x) { return x; }));
}

TEST(BuildingGenerator, RefusesAbsurdOptions) {
  Progress quiet(true);
  for (auto [change, option] :
       std::initializer_list<std::pair<void (*)(BuildingOptions&), const char*>>{
           {[](BuildingOptions& o) { o.floors = 0; }, "--floors"},
           {[](BuildingOptions& o) { o.rooms_per_side = 2; }, "--rooms"},
           {[](BuildingOptions& o) { o.room_depth = 1.0; }, "--room-depth"},
           {[](BuildingOptions& o) { o.storey = NAN; }, "--storey"},
           {[](BuildingOptions& o) { o.segment_rooms = 0; }, "--segment-rooms"}}) {
    BuildingOptions o = small_building();
    change(o);
    auto scene = generate_building(o, quiet);
    ASSERT_FALSE(scene) << option;
    EXPECT_NE(scene.error().message.find(option), std::string::npos) << scene.error().message;
  }
}

TEST(InteriorPath, WalksFromRoomToRoomAndUpTheStairs) {
  Progress quiet(true);
  auto scene = generate_building(small_building(), quiet);
  ASSERT_TRUE(scene);
  PathOptions o;
  o.kind = "interior";
  o.frames = 600;
  auto path = interior_path(*scene, o);
  ASSERT_TRUE(path) << path.error().message;
  ASSERT_EQ(path->frames.size(), 600u);
  float low = INFINITY, high = -INFINITY;
  std::vector<uint32_t> rooms;
  for (size_t i = 0; i < path->frames.size(); ++i) {
    const glm::vec3 eye = path->frames[i].position;
    low = std::min(low, eye.y), high = std::max(high, eye.y);
    if (i > 0) {
      EXPECT_LE(glm::distance(eye, path->frames[i - 1].position), 0.15f + 1e-3f) << i;
    }
    // Never outside the building's cells (cell 0 is the outside).
    const auto cell = cell_containing(*scene, eye);
    ASSERT_TRUE(cell) << i;
    EXPECT_NE(*cell, 0u) << i;
    const std::string_view name = scene->cell_name(scene->cells[*cell]);
    if (name.find("/room_") != std::string_view::npos &&
        std::find(rooms.begin(), rooms.end(), *cell) == rooms.end())
      rooms.push_back(*cell);
  }
  EXPECT_GE(rooms.size(), 3u);    // room to room
  EXPECT_GT(high - low, 3.5f);    // up at least one storey
  EXPECT_NEAR(low, 1.7f, 0.05f);  // at eye height over the ground floor

  // Scenes without rooms are refused, naming what is missing.
  auto none = interior_path(test::make_box_row(3), o);
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().message.find("cells and portals"), std::string::npos);
}

}  // namespace
}  // namespace farfield
