// The frame time a budgeted selection aims at (techniques/clusters/budget_target.hpp): a tenth
// under the budget until enough frames were measured, then under it by the 97th percentile of
// the model's recent error (or the share of frames asked for), within 0.6 and 0.95 of the
// budget.
#include "farfield/techniques/clusters/budget_target.hpp"

#include <gtest/gtest.h>

namespace farfield {
namespace {

TEST(BudgetTarget, AimsUnderTheBudgetByTheRecentError) {
  BudgetTarget target;
  EXPECT_DOUBLE_EQ(target.target_ms(33.0), 0.9 * 33.0);
  for (int f = 0; f < 15; ++f) target.observe(30.0, 30.0, 33.0);
  EXPECT_DOUBLE_EQ(target.target_ms(33.0), 0.9 * 33.0) << "too few frames yet";
  target.observe(30.0, 30.0, 33.0);
  EXPECT_DOUBLE_EQ(target.target_ms(33.0), 0.95 * 33.0) << "exact predictions: near the budget";

  // 11 frames in 128 a quarter over their prediction, the rest exact: the 97th percentile is
  // 1.25, so frames are aimed at 1.1 / 1.25 of the budget.
  for (int f = 0; f < 128; ++f) target.observe(20.0, f % 12 == 0 ? 25.0 : 20.0, 33.0);
  EXPECT_NEAR(target.target_ms(33.0), 33.0 * 1.1 / 1.25, 1e-9);
  // 2 in 128 over: beyond the 97th percentile, the frames are aimed near the budget.
  for (int f = 0; f < 128; ++f) target.observe(20.0, f % 64 == 0 ? 25.0 : 20.0, 33.0);
  EXPECT_DOUBLE_EQ(target.target_ms(33.0), 0.95 * 33.0);

  // Wildly wrong: no lower than 0.6 of the budget. Unmeasured frames are not counted.
  for (int f = 0; f < 128; ++f) target.observe(10.0, 40.0, 33.0);
  target.observe(-1.0, 5.0, 33.0);
  target.observe(10.0, 0.0, 33.0);
  EXPECT_DOUBLE_EQ(target.target_ms(33.0), 0.6 * 33.0);
}

// Frames far under the budget (a walk from disk drawing stand-ins while its pages load) are
// not kept: twice their prediction at a millisecond says nothing of frames near the budget.
TEST(BudgetTarget, FramesFarUnderTheBudgetDoNotLowerTheAim) {
  BudgetTarget target;
  for (int f = 0; f < 128; ++f) target.observe(30.0, 30.0, 33.0);
  for (int f = 0; f < 100; ++f) target.observe(0.8, 1.6, 33.0);
  EXPECT_DOUBLE_EQ(target.target_ms(33.0), 0.95 * 33.0);
  // Half the budget or more, predicted or taken, counts.
  for (int f = 0; f < 128; ++f) target.observe(10.0, 20.0, 33.0);
  EXPECT_DOUBLE_EQ(target.target_ms(33.0), 0.6 * 33.0);
  // Without a budget every frame counts.
  BudgetTarget unbudgeted;
  for (int f = 0; f < 128; ++f) unbudgeted.observe(0.8, 1.6, 0.0);
  EXPECT_DOUBLE_EQ(unbudgeted.target_ms(33.0), 0.6 * 33.0);
}

TEST(BudgetTarget, AHigherQuantileForASmallerShareOfFramesOver) {
  // 3 frames in 128 a quarter over: the default's 97th percentile passes them by, a share of
  // 1% over takes them in.
  BudgetTarget loose, strict(0.01);
  for (int f = 0; f < 128; ++f) {
    loose.observe(20.0, f % 43 == 0 ? 25.0 : 20.0, 33.0);
    strict.observe(20.0, f % 43 == 0 ? 25.0 : 20.0, 33.0);
  }
  EXPECT_DOUBLE_EQ(loose.target_ms(33.0), 0.95 * 33.0);
  EXPECT_NEAR(strict.target_ms(33.0), 33.0 * 1.1 / 1.25, 1e-9);
}

}  // namespace
}  // namespace farfield
