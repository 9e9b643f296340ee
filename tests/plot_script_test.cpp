// scripts/plot_cost_by_size.py: frame time against scene size from bench.json files.
#include <gtest/gtest.h>

#include <filesystem>

#include "test_util.hpp"

namespace farfield {
namespace {

std::string report(uint64_t triangles, double median, double p99) {
  return "{\"scene\": {\"triangles\": " + std::to_string(triangles) +
         "}, \"renderer\": \"test\", \"techniques\": [{\"name\": \"clusters\", \"summary\": "
         "{\"median_ms\": " + std::to_string(median) + ", \"p99_ms\": " + std::to_string(p99) +
         "}}]}";
}

TEST(PlotScript, PlotsMedianAndP99AgainstTriangles) {
  test::TempDir dir;
  test::write_file(dir.file("a.json"), report(100000000, 30.0, 40.0));
  test::write_file(dir.file("b.json"), report(1000000, 20.0, 25.0));
  const std::string script = std::string(FARFIELD_SOURCE_DIR) + "/scripts/plot_cost_by_size.py";
  auto run = test::run_shell("/usr/bin/python3 " + script + " -t clusters --out " +
                             dir.file("c.png") + " " + dir.file("a.json") + " " +
                             dir.file("b.json") + " 2>&1");
  ASSERT_EQ(run.exit_status, 0) << run.output;
  EXPECT_TRUE(std::filesystem::file_size(dir.file("c.png")) > 1000);
  // Sorted by size, each median against the smallest scene's.
  EXPECT_LT(run.output.find("1,000,000"), run.output.find("100,000,000")) << run.output;
  EXPECT_NE(run.output.find("1.50"), std::string::npos) << run.output;
  auto missing = test::run_shell("/usr/bin/python3 " + script + " -t octree --out " +
                                 dir.file("d.png") + " " + dir.file("a.json") + " 2>&1");
  EXPECT_NE(missing.exit_status, 0);
  EXPECT_NE(missing.output.find("no technique 'octree'"), std::string::npos) << missing.output;
}

}  // namespace
}  // namespace farfield
