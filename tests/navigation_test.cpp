#include "farfield/core/navigation.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "farfield/core/view_sphere.hpp"

namespace farfield {
namespace {

constexpr float kTolerance = 1e-4f;

TEST(Navigation, ForwardFollowsTheHeadingAndKeepsHeight) {
  CameraPose p;
  p.position = {0, 1.7f, 0};
  p.pitch_deg = -30;  // looking down does not make the walker sink
  p = navigate(p, {.forward = 1}, {.move_m_per_s = 10}, 0.5f);
  EXPECT_NEAR(p.position.x, 5.0f, kTolerance);
  EXPECT_NEAR(p.position.y, 1.7f, kTolerance);
  EXPECT_NEAR(p.position.z, 0.0f, kTolerance);
  p = navigate(p, {.forward = -1}, {.move_m_per_s = 10}, 1.0f);
  EXPECT_NEAR(p.position.x, -5.0f, kTolerance);
}

TEST(Navigation, TurningRightTurnsClockwiseFromAbove) {
  CameraPose p;
  p = navigate(p, {.turn = 1}, {.turn_deg_per_s = 90}, 1.0f);
  EXPECT_NEAR(p.yaw_deg, 90.0f, kTolerance);
  EXPECT_NEAR(glm::distance(p.forward(), glm::vec3(0, 0, 1)), 0.0f, kTolerance);
  // The camera's right, before the turn, pointed where it now looks.
  EXPECT_NEAR(glm::distance(CameraPose{}.right(), p.forward()), 0.0f, kTolerance);
  p = navigate(p, {.turn = -1}, {.turn_deg_per_s = 90}, 2.0f);
  EXPECT_NEAR(p.yaw_deg, 270.0f, kTolerance);  // wrapped into [0, 360)
}

TEST(Navigation, ClimbLookAndFast) {
  CameraPose p;
  p = navigate(p, {.climb = 1, .look = 1}, {.climb_m_per_s = 2, .look_deg_per_s = 100}, 1.0f);
  EXPECT_NEAR(p.position.y, 2.0f, kTolerance);
  EXPECT_NEAR(p.pitch_deg, 89.0f, kTolerance);  // clamped short of straight up
  p = navigate(p, {.climb = -1, .look = -1, .fast = true},
               {.climb_m_per_s = 2, .look_deg_per_s = 10}, 1.0f);
  EXPECT_NEAR(p.position.y, -8.0f, kTolerance);
  EXPECT_NEAR(p.pitch_deg, 79.0f, kTolerance);  // looking is not boosted
}

TEST(Orbit, ThroughAPoseOnTheSphereFindsItsAngles) {
  const glm::vec3 centre(10, 5, -3);
  const Orbit o = Orbit::through(pose_on_sphere(centre, 40.0f, 215.0f, 25.0f), centre, 1.0f);
  EXPECT_NEAR(o.radius, 40.0f, 1e-3f);
  EXPECT_NEAR(o.longitude_deg, 215.0f, 1e-3f);
  EXPECT_NEAR(o.latitude_deg, 25.0f, 1e-3f);
  // Its pose is the sphere's: where ibr and hybrid baked their viewpoints.
  const CameraPose p = o.pose(), q = pose_on_sphere(centre, 40.0f, 215.0f, 25.0f);
  EXPECT_NEAR(glm::distance(p.position, q.position), 0.0f, 1e-3f);
  EXPECT_NEAR(p.yaw_deg, q.yaw_deg, 1e-3f);
  EXPECT_NEAR(p.pitch_deg, q.pitch_deg, 1e-3f);
  // It looks at the centre.
  EXPECT_NEAR(glm::distance(p.position + 40.0f * p.forward(), centre), 0.0f, 1e-2f);
  // An eye at the centre gets the least radius; one straight above is kept off the pole.
  EXPECT_EQ(Orbit::through(CameraPose{.position = centre}, centre, 2.0f).radius, 2.0f);
  CameraPose above;
  above.position = centre + glm::vec3(0, 7, 0);
  EXPECT_NEAR(Orbit::through(above, centre, 1.0f).latitude_deg, 89.0f, 1e-4f);
}

TEST(Orbit, TurnLookAndZoom) {
  Orbit o;
  o.radius = 8.0f;
  o = navigate(o, {.turn = 1, .look = 1}, {.turn_deg_per_s = 30, .look_deg_per_s = 20}, 1.0f);
  EXPECT_NEAR(o.longitude_deg, 30.0f, kTolerance);
  EXPECT_NEAR(o.latitude_deg, 20.0f, kTolerance);
  EXPECT_NEAR(o.radius, 8.0f, kTolerance);
  o = navigate(o, {.forward = 1}, {}, 2.0f);  // forward for two seconds: half the radius
  EXPECT_NEAR(o.radius, 4.0f, kTolerance);
  o = navigate(o, {.forward = -1, .fast = true}, {}, 0.4f);  // x5: doubled in 0.4 s
  EXPECT_NEAR(o.radius, 8.0f, kTolerance);
  o = navigate(o, {.turn = -1, .look = 1}, {.turn_deg_per_s = 60, .look_deg_per_s = 100}, 1.0f);
  EXPECT_NEAR(o.longitude_deg, 330.0f, kTolerance);  // wrapped into [0, 360)
  EXPECT_NEAR(o.latitude_deg, 89.0f, kTolerance);    // short of the pole
}

}  // namespace
}  // namespace farfield
