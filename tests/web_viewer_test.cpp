// The web viewer (web/): headless Chromium shows an exported tileset at a farfield path's pose
// as farfield's brute force draws it there (same camera, same shading). Skipped, saying so,
// where Chromium or web/'s npm packages are not installed.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "farfield/core/image.hpp"
#include "farfield/eval/image_metrics.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

TEST(WebViewer, ShowsATilesetAsFarfieldDrawsIt) {
  const std::string web = std::string(FARFIELD_SOURCE_DIR) + "/web";
  if (!std::filesystem::exists("/usr/bin/chromium") ||
      !std::filesystem::exists(web + "/node_modules/playwright-core") ||
      !std::filesystem::exists(web + "/node_modules/3d-tiles-renderer"))
    GTEST_SKIP() << "Chromium or web/'s npm packages are not installed (make deps)";
  test::TempDir dir;
  using test::run_farfield;
  const std::string scene = dir.file("c.ffscene");
  ASSERT_EQ(run_farfield("generate city --blocks 1 --textures -q --out " + scene).exit_status, 0);
  ASSERT_EQ(run_farfield("bake -q " + scene + " -t clusters --out " + dir.file("c.ffpack"))
                .exit_status,
            0);
  ASSERT_EQ(run_farfield("export -q " + scene + " --store " + dir.file("c.ffpack") +
                         " --format 3dtiles --out " + dir.file("tiles"))
                .exit_status,
            0);
  ASSERT_EQ(run_farfield("path " + scene + " --kind orbit --frames 8 --out " + dir.file("o.json"))
                .exit_status,
            0);
  auto bench = run_farfield("bench -q " + scene + " --path " + dir.file("o.json") +
                            " -t brute --frames 3 --samples 3 --no-plot --out " + dir.file("b"));
  ASSERT_EQ(bench.exit_status, 0) << bench.output;

  // The server, on a port of its own choosing, stopped when the test ends.
  const std::string log = dir.file("serve.log"), pid_file = dir.file("serve.pid");
  ASSERT_EQ(std::system(("node " + web + "/serve.mjs " + dir.path().string() +
                         " --port 0 > " + log + " 2>&1 & echo $! > " + pid_file)
                            .c_str()),
            0);
  const pid_t server = pid_t(std::stol(test::read_file(pid_file)));
  struct Stop {
    pid_t pid;
    ~Stop() { kill(pid, SIGTERM); }
  } stop{server};
  std::string served;
  for (int k = 0; k < 100 && served.find("serving http://localhost:") == std::string::npos; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    served = test::read_file(log);
  }
  const size_t at = served.find("localhost:");
  ASSERT_NE(at, std::string::npos) << served;
  const std::string port = served.substr(at + 10, served.find('/', at) - at - 10);

  // Frame 2 of the orbit (the bench saves every frame it was asked for).
  const std::string url = "http://localhost:" + port +
                          "/?tileset=data/tiles/tileset.json&path=data/o.json&frame=2"
                          "&width=1024&height=768&shot=1";
  auto shot = test::run_shell("node " + web + "/snapshot.mjs '" + url + "' " + dir.file("web.png") +
                    " --timeout 120");
  ASSERT_EQ(shot.exit_status, 0) << shot.output;
  auto browser = read_png(dir.file("web.png"));
  auto brute = read_png(dir.file("b/brute_frame0002.png"));
  ASSERT_TRUE(browser) << browser.error().message;
  ASSERT_TRUE(brute) << brute.error().message;
  const ImageComparison c = compare_images(*brute, *browser);
  std::printf("web viewer against brute force at frame 2: %.2f dB, %llu pixels differ\n",
              c.psnr_db, (unsigned long long)c.differing_pixels);
  EXPECT_GE(c.psnr_db, 30.0) << "the browser's frame is not farfield's";
}

}  // namespace
}  // namespace farfield
