// `farfield bake --technique clusters` as a user meets it: killed with SIGKILL half-way and
// run again, it finishes without redoing the objects it had simplified, leaves no work behind,
// and a damaged blob stops the bench with its name; a field of copies is baked and walked as
// one chain of levels.
#include <gtest/gtest.h>

#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>

#include <chrono>
#include <regex>
#include <thread>

#include <nlohmann/json.hpp>

#include "farfield/gpu/context.hpp"
#include "farfield/store/store.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using test::run_farfield;

// Batches of simplified objects kept in the pack so far.
size_t kept_batches(const std::string& pack) {
  auto store = Store::open(pack, Store::Mode::kRead);
  if (!store) return 0;
  auto blobs = store->list("clusters/work/lods/0");
  return blobs ? blobs->size() : 0;
}

TEST(ClustersCli, KilledBakeResumesWithoutRedoingObjects) {
  test::TempDir dir;
  const std::string cwd = dir.path().string();
  // A small building: its 488 objects are alike, so that its eight batches are kept seconds
  // apart (a city's few large buildings come first and its many small objects follow within a
  // tenth of a second, too quickly to be caught between batches on a loaded machine).
  ASSERT_EQ(
      run_farfield("generate building -q --floors 2 --rooms 12 --out b.ffscene", cwd).exit_status,
      0);
  const std::string pack = dir.file("b.ffpack");
  // One thread, so that the bake is slow enough to be caught half-way.
  const std::vector<std::string> args = {"bake",  dir.file("b.ffscene"), "-t",    "clusters",
                                         "--set", "clusters.threads=1",  "--out", pack};
  const pid_t child = test::spawn_farfield(args);
  ASSERT_GT(child, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (kept_batches(pack) < 1 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_EQ(kill(child, SIGKILL), 0);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the bake ended before it was killed";
  const size_t batches = kept_batches(pack);
  ASSERT_GE(batches, 1u);

  std::string rerun;
  for (const std::string& a : args) rerun += "'" + a + "' ";
  auto r = run_farfield(rerun);
  ASSERT_EQ(r.exit_status, 0) << r.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m,
                                std::regex("clusters: ([0-9]+) of ([0-9]+) objects already kept")))
      << r.output;
  EXPECT_GE(std::stoull(m[1]), 64 * (batches - 1) + 1);  // batches of 64; the last may be short
  EXPECT_LT(std::stoull(m[1]), std::stoull(m[2]));
  auto store = Store::open(pack, Store::Mode::kRead);
  ASSERT_TRUE(store);
  auto work = store->list("clusters/work/");
  ASSERT_TRUE(work);
  EXPECT_TRUE(work->empty());  // the work went once the bake was saved
  EXPECT_TRUE(store->verify());
  r = run_farfield("info '" + pack + "'");
  EXPECT_NE(r.output.find("clusters bake"), std::string::npos) << r.output;
}

TEST(ClustersCli, ADamagedBlobIsNamed) {
  test::TempDir dir;
  const std::string cwd = dir.path().string();
  ASSERT_EQ(run_farfield("generate city -q --blocks 1 --out city.ffscene", cwd).exit_status, 0);
  ASSERT_EQ(
      run_farfield("path city.ffscene --kind street --frames 4 --out street.json", cwd).exit_status,
      0);
  auto r = run_farfield("bake city.ffscene -t clusters -q --out p.ffpack", cwd);
  ASSERT_EQ(r.exit_status, 0) << r.output;
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(dir.file("p.ffpack").c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "UPDATE blobs SET data = zeroblob(length(data)) "
                         "WHERE name = 'clusters/tree_nodes'",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  r = run_farfield(
      "bench city.ffscene --path street.json --store p.ffpack -t clusters "
      "--width 128 --height 96 --no-plot -q --out broken",
      cwd);
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_NE(r.output.find("blob 'clusters/tree_nodes' is corrupted"), std::string::npos)
      << r.output;
}

// Nine copies of a tree (Scene::instances) and one tree alone: the field's pack stores one
// chain of levels (as many level triangles as the lone tree's), its walk draws the copies'
// levels, and from disk with a small cache (waiting for its pages) the frames are those of the
// walk in memory.
TEST(ClustersCli, AFieldsCopiesAreBakedAndWalkedAsOneChain) {
  if (auto context = gpu::create_headless_context(); !context)
    GTEST_SKIP() << context.error().message;
  test::TempDir dir;
  const std::string cwd = dir.path().string();
  for (const char* command :
       {"generate tree --iterations 3 -q --out tree.ffscene",
        "generate field --mesh tree.ffscene --count 9 -q --out field.ffscene",
        "generate field --mesh tree.ffscene --count 1 -q --out one.ffscene",
        "path field.ffscene --kind orbit --frames 6 --out orbit.json",
        "bake field.ffscene -t clusters --set clusters.accuracy_directions=4 -q --out f.ffpack",
        "bake one.ffscene -t clusters --set clusters.accuracy_directions=4 -q --out o.ffpack"}) {
    const auto r = run_farfield(command, cwd);
    ASSERT_EQ(r.exit_status, 0) << command << ": " << r.output;
  }
  auto walk = [&](const std::string& scene, const std::string& pack, const std::string& more,
                  const std::string& out) {
    const auto r = run_farfield("bench " + scene + " --store " + pack +
                                    " --path orbit.json -t brute,clusters --reference-every 1"
                                    " --set clusters.error_px=4 --set clusters.errors=geometric"
                                    " --width 160 --height 120 --no-plot -q --out " +
                                    out + more,
                                cwd);
    EXPECT_EQ(r.exit_status, 0) << r.output;
    const auto json = nlohmann::json::parse(test::read_file(dir.file(out + "/bench.json")));
    return json["techniques"][1];
  };
  const auto one = walk("one.ffscene", "o.ffpack", "", "one");
  const auto memory = walk("field.ffscene", "f.ffpack", "", "memory");
  const auto disk =
      walk("field.ffscene", "f.ffpack", " --cache-mb 16 --set clusters.wait=1", "disk");
  ASSERT_EQ(memory["name"], "clusters");
  EXPECT_EQ(memory["figures"]["lod_triangles"], one["figures"]["lod_triangles"]);
  EXPECT_EQ(memory["figures"]["lods"].get<double>(), 9 * one["figures"]["lods"].get<double>());
  EXPECT_GT(memory["figures"]["mean_objects_as_lods"].get<double>(), 3.0);
  EXPECT_GT(memory["summary"]["psnr_db_mean"].get<double>(), 20.0);
  EXPECT_EQ(disk["figures"]["coarser_frames"].get<double>(), 0.0);
  ASSERT_EQ(memory["frames"].size(), disk["frames"].size());
  for (size_t f = 0; f < memory["frames"].size(); ++f)
    EXPECT_EQ(memory["frames"][f]["psnr_db"], disk["frames"][f]["psnr_db"]) << "frame " << f;
}

}  // namespace
}  // namespace farfield
