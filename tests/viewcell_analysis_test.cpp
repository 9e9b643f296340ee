// The viewcell analysis of paper 000 against the paper's own figures. The paper prints lengths
// rounded (6.35 m, 33 m) and sometimes truncated (its factor "1.13" is 1.1365, its "16.6" m is
// 16.69 m), so each figure is checked to the digits the paper prints: to within half a unit of
// its last digit, or as an integer where it prints one.
#include "farfield/techniques/stratified/viewcell_analysis.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_util.hpp"

namespace farfield::stratified {
namespace {

using test::run_farfield;

const std::array<double, 3> kCampus = {1000.0, 1000.0, 10.0};  // Sec. 2.4.3, m

double value(const Result<double>& r) {
  EXPECT_TRUE(r.ok()) << r.error().message;
  return r.ok() ? r.value() : NAN;
}

std::vector<double> viewcells(const std::vector<Shell>& shells) {
  std::vector<double> v;
  for (const Shell& shell : shells) v.push_back(shell.viewcell);
  return v;
}

uint64_t total_grid(const std::vector<Shell>& shells, std::vector<uint64_t>* per_shell = nullptr) {
  uint64_t total = 0;
  for (const Shell& shell : shells) {
    auto count = count_viewcells(shell.viewcell, kCampus);
    EXPECT_TRUE(count.ok());
    total += count->grid;
    if (per_shell) per_shell->push_back(count->grid);
  }
  return total;
}

void expect_error(const Error& error, const std::string& option) {
  EXPECT_NE(error.message.find(option), std::string::npos) << error.message;
}

TEST(ViewcellAnalysis, CampusAndCityOfChapter2) {
  // Sec. 2.4.3: alpha_max 10 deg, b 56 m, l 1000 m gives 6.35 m and "50,000" viewcells.
  const double campus = value(viewcell_length(10.0, 56.0, 1000.0));
  EXPECT_NEAR(campus, 6.35, 0.005);
  auto count = count_viewcells(campus, kCampus);
  ASSERT_TRUE(count.ok());
  EXPECT_EQ(count->cells, (std::array<uint64_t, 3>{158, 158, 2}));
  EXPECT_EQ(count->grid, 49928u);
  EXPECT_NEAR(static_cast<double>(count->grid), 50000.0, 500.0);  // the paper's two digits
  // Sec. 2.4.4: l 10,000 m gives 6.22 m and "approximately 4.1 x 10^7" viewcells over
  // 10 km x 10 km x 100 m: the volume ratio, 4.15e7, with its digits cut.
  const double city = value(viewcell_length(10.0, 56.0, 10000.0));
  EXPECT_NEAR(city, 6.22, 0.005);
  auto city_count = count_viewcells(city, {10000.0, 10000.0, 100.0});
  ASSERT_TRUE(city_count.ok());
  EXPECT_GE(city_count->volume_ratio, 4.1e7);
  EXPECT_LT(city_count->volume_ratio, 4.2e7);
}

TEST(ViewcellAnalysis, StratifiedAAndBOfTable61) {
  EXPECT_EQ(std::lround(value(viewcell_length(7.5, 330.0, 1000.0))), 33);
  EXPECT_EQ(std::lround(value(viewcell_length(1.0, 330.0, 1000.0))), 5);
}

TEST(ViewcellAnalysis, ShellsOfTable41) {
  // The five boxes the table lists: the three inner viewcells are the table's.
  const std::vector<double> listed = {56.0, 96.4, 166.2, 286.3, 493.3};
  auto shells = shell_viewcells(10.0, listed, 1000.0);
  ASSERT_TRUE(shells.ok()) << shells.error().message;
  const std::vector<double> v = viewcells(*shells);
  EXPECT_NEAR(v[0], 10.0, 0.05);
  EXPECT_NEAR(v[1], 17.2, 0.05);
  EXPECT_NEAR(v[2], 29.6, 0.05);
  EXPECT_DOUBLE_EQ((*shells)[4].far, 1000.0);
  EXPECT_NEAR((*shells)[0].far, v[0] + (v[1] + 96.4) / 2.0, 1e-9);  // Sec. 4.2.1

  // The outer two (51.1, 88.0) and the total 15230 need the sixth shell the paper counted but did
  // not list: linear spacing from 56 m by 1.72 while the box is shorter than the model.
  auto boxes = box_series(Spacing::linear, 56.0, 1.72, 1000.0);
  ASSERT_TRUE(boxes.ok());
  ASSERT_EQ(boxes->size(), 6u);
  auto six = shell_viewcells(10.0, *boxes, 1000.0);
  ASSERT_TRUE(six.ok()) << six.error().message;
  std::vector<uint64_t> counts;
  EXPECT_EQ(total_grid(*six, &counts), 15230u);
  EXPECT_EQ(counts, (std::vector<uint64_t>{10000, 3481, 1156, 400, 144, 49}));
  // The listed boxes grow by 1.721 to 1.724, "1.72" with the digits cut, as the table cuts its
  // lengths: with a sixth box 1.7225 times the fifth, every listed v is the table's, cut to 0.1.
  std::vector<double> listed_and_sixth = listed;
  listed_and_sixth.push_back(493.3 * 1.7225);
  auto paper = shell_viewcells(10.0, listed_and_sixth, 1000.0);
  ASSERT_TRUE(paper.ok());
  const double table[] = {10.0, 17.2, 29.6, 51.1, 88.0};
  for (int i = 0; i < 5; ++i) {
    EXPECT_GE((*paper)[i].viewcell, table[i]) << i;
    EXPECT_LT((*paper)[i].viewcell, table[i] + 0.1) << i;
  }
}

TEST(ViewcellAnalysis, ShellsOfTable42AndTheJumpAfter172) {
  // Exponential spacing: the paper's boxes 56, 97.0, 181.1, 368.4 are 56^(1.1365^i), shown
  // as "1.13". Its total 15129 again counts an unlisted outer shell (49 viewcells).
  auto boxes = box_series(Spacing::exponential, 56.0, 1.1365, 1000.0);
  ASSERT_TRUE(boxes.ok());
  ASSERT_EQ(boxes->size(), 5u);
  EXPECT_NEAR((*boxes)[1], 97.0, 0.05);
  EXPECT_NEAR((*boxes)[2], 181.1, 0.1);
  EXPECT_NEAR((*boxes)[3], 368.4, 0.2);
  auto shells = shell_viewcells(10.0, *boxes, 1000.0);
  ASSERT_TRUE(shells.ok());
  std::vector<uint64_t> counts;
  EXPECT_EQ(total_grid(*shells, &counts), 15129u);
  EXPECT_EQ(counts, (std::vector<uint64_t>{10000, 3600, 1156, 324, 49}));
  const double table[] = {10.0, 16.6, 30.0, 58.1};  // 16.6: the paper's cut 16.69
  for (int i = 0; i < 4; ++i) EXPECT_NEAR((*shells)[i].viewcell, table[i], 0.1) << i;

  // Sec. 4.2: "right after f = 1.72" v_0 drops under 10 m and the 10 m height needs two
  // layers of innermost viewcells, so the total jumps.
  auto wider = shell_viewcells(10.0, *box_series(Spacing::linear, 56.0, 1.73, 1000.0), 1000.0);
  ASSERT_TRUE(wider.ok());
  EXPECT_LT((*wider)[0].viewcell, 10.0);
  EXPECT_GT(total_grid(*wider), 25000u);
}

TEST(ViewcellAnalysis, InverseSolvesRoundTrip) {
  for (double alpha : {0.5, 1.0, 7.5, 10.0, 30.0, 60.0}) {
    for (double box : {10.0, 56.0, 330.0}) {
      for (double model : {1000.0, 3000.0, 10000.0}) {
        SCOPED_TRACE(testing::Message() << alpha << " " << box << " " << model);
        auto v = viewcell_length(alpha, box, model);
        if (!v) continue;  // alpha too large for this box: tested below
        EXPECT_NEAR(value(alpha_for_viewcell(*v, box, model)), alpha, 1e-9 * alpha + 1e-12);
        EXPECT_NEAR(value(box_for_viewcell(alpha, *v, model)), box, 1e-7 * box);
        EXPECT_NEAR(value(model_for_viewcell(alpha, *v, box)), model, 1e-6 * model);
      }
    }
  }
  // Scale free (Sec. 2.4.1): multiplying l, b and v by a constant does not change the equation.
  EXPECT_NEAR(value(viewcell_length(10.0, 5600.0, 100000.0)),
              100.0 * value(viewcell_length(10.0, 56.0, 1000.0)), 1e-9);
}

TEST(ViewcellAnalysis, LongBoxTakesTheFirstViewcellThatReachesTheBound) {
  // With the box long against the model the error rises and falls again before v = b; the
  // viewcell must be the first length that reaches alpha_max, so every shorter one is within it.
  const double alpha = 9.0, box = 900.0, model = 1000.0;
  const double v = value(viewcell_length(alpha, box, model));
  EXPECT_NEAR(value(alpha_for_viewcell(v, box, model)), alpha, 1e-9);
  for (double u = v / 100.0; u < v; u += v / 100.0)
    EXPECT_LT(value(alpha_for_viewcell(u, box, model)), alpha) << u;
  EXPECT_LT(value(alpha_for_viewcell(0.999 * box, box, model)), alpha);  // and falls again
}

TEST(ViewcellAnalysis, DomainErrorsNameTheOption) {
  for (double alpha : {0.0, -1.0, 90.0, 120.0, double(NAN), double(INFINITY)})
    expect_error(viewcell_length(alpha, 56.0, 1000.0).error(), "--alpha-deg");
  expect_error(viewcell_length(10.0, 0.0, 1000.0).error(), "--box");
  expect_error(viewcell_length(10.0, 56.0, -1.0).error(), "--model");
  expect_error(viewcell_length(10.0, 1000.0, 1000.0).error(), "--box");        // b < l
  expect_error(viewcell_length(89.0, 56.0, 1000.0).error(), "--alpha-deg");    // v would pass b
  expect_error(alpha_for_viewcell(60.0, 56.0, 1000.0).error(), "--viewcell");  // v < b
  expect_error(alpha_for_viewcell(6.0, 56.0, 50.0).error(), "--box");
  expect_error(box_for_viewcell(10.0, 600.0, 1000.0).error(), "--alpha-deg");  // b >= l
  expect_error(box_for_viewcell(89.9, 6.0, 1000.0).error(), "--alpha-deg");    // any box does
  expect_error(box_for_viewcell(10.0, 6.0, 6.0).error(), "--viewcell");
  expect_error(model_for_viewcell(89.0, 6.0, 56.0).error(), "--alpha-deg");  // any model does
  expect_error(model_for_viewcell(0.1, 6.0, 56.0).error(), "--alpha-deg");   // l <= b
  expect_error(model_for_viewcell(10.0, 56.0, 56.0).error(), "--viewcell");

  const std::vector<double> shrinking = {56.0, 50.0}, too_long = {56.0, 1000.0};
  expect_error(shell_viewcells(10.0, shrinking, 1000.0).error(), "--shells");
  expect_error(shell_viewcells(10.0, too_long, 1000.0).error(), "--shells");
  expect_error(shell_viewcells(10.0, {}, 1000.0).error(), "--shells");
  expect_error(box_series(Spacing::linear, 56.0, 1.0, 1000.0).error(), "--factor");
  expect_error(box_series(Spacing::exponential, 1.0, 1.5, 1000.0).error(), "--b0");
  expect_error(box_series(Spacing::linear, 56.0, 1.72, 1000.0, 7).error(), "--count");
  expect_error(box_series(Spacing::linear, 56.0, 1.0001, 1000.0).error(), "--factor");
  EXPECT_EQ(box_series(Spacing::linear, 56.0, 1.72, 1000.0, 3)->size(), 3u);
  expect_error(count_viewcells(6.35, {1000.0, 0.0, 10.0}).error(), "--region");
  expect_error(count_viewcells(1e-9, {1e9, 1e9, 1e9}).error(), "--region");
}

TEST(ViewcellAnalysis, BoxFromThroughputOfSection242) {
  // RealityEngine 2: 1.8M polygons/s at 60 Hz, 1 polygon/m^3, a 90 x 90 deg view: p = 30,000,
  // b^3 = 180,000 m^3, "b = 56m".
  auto box = box_from_throughput({1.8e6, 1000.0 / 60.0, 1.0});
  ASSERT_TRUE(box.ok()) << box.error().message;
  EXPECT_NEAR(box->triangles_per_frame, 30000.0, 1e-6);
  EXPECT_NEAR(box->visible_fraction, 1.0 / 6.0, 1e-12);
  EXPECT_NEAR(box->box * box->box * box->box, 180000.0, 1e-6);
  EXPECT_EQ(std::lround(box->box), 56);
  // Our bench protocol, 1024 x 768 at 90 deg across: the vertical view is 2 atan(0.75).
  Throughput ours{1.8e6, 1000.0 / 60.0, 1.0};
  ours.vfov_deg = 2.0 * std::atan(0.75) * 180.0 / M_PI;
  EXPECT_NEAR(box_from_throughput(ours)->visible_fraction, 1.0 / 8.0, 1e-12);
  // Per area: the 90 deg wedge is a quarter of the square, p = b^2 rho / 4.
  auto ground = box_from_throughput({1e6, 10.0, 0.5, DensityUnit::per_square_metre});
  ASSERT_TRUE(ground.ok());
  EXPECT_NEAR(ground->box * ground->box * 0.5 / 4.0, 10000.0, 1e-6);

  expect_error(box_from_throughput({0.0, 16.0, 1.0}).error(), "--triangles-per-second");
  expect_error(box_from_throughput({1e6, -1.0, 1.0}).error(), "--frame-ms");
  expect_error(box_from_throughput({1e6, 16.0, 0.0}).error(), "--triangle-density");
  Throughput wide{1e6, 16.0, 1.0};
  wide.hfov_deg = 120.0;
  expect_error(box_from_throughput(wide).error(), "--hfov-deg");
}

TEST(ViewcellCli, CampusAndErrors) {
  auto r =
      run_farfield("analyze viewcell --alpha-deg 10 --box 56 --model 1000 --region 1000,1000,10");
  EXPECT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("v = 6.35"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("49928"), std::string::npos) << r.output;

  r = run_farfield("analyze viewcell --alpha-deg 95 --box 56 --model 1000");
  EXPECT_EQ(r.exit_status, 1) << r.output;
  EXPECT_NE(r.output.find("--alpha-deg"), std::string::npos) << r.output;
  r = run_farfield("analyze viewcell --alpha-deg 10 --box 2000 --model 1000");
  EXPECT_EQ(r.exit_status, 1) << r.output;
  EXPECT_NE(r.output.find("--box"), std::string::npos) << r.output;

  for (const char* args :
       {"analyze", "analyze viewcell --alpha-deg 10 --box 56",
        "analyze viewcell --alpha-deg 10 --box 56 --model 1000 --viewcell 6",
        "analyze viewcell --alpha-deg 10 --box 56 --model 1000 --solve box",
        "analyze viewcell --alpha-deg 10 --box 56 --model 1000 --solve speed",
        "analyze viewcell --alpha-deg 10 --model 1000 --shells 56,96 --box 56",
        "analyze viewcell --alpha-deg 10 --model 1000 --spacing linear --b0 56",
        "analyze viewcell --alpha-deg 10 --model 1000 --spacing linear --factor 1.7",
        "analyze viewcell --alpha-deg 10 --box 56 --model 1000 --region 1000,10",
        "analyze viewcell --triangles-per-second 1e6 --frame-ms 16"}) {
    auto u = run_farfield(args);
    EXPECT_EQ(u.exit_status, 2) << args << "\n" << u.output;
    EXPECT_FALSE(u.output.empty()) << args;
  }
}

TEST(ViewcellCli, SolvesShellsAndThroughput) {
  auto r = run_farfield("analyze viewcell --alpha-deg 10 --viewcell 6.353784506 --model 1000");
  EXPECT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("b = 56.00 m  (solved)"), std::string::npos) << r.output;
  r = run_farfield("analyze viewcell --viewcell 6.353784506 --box 56 --model 1000");
  EXPECT_NE(r.output.find("alpha_max = 10.000 deg  (solved)"), std::string::npos) << r.output;

  r = run_farfield(
      "analyze viewcell --alpha-deg 10 --model 1000 --spacing linear --b0 56 "
      "--factor 1.72 --region 1000,1000,10");
  EXPECT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("6 shells"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(": 15230"), std::string::npos) << r.output;
  r = run_farfield(
      "analyze viewcell --alpha-deg 10 --model 1000 --shells 56,96.4,166.2,286.3,493.3");
  EXPECT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("10.00"), std::string::npos) << r.output;
  r = run_farfield("analyze viewcell --alpha-deg 10 --model 1000 --shells 56,50");
  EXPECT_EQ(r.exit_status, 1) << r.output;
  EXPECT_NE(r.output.find("--shells"), std::string::npos) << r.output;

  // The paper's chain: throughput -> b = 56 m -> v.
  r = run_farfield(
      "analyze viewcell --triangles-per-second 1.8e6 --frame-ms 16.6667 "
      "--triangle-density 1 --alpha-deg 10 --model 1000");
  EXPECT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("b = 56.46"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("v = 6.4"), std::string::npos) << r.output;
  r = run_farfield(
      "analyze viewcell --triangles-per-second 1.8e6 --frame-ms 0 --triangle-density 1");
  EXPECT_EQ(r.exit_status, 1) << r.output;
  EXPECT_NE(r.output.find("--frame-ms"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace farfield::stratified
