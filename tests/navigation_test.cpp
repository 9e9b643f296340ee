#include "farfield/core/navigation.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

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

}  // namespace
}  // namespace farfield
