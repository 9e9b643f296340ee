// `farfield view` in a real window under Xvfb: it opens, draws the scene with its overlay,
// plays a path and records one. Skipped where xvfb-run is not installed.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "farfield/core/camera_path.hpp"
#include <glm/geometric.hpp>

#include "farfield/core/image.hpp"
#include "farfield/eval/image_metrics.hpp"
#include "farfield/scene/scene_file.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

TEST(ViewGL, ShowsTheSceneInAWindowUnderXvfb) {
  if (!std::filesystem::exists("/usr/bin/xvfb-run")) GTEST_SKIP() << "xvfb-run not installed";
  test::TempDir dir;
  auto gen = test::run_farfield("generate city --blocks 2 -q --out " + dir.file("c.ffscene"));
  ASSERT_EQ(gen.exit_status, 0) << gen.output;
  auto path = test::run_farfield("path " + dir.file("c.ffscene") +
                                 " --kind orbit --frames 10 --out " + dir.file("p.json"));
  ASSERT_EQ(path.exit_status, 0) << path.output;
  const std::string xvfb = "-a -s '-screen 0 800x600x24' ";
  auto r = test::run_farfield("view " + dir.file("c.ffscene") + " --path " + dir.file("p.json") +
                                  " --width 320 --height 240 --frames 6 --screenshot " +
                                  dir.file("shot.png") + " --record " + dir.file("rec.json"),
                              "", "xvfb-run " + xvfb);
  ASSERT_EQ(r.exit_status, 0) << r.output;
  auto shot = read_png(dir.file("shot.png"));
  ASSERT_TRUE(shot) << shot.error().message;
  EXPECT_EQ(shot->width, 320);
  std::set<uint32_t> colours;
  for (size_t i = 0; i < shot->rgb.size(); i += 3)
    colours.insert(shot->rgb[i] | shot->rgb[i + 1] << 8 | shot->rgb[i + 2] << 16);
  EXPECT_GT(colours.size(), 50u);  // sky, buildings, streets, overlay text: not a blank window
  // The session played the path: the recording holds its first frames.
  auto recorded = read_camera_path(dir.file("rec.json"));
  ASSERT_TRUE(recorded) << recorded.error().message;
  auto played = read_camera_path(dir.file("p.json"));
  ASSERT_EQ(recorded->frames.size(), 6u);
  EXPECT_EQ(recorded->frames[3].position, played->frames[3].position);

  // The geometry left on disk: brute streams it; a technique that needs it in memory is
  // refused at start.
  auto streamed = test::run_farfield("view " + dir.file("c.ffscene") + " --cache-mb 64 --path " +
                                         dir.file("p.json") +
                                         " --width 320 --height 240 --frames 8 --screenshot " +
                                         dir.file("streamed.png"),
                                     "", "xvfb-run " + xvfb);
  ASSERT_EQ(streamed.exit_status, 0) << streamed.output;
  EXPECT_NE(streamed.output.find("(brute,"), std::string::npos) << streamed.output;
  auto refused = test::run_farfield("view " + dir.file("c.ffscene") +
                                        " --cache-mb 64 -t octree --frames 2",
                                    "", "xvfb-run " + xvfb);
  EXPECT_EQ(refused.exit_status, 1) << refused.output;
  EXPECT_NE(refused.output.find("octree cannot walk a scene left on disk"), std::string::npos)
      << refused.output;
}

TEST(ViewGL, OpensInsideTheBakeWithoutAPath) {
  if (!std::filesystem::exists("/usr/bin/xvfb-run")) GTEST_SKIP() << "xvfb-run not installed";
  test::TempDir dir;
  ASSERT_EQ(
      test::run_farfield("generate city --blocks 2 -q --out " + dir.file("c.ffscene")).exit_status,
      0);
  ASSERT_EQ(test::run_farfield("path " + dir.file("c.ffscene") +
                               " --kind street --frames 8 --out " + dir.file("p.json"))
                .exit_status,
            0);
  ASSERT_EQ(test::run_farfield("bake -q " + dir.file("c.ffscene") +
                               " -t stratified --set stratified.box=100 --set stratified.path=" +
                               dir.file("p.json") + " --out " + dir.file("c.ffpack"))
                .exit_status,
            0);
  const std::string xvfb = "xvfb-run -a -s '-screen 0 800x600x24' ";
  // No path: stratified opens inside a viewcell it baked, so it draws its near objects only.
  auto r = test::run_farfield(
      "view " + dir.file("c.ffscene") + " --store " + dir.file("c.ffpack") +
          " -t stratified --width 320 --height 240 --frames 2 --screenshot " + dir.file("s.png"),
      "", xvfb);
  ASSERT_EQ(r.exit_status, 0) << r.output;
  auto scene = read_scene(dir.file("c.ffscene"));
  ASSERT_TRUE(scene);
  const size_t at = r.output.find("(stratified, ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const uint64_t drawn =
      std::stoull(r.output.substr(r.output.find(", ", r.output.find("ms", at)) + 2));
  EXPECT_LT(drawn, scene->triangle_count()) << r.output;
}

// Paper 003's controls: orbiting the scene's centre on the sphere of path --kind orbit, the
// lights turned, and a pixel picked (as a click does) naming its triangle and object.
TEST(ViewGL, OrbitsPicksAndRelights) {
  if (!std::filesystem::exists("/usr/bin/xvfb-run")) GTEST_SKIP() << "xvfb-run not installed";
  test::TempDir dir;
  ASSERT_EQ(
      test::run_farfield("generate city --blocks 2 -q --out " + dir.file("c.ffscene")).exit_status,
      0);
  ASSERT_EQ(test::run_farfield("path " + dir.file("c.ffscene") +
                               " --kind orbit --frames 10 --out " + dir.file("o.json"))
                .exit_status,
            0);
  const std::string xvfb = "xvfb-run -a -s '-screen 0 800x600x24' ";
  const std::string view = "view " + dir.file("c.ffscene") +
                           " -t brute --orbit --width 320 --height 240 --frames 2 ";
  // The middle pixel looks at the city's centre; the top left corner at the sky.
  auto r = test::run_farfield(view + "--pick 160,120 --screenshot " + dir.file("a.png") +
                                  " --record " + dir.file("rec.json"),
                              "", xvfb);
  ASSERT_EQ(r.exit_status, 0) << r.output;
  auto scene = read_scene(dir.file("c.ffscene"));
  ASSERT_TRUE(scene);
  const size_t at = r.output.find("picked pixel (160, 120): triangle ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const uint64_t triangle = std::stoull(r.output.substr(at + 34));
  const size_t of = r.output.find("of object ", at);
  ASSERT_NE(of, std::string::npos) << r.output;
  const uint32_t object = uint32_t(std::stoul(r.output.substr(of + 10)));
  ASSERT_LT(object, scene->objects.size());
  const Object& o = scene->objects[object];
  EXPECT_GE(3 * triangle, o.first_index);
  EXPECT_LT(3 * triangle, uint64_t(o.first_index) + o.index_count);
  EXPECT_NE(r.output.find("'" + std::string(scene->object_name(o)) + "'", of), std::string::npos)
      << r.output;
  // Orbiting with no key down stays at the orbit's first frame.
  auto recorded = read_camera_path(dir.file("rec.json"));
  auto orbit = read_camera_path(dir.file("o.json"));
  ASSERT_TRUE(recorded && orbit);
  EXPECT_LT(glm::distance(recorded->frames.back().position, orbit->frames.front().position), 0.01f);

  auto sky = test::run_farfield(view + "--pick 0,0 --light 120,50 --screenshot " +
                                    dir.file("b.png"), "", xvfb);
  ASSERT_EQ(sky.exit_status, 0) << sky.output;
  EXPECT_NE(sky.output.find("picked pixel (0, 0): no scene triangle"), std::string::npos)
      << sky.output;
  auto a = read_png(dir.file("a.png")), b = read_png(dir.file("b.png"));
  ASSERT_TRUE(a && b);
  EXPECT_GT(compare_images(*a, *b).differing_pixels, 1000u) << "the light did not turn";

  for (const char* bad : {"--pick 320,0", "--pick -1,5", "--light 400,10", "--light 10,95"}) {
    auto refused = test::run_farfield(view + bad, "", xvfb);
    EXPECT_EQ(refused.exit_status, 2) << bad << ": " << refused.output;
    EXPECT_NE(refused.output.find(std::string(bad).substr(0, 6)), std::string::npos)
        << refused.output;
  }
}

TEST(View, WithoutADisplayItFailsWithAMessage) {
  test::TempDir dir;
  auto gen = test::run_farfield("generate city --blocks 1 -q --out " + dir.file("c.ffscene"));
  ASSERT_EQ(gen.exit_status, 0);
  auto r = test::run_farfield("view " + dir.file("c.ffscene") + " --frames 1", "",
                              "env -u DISPLAY -u WAYLAND_DISPLAY ");
  EXPECT_EQ(r.exit_status, 1) << r.output;
  EXPECT_NE(r.output.find("window"), std::string::npos) << r.output;
  auto bad = test::run_farfield("view " + dir.file("missing.ffscene"));
  EXPECT_EQ(bad.exit_status, 1);
  EXPECT_NE(bad.output.find("missing.ffscene"), std::string::npos);
}

}  // namespace
}  // namespace farfield
