// Walking through a scene: rays find the ground and the walls, the walk stops short of a wall,
// keeps the eye above the ground, and flies where there is no ground.
#include "farfield/spatial/walking.hpp"

#include <gtest/gtest.h>

#include "test_util.hpp"

namespace farfield {
namespace {

// A 20 m floor (top at y = 0) and a wall 3 m high across x = 3..4.
Scene floor_and_wall() {
  Scene scene = test::make_box_row(2);
  for (uint32_t o = 0; o < 2; ++o) {
    Object& object = scene.objects[o];
    object.bounds = Bounds3{};
    for (uint32_t v = object.first_vertex; v < object.first_vertex + object.vertex_count; ++v) {
      glm::vec3& p = scene.vertices[v].position;
      p = o == 0 ? glm::vec3(p.x * 20.0f - 10.0f, p.y * 0.2f - 0.2f, p.z * 20.0f - 10.0f)
                 : glm::vec3(p.x + 1.0f, p.y * 3.0f, p.z * 10.0f - 5.0f);
      object.bounds.expand(p);
    }
  }
  scene.bounds = Bounds3{};
  for (const Object& o : scene.objects) scene.bounds.expand(o.bounds);
  return scene;
}

CameraPose at(float x, float y, float z) {
  CameraPose p;
  p.position = {x, y, z};
  return p;
}

TEST(RayCaster, FindsTheNearestSurfaceOrNone) {
  const Scene scene = floor_and_wall();
  const RayCaster caster(scene);
  auto down = caster.cast({0, 5, 0}, {0, -1, 0}, 100);
  ASSERT_TRUE(down);
  EXPECT_NEAR(down->distance, 5.0f, 1e-4);
  EXPECT_EQ(down->object, 0u);
  auto ahead = caster.cast({0, 1, 0}, {1, 0, 0}, 100);
  ASSERT_TRUE(ahead);
  EXPECT_NEAR(ahead->distance, 3.0f, 1e-4);
  EXPECT_EQ(ahead->object, 1u);
  EXPECT_FALSE(caster.cast({0, 1, 0}, {1, 0, 0}, 2.5f));  // the wall is farther
  EXPECT_FALSE(caster.cast({0, 5, 0}, {0, 1, 0}, 100));   // nothing above
}

TEST(Walking, StopsShortOfWallsFollowsTheGroundAndFliesElsewhere) {
  const Scene scene = floor_and_wall();
  const RayCaster caster(scene);
  const WalkOptions o{.eye_height = 1.7f, .step_height = 0.5f, .clearance = 0.3f};
  // Into the wall: stopped 0.3 m before it.
  CameraPose p = walk(caster, at(0, 1.7f, 0), at(5, 1.7f, 0), o);
  EXPECT_NEAR(p.position.x, 2.7f, 1e-4);
  EXPECT_NEAR(p.position.y, 1.7f, 1e-4);
  // Along it: free.
  p = walk(caster, at(0, 1.7f, 0), at(0, 1.7f, 4), o);
  EXPECT_NEAR(p.position.z, 4.0f, 1e-4);
  // Too high after a climb: back to eye height over the floor.
  p = walk(caster, at(0, 3.0f, 0), at(1, 3.0f, 0), o);
  EXPECT_NEAR(p.position.y, 1.7f, 1e-4);
  // Off the floor there is no ground: the height is kept (flying).
  p = walk(caster, at(30, 40.0f, 0), at(31, 40.0f, 0), o);
  EXPECT_NEAR(p.position.y, 40.0f, 1e-4);
  EXPECT_NEAR(p.position.x, 31.0f, 1e-4);
  // Eye height scales down for small models.
  EXPECT_NEAR(walk_options_for(Bounds3{{0, 0, 0}, {1, 1, 1}}).eye_height, 0.1f, 1e-4);
  EXPECT_NEAR(walk_options_for(scene.bounds).eye_height, 1.7f, 1e-4);
}

}  // namespace
}  // namespace farfield
