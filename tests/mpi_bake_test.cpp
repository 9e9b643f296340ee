// A clusters bake spread over two MPI ranks (mpirun -n 2 farfield bake ...) makes the pack one
// process makes, blob for blob, and leaves no shard behind; a bake that does not spread is
// refused under mpirun. Skipped, saying why, where MPI or mpirun is absent.
#include <gtest/gtest.h>

#include "farfield/core/mpi_world.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/store/store.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// mpirun as root needs its consent (this machine runs tests as root).
const char* kMpirun =
    "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -n 2 --oversubscribe ";

std::string why_not() {
  if (!MpiWorld::available()) return "this build has no MPI (libopenmpi-dev absent)";
  if (test::run_shell("command -v mpirun").exit_status != 0) return "no mpirun (openmpi-bin)";
  if (!gpu::create_headless_context()) return "no GL context (the clusters bake renders)";
  return "";
}

TEST(MpiBakeGL, TwoRanksMakeTheSamePackAsOne) {
  if (const std::string reason = why_not(); !reason.empty()) GTEST_SKIP() << reason;
  test::TempDir dir;
  const std::string scene = dir.file("c.ffscene");
  ASSERT_EQ(test::run_farfield("generate city --blocks 2 -q --out " + scene).exit_status, 0);
  // The largest clusters from the levels (rank 0's, the only one holding every level).
  const std::string bake =
      "bake " + scene + " -t clusters --set clusters.cluster_input_triangles=20000 -q --out ";
  auto one = test::run_farfield(bake + dir.file("one.ffpack"));
  ASSERT_EQ(one.exit_status, 0) << one.output;
  auto two = test::run_farfield(bake + dir.file("two.ffpack"), "", kMpirun);
  ASSERT_EQ(two.exit_status, 0) << two.output;
  EXPECT_NE(two.output.find("rank 1 of 2: its share kept in"), std::string::npos) << two.output;
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"c.ffscene", "one.ffpack", "two.ffpack"}))
      << "the shard is gone";

  auto a = Store::open(dir.file("one.ffpack"), Store::Mode::kRead);
  auto b = Store::open(dir.file("two.ffpack"), Store::Mode::kRead);
  ASSERT_TRUE(a && b);
  auto names = a->list("clusters/");
  ASSERT_TRUE(names);
  ASSERT_GT(names->size(), 5u);
  auto other = b->list("clusters/");
  ASSERT_TRUE(other);
  EXPECT_EQ(other->size(), names->size());
  for (const BlobInfo& blob : *names) {
    auto x = a->get(blob.name);
    auto y = b->get(blob.name);
    ASSERT_TRUE(x && y) << blob.name;
    EXPECT_TRUE(*x == *y) << blob.name << " differs";
  }
  // The pack serves a bench as one baked by one process does.
  ASSERT_EQ(test::run_farfield("info " + dir.file("two.ffpack")).exit_status, 0);
}

TEST(MpiBakeGL, BakesThatDoNotSpreadAreRefused) {
  if (const std::string reason = why_not(); !reason.empty()) GTEST_SKIP() << reason;
  test::TempDir dir;
  const std::string scene = dir.file("c.ffscene");
  ASSERT_EQ(test::run_farfield("generate city --blocks 1 -q --out " + scene).exit_status, 0);
  auto run = test::run_farfield("bake " + scene + " -t colorcube -q --out " + dir.file("p.ffpack"),
                                "", kMpirun);
  EXPECT_NE(run.exit_status, 0) << run.output;
  EXPECT_NE(run.output.find("does not spread over the ranks of an MPI job"), std::string::npos)
      << run.output;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"c.ffscene"});
}

}  // namespace
}  // namespace farfield
