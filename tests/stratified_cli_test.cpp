// `farfield bake --technique stratified` as a user meets it: killed with SIGKILL half-way and
// run again, it finishes without redoing finished viewcells; a damaged blob stops the bench
// with its name. Needs GL (skipped without a context).
#include <gtest/gtest.h>

#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>

#include <chrono>
#include <regex>
#include <thread>

#include "farfield/gpu/context.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/stratified/stratified_pack.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using test::run_farfield;

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

uint64_t baked_count(const std::string& pack) {
  auto store = Store::open(pack, Store::Mode::kRead);
  if (!store) return 0;
  auto cells = stratified::baked_cells(*store, 0);
  return cells ? cells->size() : 0;
}

TEST(StratifiedCliGL, KilledBakeResumesWithoutRedoingViewcells) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  test::TempDir dir;
  ASSERT_EQ(run_farfield("generate city -q --blocks 3 --out city.ffscene", dir.path().string())
                .exit_status,
            0);
  const std::string pack = dir.file("city.ffpack");
  // About 80 viewcells of 6 m in a 48 m x 60 m piece of street level.
  const std::vector<std::string> args = {"bake",  dir.file("city.ffscene"),
                                         "-t",    "stratified",
                                         "--set", "stratified.viewcell=6",
                                         "--set", "stratified.box=100",
                                         "--set", "stratified.resolution=128",
                                         "--set", "stratified.limit=100,100,148,160",
                                         "--out", pack,
                                         "-q"};
  const pid_t child = test::spawn_farfield(args);
  ASSERT_GT(child, 0);
  // Kill it once a few viewcells are in, well before the end.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (baked_count(pack) < 5 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(kill(child, SIGKILL), 0);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the bake ended before it was killed";
  const uint64_t before = baked_count(pack);
  ASSERT_GE(before, 5u);

  std::string rerun;
  for (size_t i = 0; i + 1 < args.size(); ++i) rerun += quoted(args[i]) + " ";  // without -q
  auto r = run_farfield(rerun);
  ASSERT_EQ(r.exit_status, 0) << r.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m,
                                std::regex("([0-9]+) of ([0-9]+) viewcells already "
                                           "baked")))
      << r.output;
  const uint64_t total = std::stoull(m[2]);
  EXPECT_EQ(std::stoull(m[1]), before);
  EXPECT_LT(before, total);
  EXPECT_NE(r.output.find("baked " + std::to_string(total - before) + " viewcells"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(baked_count(pack), total);
  auto store = Store::open(pack, Store::Mode::kRead);
  ASSERT_TRUE(store);
  EXPECT_TRUE(store->verify());

  // A third run has nothing left to do; other settings are refused, naming the pack.
  r = run_farfield(rerun);
  EXPECT_EQ(r.exit_status, 0);
  EXPECT_NE(r.output.find("baked 0 viewcells"), std::string::npos) << r.output;
  r = run_farfield("bake " + quoted(dir.file("city.ffscene")) + " -t stratified --out " +
                   quoted(pack) + " --set stratified.box=90");
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_NE(r.output.find("other settings"), std::string::npos) << r.output;
  EXPECT_EQ(baked_count(pack), total);
}

// Limits that select nothing, paths that cannot be read or never enter the region, absurd
// settings: exit 1, a message naming the setting or file, and no pack left behind.
TEST(StratifiedCli, BakeRefusesLimitsThatSelectNothing) {
  test::TempDir dir;
  const std::string cwd = dir.path().string();
  ASSERT_EQ(run_farfield("generate city -q --blocks 1 --out city.ffscene", cwd).exit_status, 0);
  ASSERT_EQ(run_farfield("path city.ffscene --kind street --frames 10 --out street.json", cwd)
                .exit_status,
            0);
  for (const auto& [setting, words] : std::vector<std::pair<std::string, std::string>>{
           {"stratified.limit=5000,5000,6000,6000", "meets no viewcell"},
           {"stratified.path=missing.json", "missing.json"},
           {"stratified.band=100,103 --set stratified.path=street.json", "never enters"},
           {"stratified.resolution=100000", "stratified.resolution"},
           {"stratified.sizing=loose", "strict,paper"},
       }) {
    auto r = run_farfield("bake city.ffscene -t stratified -q --set stratified.box=60 --set " +
                              setting + " --out p.ffpack",
                          cwd);
    EXPECT_EQ(r.exit_status, 1) << setting;
    EXPECT_NE(r.output.find(words), std::string::npos) << setting << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("p.ffpack"))) << setting;
  }
  // Bakes that would not help say why, and write nothing: a model without streets and no
  // path has no region to walk; a tree seen along an orbit fits in the box its density asks
  // for; and one object (a tree in one piece) is never wholly outside a smaller box around a
  // viewpoint inside its crown.
  ASSERT_EQ(run_farfield("generate tree -q --iterations 3 --objects 1 --out tree.ffscene", cwd)
                .exit_status,
            0);
  ASSERT_EQ(
      run_farfield("path tree.ffscene --kind orbit --frames 20 --out orbit.json", cwd).exit_status,
      0);
  for (const auto& [settings, words] : std::vector<std::pair<std::string, std::string>>{
           {"", "no navigable region"},
           {"--set stratified.path=orbit.json", "nothing far to bake"},
           {"--set stratified.band=4,6 --set stratified.limit=-1,-1,1,1 --set stratified.box=4",
            "nothing worth baking"}}) {
    auto r =
        run_farfield("bake tree.ffscene -t stratified -q " + settings + " --out t.ffpack", cwd);
    EXPECT_EQ(r.exit_status, 1) << settings;
    EXPECT_NE(r.output.find(words), std::string::npos) << settings << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("t.ffpack"))) << settings;
  }
}

TEST(StratifiedCliGL, BenchStopsOnADamagedBlobAndNamesIt) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  test::TempDir dir;
  const std::string cwd = dir.path().string();
  ASSERT_EQ(run_farfield("generate city -q --blocks 3 --out city.ffscene", cwd).exit_status, 0);
  ASSERT_EQ(run_farfield("path city.ffscene --kind street --frames 20 --out street.json", cwd)
                .exit_status,
            0);
  auto r = run_farfield(
      "bake city.ffscene -t stratified -q --set stratified.path=street.json "
      "--set stratified.resolution=64 --set stratified.box=100 --out p.ffpack",
      cwd);
  ASSERT_EQ(r.exit_status, 0) << r.output;
  r = run_farfield(
      "bench city.ffscene --path street.json --store p.ffpack -t stratified "
      "--width 128 --height 96 --no-plot -q --birdseye 200 --out ok",
      cwd);
  ASSERT_EQ(r.exit_status, 0) << r.output;
  int birdseye = 0, diff = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.file("ok"))) {
    const std::string name = entry.path().filename().string();
    birdseye += name.starts_with("stratified_") && name.ends_with("_birdseye.png");
    diff += name.starts_with("stratified_") && name.ends_with("_diff.png");
  }
  EXPECT_EQ(birdseye, 3);
  EXPECT_EQ(diff, 3);

  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(dir.file("p.ffpack").c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "UPDATE blobs SET data = zeroblob(length(data)) "
                         "WHERE name LIKE 'stratified/s0/%/face1'",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  r = run_farfield(
      "bench city.ffscene --path street.json --store p.ffpack -t stratified "
      "--width 128 --height 96 --no-plot -q --out broken",
      cwd);
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_TRUE(std::regex_search(r.output, std::regex("blob 'stratified/s0/[0-9_]+/face1' is "
                                                     "corrupted")))
      << r.output;
}

}  // namespace
}  // namespace farfield
