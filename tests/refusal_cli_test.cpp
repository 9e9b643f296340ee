// Requests that bench, bake and view would fail at, or ignore, are refused before any frame is
// drawn or file written, with a message that names what is wrong (issue 10's list).
#include <gtest/gtest.h>

#include <sqlite3.h>

#include <nlohmann/json.hpp>

#include <filesystem>

#include "farfield/gpu/context.hpp"
#include "farfield/scene/scene_file.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using test::run_farfield;

// A small city, its street path, a second scene, and packs baked for the first.
class RefusalGL : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    ok_ = gpu::create_headless_context().ok();
    if (!ok_) return;
    for (const std::string& args :
         {"generate city --blocks 2 --out " + file("c.ffscene"),
          "generate city --blocks 2 --seed 7 --out " + file("other.ffscene"),
          "path " + file("c.ffscene") + " --kind street --frames 12 --out " + file("p.json"),
          "bake -q " + file("c.ffscene") + " -t colorcube --set colorcube.force=1 --out " +
              file("c.ffpack"),
          "bake -q " + file("c.ffscene") +
              " -t stratified --set stratified.box=100 --set stratified.path=" + file("p.json") +
              " --out " + file("c.ffpack")}) {
      auto r = run_farfield(args);
      if (r.exit_status != 0) {  // every test then fails with this, rather than skipping
        setup_failure_ = args + "\n" + r.output;
        return;
      }
    }
  }
  static void TearDownTestSuite() { delete dir_; }
  void SetUp() override {
    if (!ok_) GTEST_SKIP() << "no GL context";
    ASSERT_TRUE(setup_failure_.empty()) << "setting up the suite failed: " << setup_failure_;
  }
  static std::string file(const std::string& name) { return dir_->file(name); }

  // Runs a bench into a fresh folder that must not appear.
  void expect_refused(const std::string& args, const std::string& words, int status = 1) {
    const std::string out = file("out");
    std::filesystem::remove_all(out);
    auto r = run_farfield("bench -q --no-plot " + file("c.ffscene") + " --path " + file("p.json") +
                          " --out " + out + " " + args);
    EXPECT_EQ(r.exit_status, status) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << args << "\n" << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << args << ": wrote its folder";
    EXPECT_EQ(r.output.find("median_ms"), std::string::npos) << args << ": ran frames";
  }

  static test::TempDir* dir_;
  static bool ok_;
  static std::string setup_failure_;
};
test::TempDir* RefusalGL::dir_ = nullptr;
bool RefusalGL::ok_ = false;
std::string RefusalGL::setup_failure_;

TEST_F(RefusalGL, BenchChecksEverythingBeforeTheFirstFrame) {
  expect_refused("-t stratified", "stratified draws from a bake");
  expect_refused("-t colorcube --set colorcube.depth=13", "colorcube.depth");
  expect_refused("-t colorcube --set colorcube.depth=6.7", "not a whole number");
  expect_refused("-t brute,octree --set colourcube.depth=6", "unknown technique 'colourcube'", 2);
  expect_refused("-t brute --set colorcube", "TECHNIQUE.KEY=VALUE", 2);
  expect_refused("-t brute,octree --set colorcube.depth=6",
                 "colorcube is not among the techniques run");
  expect_refused("-t octree --set octree.depht=3", "octree has no such setting");
  expect_refused("-t colorcube --store " + file("c.ffpack") + " --set colorcube.cluster=2",
                 "which a run cannot change");
  expect_refused("-t stratified --store " + file("c.ffpack") + " --set stratified.alpha=1",
                 "which a run cannot change");
  expect_refused("-t teleport", "unknown technique 'teleport'");
  expect_refused("-t composite --set composite.far=octree", "composite.far");
  expect_refused("-t brute --interleave --pipelined", "cannot be combined");
  expect_refused("-t octree --no-brute --reference-supersample 2", "needs brute's frames", 2);
  expect_refused("-t octree --reference-supersample 5", "--reference-supersample", 2);
  expect_refused("-t octree --width 8000 --reference-supersample 3", "over 16384 pixels", 2);
  // A walk setting is the run's to choose, a bake setting that agrees with the pack is fine.
  const std::string out = file("fine");
  auto fine =
      run_farfield("bench -q --no-plot " + file("c.ffscene") + " --path " + file("p.json") +
                   " --store " + file("c.ffpack") +
                   " -t composite --set stratified.style=near"
                   " --set stratified.alpha=2 --samples 0 --reference-every 0 --frames 4 --out " +
                   out);
  EXPECT_EQ(fine.exit_status, 0) << fine.output;
  const auto report = nlohmann::json::parse(test::read_file(out + "/bench.json"));
  EXPECT_EQ(report["techniques"][0]["frames"].size(), 4u);  // --frames 4 of the path's 12
}

TEST_F(RefusalGL, PacksOfAnotherSceneOrFormatAreRefused) {
  // The pack was baked for c.ffscene.
  const std::string out = file("out");
  auto r =
      run_farfield("bench -q --no-plot " + file("other.ffscene") + " --path " + file("p.json") +
                   " --store " + file("c.ffpack") + " -t colorcube --out " + out);
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_NE(r.output.find("made for another scene"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  // A pack whose stratified bake has no record (unfinished, or from an older farfield).
  std::filesystem::copy_file(file("c.ffpack"), file("old.ffpack"),
                             std::filesystem::copy_options::overwrite_existing);
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file("old.ffpack").c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "DELETE FROM meta WHERE key = 'stratified/bake'", nullptr, nullptr,
                           nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  expect_refused("-t stratified --store " + file("old.ffpack"), "no bake record");
}

TEST_F(RefusalGL, OutputsMustBeWritable) {
  test::write_file(file("plain.txt"), "a file, not a folder");
  auto r = run_farfield("bench -q --no-plot " + file("c.ffscene") + " --path " + file("p.json") +
                        " -t octree --out " + file("plain.txt") + "/report");
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_NE(r.output.find("cannot create the output folder"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("median_ms"), std::string::npos);
  // view checks its --record file before the window opens (no display is needed to see it).
  auto view = run_farfield("view " + file("c.ffscene") + " --record " + file("missing/rec.json"));
  EXPECT_EQ(view.exit_status, 1);
  EXPECT_NE(view.output.find("missing"), std::string::npos) << view.output;
  EXPECT_NE(view.output.find("does not exist"), std::string::npos) << view.output;
  // bake: a technique with nothing to bake, and a pack in a folder that is not there.
  auto nothing = run_farfield("bake " + file("c.ffscene") + " -t octree --out " + file("n.ffpack"));
  EXPECT_EQ(nothing.exit_status, 1);
  EXPECT_NE(nothing.output.find("nothing to bake"), std::string::npos) << nothing.output;
  EXPECT_FALSE(std::filesystem::exists(file("n.ffpack")));
  auto nowhere =
      run_farfield("bake " + file("c.ffscene") + " -t colorcube --out " + file("missing/n.ffpack"));
  EXPECT_EQ(nowhere.exit_status, 1);
  EXPECT_NE(nowhere.output.find("does not exist"), std::string::npos) << nowhere.output;
  auto other = run_farfield("bake " + file("c.ffscene") +
                            " -t colorcube --set octree.depth=3 --out " + file("n.ffpack"));
  EXPECT_EQ(other.exit_status, 1);
  EXPECT_NE(other.output.find("bake runs only colorcube"), std::string::npos) << other.output;
  EXPECT_FALSE(std::filesystem::exists(file("n.ffpack")));
}

}  // namespace
}  // namespace farfield
