// A scene left on disk walked through a small cache (techniques/chunk_stream.hpp, brute with
// --cache-mb): chunks are evicted as the view moves, and every frame whose chunks were all
// loaded equals brute force's from the scene in memory, pixel for pixel (GL, headless).
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "farfield/eval/chunked_reference.hpp"
#include "farfield/eval/image_metrics.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/chunked_scene.hpp"
#include "farfield/scene/city_generator.hpp"
#include "farfield/scene/scene_file_writer.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

Scene make_city(uint32_t blocks, bool textures) {
  CityOptions options;
  options.blocks_x = options.blocks_z = blocks;
  options.textures = textures;  // texture coordinates spread per vertex on the way
  Progress quiet(true);
  auto scene = generate_city(options, quiet);
  EXPECT_TRUE(scene) << scene.error().message;
  return std::move(*scene);
}

TEST(ChunkStreamGL, SmallCacheEvictsAndLoadedFramesEqualBrute) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  test::TempDir dir;
  const Scene city = make_city(3, true);
  ASSERT_TRUE(test::write_in_chunks(city, dir.file("c.ffscene"), 3000));
  auto on_disk = ChunkedScene::open(dir.file("c.ffscene"));
  ASSERT_TRUE(on_disk) << on_disk.error().message;
  uint64_t scene_bytes = 0;
  for (const SceneChunk& k : on_disk->chunks()) scene_bytes += k.byte_size();
  ASSERT_GT(on_disk->chunks().size(), 20u);

  auto whole = gpu::Renderer::create(city);
  auto streamed = gpu::Renderer::create(on_disk->index());
  ASSERT_TRUE(whole && streamed);
  auto brute = make_technique("brute");
  auto walker = make_technique("brute", test::settings_of({"brute.wait=1"}));
  ASSERT_TRUE(test::load_technique(**brute, city, whole->get()));
  Progress silent(true);
  const uint64_t cache = scene_bytes / 4;
  ASSERT_TRUE((*walker)->load({on_disk->index(), nullptr, **streamed, silent, &*on_disk, cache}));

  const Bounds3 b = city.bounds;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> x(b.min.x, b.max.x), z(b.min.z, b.max.z),
      height(40.0f, 90.0f), yaw(0.0f, 360.0f);
  DrawList all, list;
  int complete = 0;
  for (int i = 0; i < 24; ++i) {
    View view;
    view.width = 160;
    view.height = 120;
    view.hfov_deg = 50.0f;
    view.pose = {{x(rng), height(rng), z(rng)}, yaw(rng), -85.0f};  // looking down on a block
    (*whole)->set_offscreen(view.width, view.height);
    (*streamed)->set_offscreen(view.width, view.height);
    test::select_view(**brute, view, all);
    (*whole)->draw(view, all);
    const Image reference = (*whole)->capture();
    const double incomplete = test::figure(**walker, "incomplete_frames");
    test::select_view(**walker, view, list, uint64_t(i));
    (*streamed)->draw(view, list);
    const Image image = (*streamed)->capture();
    if (test::figure(**walker, "incomplete_frames") > incomplete) continue;  // more than the cache
    ++complete;
    const ImageComparison c = compare_images(reference, image);
    EXPECT_TRUE(c.identical()) << "view " << i << ": " << c.differing_pixels
                               << " pixels differ, PSNR " << c.psnr_db;
  }
  EXPECT_GE(complete, 20);
  EXPECT_GT(test::figure(**walker, "cache_evictions"), 0) << "the cache was small enough to evict";
  EXPECT_LE(test::figure(**walker, "cache_peak_mb") * 1e6, double(cache));
  EXPECT_EQ((*walker)->failure(), "");
}

TEST(ChunkStreamGL, PartsMakeBruteForcesFrame) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  test::TempDir dir;
  const Scene city = make_city(3, true);
  ASSERT_TRUE(test::write_in_chunks(city, dir.file("c.ffscene"), 2000));
  auto on_disk = ChunkedScene::open(dir.file("c.ffscene"));
  ASSERT_TRUE(on_disk);
  auto whole = gpu::Renderer::create(city);
  auto parts = gpu::Renderer::create(on_disk->index());
  ASSERT_TRUE(whole && parts);
  auto brute = make_technique("brute");
  ASSERT_TRUE(test::load_technique(**brute, city, whole->get()));
  const Bounds3 b = city.bounds;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> x(b.min.x, b.max.x), z(b.min.z, b.max.z),
      yaw(0.0f, 360.0f), pitch(-20.0f, 20.0f);
  DrawList all;
  for (int i = 0; i < 12; ++i) {
    View view;
    view.width = 160;
    view.height = 120;
    // At street level, seeing across the city through glass: many parts, both passes.
    view.pose = {{x(rng), 1.9f, z(rng)}, yaw(rng), pitch(rng)};
    (*whole)->set_offscreen(view.width, view.height);
    (*parts)->set_offscreen(view.width, view.height);
    test::select_view(**brute, view, all);
    (*whole)->draw(view, all);
    const Image reference = (*whole)->capture();
    // A budget of a few chunks: the frame is drawn in many parts.
    ASSERT_TRUE(draw_chunked_reference(**parts, *on_disk, view, 300000));
    const ImageComparison c = compare_images(reference, (*parts)->capture());
    EXPECT_TRUE(c.identical()) << "view " << i << ": " << c.differing_pixels
                               << " pixels differ, PSNR " << c.psnr_db;
  }
}

TEST(ChunkStreamGL, ADamagedChunkIsNamedWhileWalking) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  test::TempDir dir;
  const Scene city = make_city(2, false);
  ASSERT_TRUE(write_scene(city, dir.file("c.ffscene")));
  std::string bytes = test::read_file(dir.file("c.ffscene"));
  const char* vertex = reinterpret_cast<const char*>(&city.vertices[10]);
  const size_t at = bytes.find(std::string(vertex, sizeof(Vertex)));
  ASSERT_NE(at, std::string::npos);
  bytes[at + 2] ^= 4;
  test::write_file(dir.file("c.ffscene"), bytes);
  auto on_disk = ChunkedScene::open(dir.file("c.ffscene"));
  ASSERT_TRUE(on_disk);
  auto streamed = gpu::Renderer::create(on_disk->index());
  ASSERT_TRUE(streamed);
  auto walker = make_technique("brute", test::settings_of({"brute.wait=1"}));
  Progress silent(true);
  ASSERT_TRUE((*walker)->load({on_disk->index(), nullptr, **streamed, silent, &*on_disk, 1 << 30}));
  View view;
  view.width = 64;
  view.height = 48;
  view.pose = {city.bounds.center() + glm::vec3(0, 300, 0), 0.0f, -89.0f};
  DrawList list;
  test::select_view(**walker, view, list);
  EXPECT_NE((*walker)->failure().find("chunk 0 (objects 0 to"), std::string::npos)
      << (*walker)->failure();
  EXPECT_NE((*walker)->failure().find("checksum mismatch"), std::string::npos);
}

}  // namespace
}  // namespace farfield

namespace farfield {
namespace {

TEST(ChunkStreamCliGL, BenchWalksASceneLeftOnDisk) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  test::TempDir dir;
  const std::string scene = dir.file("c.ffscene"), path = dir.file("p.json");
  ASSERT_EQ(test::run_farfield("generate city --blocks 2 -q --out " + scene).exit_status, 0);
  ASSERT_EQ(test::run_farfield("path " + scene + " --kind street --frames 6 --out " + path)
                .exit_status,
            0);
  auto run = test::run_farfield("bench " + scene + " --path " + path +
                                " --cache-mb 64 --set brute.wait=1 --width 96 --height 64 "
                                "--samples 1 --no-plot -q --out " + dir.file("b"));
  ASSERT_EQ(run.exit_status, 0) << run.output;
  const std::string json = test::read_file(dir.file("b/bench.json"));
  for (const char* field : {"\"cache_mb\": 64", "\"cache_hits\"", "\"cache_misses\"",
                            "\"bytes_read\"", "\"incomplete_frames\": 0.0"})
    EXPECT_NE(json.find(field), std::string::npos) << field << " in " << json;
  // Brute's frames are compared with the reference drawn in parts: equal, as it waited.
  EXPECT_TRUE(std::filesystem::exists(dir.file("b/brute_frame0000_reference.png")));
  EXPECT_NE(json.find("\"identical_frames\": 1"), std::string::npos) << json;
  // What cannot walk a scene on disk is refused by name, before any frame.
  auto octree = test::run_farfield("bench " + scene + " --path " + path +
                                   " --cache-mb 64 -t octree -q --out " + dir.file("o"));
  EXPECT_EQ(octree.exit_status, 1) << octree.output;
  EXPECT_NE(octree.output.find("octree cannot walk a scene left on disk"), std::string::npos)
      << octree.output;
  auto raw = test::run_farfield("bench " + scene + " --path " + path +
                                " --cache-mb 64 -t raw -q --out " + dir.file("r"));
  EXPECT_EQ(raw.exit_status, 1) << raw.output;
  EXPECT_NE(raw.output.find("not with --cache-mb"), std::string::npos) << raw.output;
}

}  // namespace
}  // namespace farfield
