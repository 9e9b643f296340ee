// 3D Tiles export of the cluster hierarchy: errors fall from the root to the leaves, refining
// all the way shows every object exactly once, the package holds what the folder holds, bad
// options are refused, and the specification checker and glTF validator (web/) pass it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "farfield/scene/scene_file.hpp"
#include "farfield/store/tiles_package.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using nlohmann::json;

std::string slurp(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The node names of a .glb's JSON chunk.
std::vector<std::string> glb_node_names(const std::string& glb) {
  uint32_t length = 0;
  EXPECT_GE(glb.size(), 20u);
  EXPECT_EQ(glb.substr(0, 4), "glTF");
  std::memcpy(&length, glb.data() + 12, 4);
  const json gltf = json::parse(glb.substr(20, length));
  std::vector<std::string> names;
  for (const json& node : gltf["nodes"]) names.push_back(node["name"]);
  return names;
}

struct Walk {
  std::map<std::string, int> exact;  // object name -> times found in error-0 contents
  int tiles = 0, contents = 0;
};

void walk(const json& tile, double parent_error, const std::string& folder, Walk& w) {
  ++w.tiles;
  const double error = tile["geometricError"];
  EXPECT_LE(error, parent_error) << "a child's error above its parent's";
  if (!tile.contains("children")) {
    EXPECT_EQ(error, 0.0) << "a leaf that is not exact";
  }
  if (tile.contains("content")) {
    ++w.contents;
    if (error == 0.0)
      for (const std::string& name : glb_node_names(slurp(folder + "/" +
                                                          tile["content"]["uri"].get<std::string>())))
        ++w.exact[name];
  }
  if (tile.contains("children"))
    for (const json& child : tile["children"]) walk(child, error, folder, w);
}

class TilesetCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    using test::run_farfield;
    ASSERT_EQ(run_farfield("generate city --blocks 1 --textures -q --out " + file("c.ffscene"))
                  .exit_status,
              0);
    auto bake = run_farfield("bake -q " + file("c.ffscene") + " -t clusters --out " +
                             file("c.ffpack"));
    ASSERT_EQ(bake.exit_status, 0) << bake.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string file(const std::string& name) { return dir_->file(name); }
  static test::TempDir* dir_;
};
test::TempDir* TilesetCli::dir_ = nullptr;

TEST_F(TilesetCli, ErrorsFallToExactLeavesHoldingEveryObjectOnce) {
  auto r = test::run_farfield("export " + file("c.ffscene") + " --store " + file("c.ffpack") +
                              " --format 3dtiles -q --out " + file("tiles"));
  ASSERT_EQ(r.exit_status, 0) << r.output;
  EXPECT_FALSE(std::filesystem::exists(file("tiles.partial")));
  const json tileset = json::parse(slurp(file("tiles/tileset.json")));
  EXPECT_EQ(tileset["asset"]["version"], "1.1");
  EXPECT_EQ(tileset["root"]["refine"], "REPLACE");
  const double root_error = tileset["root"]["geometricError"];
  EXPECT_GT(root_error, 0.0) << "the root is a simplified cluster";
  EXPECT_GE(tileset["geometricError"].get<double>(), root_error);
  Walk w;
  walk(tileset["root"], root_error, file("tiles"), w);
  auto scene = read_scene(file("c.ffscene"));
  ASSERT_TRUE(scene);
  EXPECT_GT(w.tiles, 3);
  ASSERT_EQ(w.exact.size(), scene->objects.size()) << "objects missing from the exact tiles";
  for (const Object& o : scene->objects)
    EXPECT_EQ(w.exact[std::string(scene->object_name(o))], 1) << scene->object_name(o);

  // The package holds the same files under the same keys.
  r = test::run_farfield("export " + file("c.ffscene") + " --store " + file("c.ffpack") +
                         " --format 3dtiles -q --out " + file("c.3dtiles"));
  ASSERT_EQ(r.exit_status, 0) << r.output;
  auto json_in_package = read_tiles_package(file("c.3dtiles"), "tileset.json");
  ASSERT_TRUE(json_in_package) << json_in_package.error().message;
  EXPECT_EQ(*json_in_package, slurp(file("tiles/tileset.json")));
  auto first = read_tiles_package(file("c.3dtiles"), "tiles/0.glb");
  ASSERT_TRUE(first);
  EXPECT_EQ(*first, slurp(file("tiles/tiles/0.glb")));
  auto missing = read_tiles_package(file("c.3dtiles"), "tiles/none.glb");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("tiles/none.glb"), std::string::npos);
  EXPECT_FALSE(read_tiles_package(file("c.ffscene"), "tileset.json"));
}

// paper 001's cluster representation: where the bake made boxes for the clusters, a cluster's
// textured box is a tile above its mesh's, its error between the mesh's and its parent's.
void find_boxes(const json& tile, double parent_error, const std::string& folder, int& boxes) {
  const double error = tile["geometricError"];
  if (tile.contains("content")) {
    const auto names = glb_node_names(slurp(folder + "/" + tile["content"]["uri"].get<std::string>()));
    if (names.size() == 1 && names[0].starts_with("box ")) {
      ++boxes;
      EXPECT_LE(error, parent_error);
      ASSERT_EQ(tile["children"].size(), 1u);
      EXPECT_LT(tile["children"][0]["geometricError"].get<double>(), error);
    }
  }
  if (tile.contains("children"))
    for (const json& child : tile["children"]) find_boxes(child, error, folder, boxes);
}

TEST_F(TilesetCli, ClusterBoxesStandAboveTheirMeshes) {
  using test::run_farfield;
  auto bake = run_farfield("bake -q " + file("c.ffscene") +
                           " -t clusters --set clusters.boxes=all --out " + file("boxes.ffpack"));
  ASSERT_EQ(bake.exit_status, 0) << bake.output;
  auto r = run_farfield("export " + file("c.ffscene") + " --store " + file("boxes.ffpack") +
                        " --format 3dtiles -q --out " + file("boxed"));
  ASSERT_EQ(r.exit_status, 0) << r.output;
  const json tileset = json::parse(slurp(file("boxed/tileset.json")));
  int boxes = 0;
  find_boxes(tileset["root"], tileset["geometricError"], file("boxed"), boxes);
  EXPECT_GT(boxes, 0) << r.output;
  EXPECT_NE(r.output.find(std::to_string(boxes) + " textured boxes"), std::string::npos)
      << r.output;
  Walk w;  // still every object once at the exact leaves
  walk(tileset["root"], tileset["geometricError"], file("boxed"), w);
  auto scene = read_scene(file("c.ffscene"));
  ASSERT_TRUE(scene);
  EXPECT_EQ(w.exact.size(), scene->objects.size());
}

TEST_F(TilesetCli, RefusesWhatItCannotExport) {
  using test::run_farfield;
  ASSERT_EQ(run_farfield("generate tree -q --out " + file("t.ffscene")).exit_status, 0);
  auto other = run_farfield("bake -q " + file("t.ffscene") +
                            " -t ibr --set ibr.d_theta=90 --set ibr.d_phi=90 "
                            "--set ibr.resolution=32 --out " + file("other.ffpack"));
  ASSERT_EQ(other.exit_status, 0) << other.output;
  std::filesystem::create_directories(file("full"));
  std::ofstream(file("full/x")) << "x";
  struct Bad {
    std::string args;
    int status;
    std::string says;
  };
  const std::string c = "export " + file("c.ffscene") + " --format 3dtiles ";
  const Bad bad[] = {
      {c + "--out " + file("a"), 2, "--store"},
      {c + "--store " + file("c.ffpack") + " --objects 'x*' --out " + file("a"), 2, "--objects"},
      {c + "--store " + file("missing.ffpack") + " --out " + file("a"), 1, "missing.ffpack"},
      {"export " + file("t.ffscene") + " --format 3dtiles --store " + file("other.ffpack") +
           " --out " + file("a"),
       1, "no clusters bake"},
      {c + "--store " + file("c.ffpack") + " --out " + file("full"), 1, "not empty"},
      {"export " + file("c.ffscene") + " --store " + file("c.ffpack") + " --out " + file("a.glb"),
       2, "--store is for --format 3dtiles"},
  };
  for (const Bad& b : bad) {
    auto refused = run_farfield(b.args);
    EXPECT_EQ(refused.exit_status, b.status) << b.args << "\n" << refused.output;
    EXPECT_NE(refused.output.find(b.says), std::string::npos) << refused.output;
  }
  EXPECT_FALSE(std::filesystem::exists(file("a")));
}

TEST_F(TilesetCli, PassesTheSpecificationCheckAndTheGltfValidator) {
  const std::string web = std::string(FARFIELD_SOURCE_DIR) + "/web";
  if (!std::filesystem::exists(web + "/node_modules/gltf-validator") ||
      std::system("node --version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the glTF validator is not installed (make deps: npm ci in web/)";
  // With the clusters' textured boxes, whose quads and cut-out textures are checked too.
  auto bake = test::run_farfield("bake -q " + file("c.ffscene") +
                                 " -t clusters --set clusters.boxes=all --out " +
                                 file("checked.ffpack"));
  ASSERT_EQ(bake.exit_status, 0) << bake.output;
  auto r = test::run_farfield("export " + file("c.ffscene") + " --store " +
                              file("checked.ffpack") + " --format 3dtiles -q --out " +
                              file("checked"));
  ASSERT_EQ(r.exit_status, 0) << r.output;
  const test::CommandResult check =
      test::run_shell("node " + web + "/validate_tileset.mjs " + file("checked"));
  const std::string& output = check.output;
  EXPECT_EQ(check.exit_status, 0) << output;
  EXPECT_NE(output.find(": 0 errors, 0 warnings"), std::string::npos) << output;
}

}  // namespace
}  // namespace farfield
