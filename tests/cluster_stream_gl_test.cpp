// The clusters walk of a scene left on disk (techniques/clusters/cluster_stream.hpp, clusters
// with --cache-mb) through a small cache: pages are evicted as the view moves; every frame
// whose pages were all loaded equals the walk from the whole pack in memory, pixel for pixel;
// a frame never waits (clusters.wait=0) and is then drawn coarser, never with holes where
// the top of the hierarchy stands in; a damaged page is named (GL, headless).
#include <gtest/gtest.h>

#include <sqlite3.h>

#include <chrono>
#include <filesystem>
#include <random>
#include <thread>

#include "farfield/eval/image_metrics.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/chunked_scene.hpp"
#include "farfield/scene/city_generator.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// A small textured city in chunks of 3,000 triangles, and its clusters bake.
struct Baked {
  test::TempDir dir;
  Scene city;
  std::string scene_path, pack_path;
};

const Baked& baked() {
  static Baked* b = [] {
    auto* out = new Baked;
    CityOptions options;
    options.blocks_x = options.blocks_z = 3;
    options.textures = true;
    Progress quiet(true);
    auto city = generate_city(options, quiet);
    EXPECT_TRUE(city) << city.error().message;
    out->city = std::move(*city);
    out->scene_path = out->dir.file("c.ffscene");
    out->pack_path = out->dir.file("c.ffpack");
    EXPECT_TRUE(test::write_in_chunks(out->city, out->scene_path, 3000));
    auto r = test::run_farfield("bake " + out->scene_path +
                                " -t clusters --set clusters.accuracy_directions=4 -q --out " +
                                out->pack_path);
    EXPECT_EQ(r.exit_status, 0) << r.output;
    return out;
  }();
  return *b;
}

View looking_down(std::mt19937& rng, const Bounds3& b) {
  std::uniform_real_distribution<float> x(b.min.x, b.max.x), z(b.min.z, b.max.z),
      height(15.0f, 90.0f), yaw(0.0f, 360.0f), pitch(-80.0f, -10.0f);
  View view;
  view.width = 160;
  view.height = 120;
  view.hfov_deg = 60.0f;
  view.pose = {{x(rng), height(rng), z(rng)}, yaw(rng), pitch(rng)};
  return view;
}

// Loaded from the whole pack and from the pack and the scene left on disk, both culling with
// the bake's occluder boxes (the walk from disk has no triangles at hand for mesh occluders).
struct Walks {
  std::unique_ptr<gpu::Renderer> whole, streamed;
  std::unique_ptr<Technique> in_memory, from_disk;
  std::optional<Store> store;
  std::optional<ChunkedScene> on_disk;
  uint64_t cache = 0;
};

void load_walks(Walks& w, std::initializer_list<const char*> streamed_settings, uint64_t cache,
                std::initializer_list<const char*> both_settings = {}) {
  const Baked& b = baked();
  auto store = Store::open(b.pack_path, Store::Mode::kRead);
  ASSERT_TRUE(store) << store.error().message;
  w.store.emplace(std::move(*store));
  auto on_disk = ChunkedScene::open(b.scene_path);
  ASSERT_TRUE(on_disk) << on_disk.error().message;
  w.on_disk.emplace(std::move(*on_disk));
  auto whole = gpu::Renderer::create(b.city);
  auto streamed = gpu::Renderer::create(w.on_disk->index());
  ASSERT_TRUE(whole && streamed);
  w.whole = std::move(*whole);
  w.streamed = std::move(*streamed);
  // The same tiles of the boxes both ways (with the scene in memory the default is the pages).
  TechniqueSettings shared =
      test::settings_of({"clusters.occluders=boxes", "clusters.box_tile_px=512"});
  for (const char* s : both_settings) ASSERT_TRUE(shared.add(s));
  auto in_memory = make_technique("clusters", shared);
  ASSERT_TRUE(in_memory);
  w.in_memory = std::move(*in_memory);
  ASSERT_TRUE(test::load_technique(*w.in_memory, b.city, w.whole.get(), &*w.store));
  TechniqueSettings settings = shared;
  for (const char* s : streamed_settings) ASSERT_TRUE(settings.add(s));
  auto from_disk = make_technique("clusters", settings);
  ASSERT_TRUE(from_disk);
  w.from_disk = std::move(*from_disk);
  Progress silent(true);
  w.cache = cache;
  auto loaded = w.from_disk->load(
      {w.on_disk->index(), &*w.store, *w.streamed, silent, &*w.on_disk, cache});
  ASSERT_TRUE(loaded) << loaded.error().message;
}

Image draw(gpu::Renderer& renderer, Technique& technique, const View& view, uint64_t frame) {
  DrawList list;
  renderer.set_offscreen(view.width, view.height);
  test::select_view(technique, view, list, frame);
  renderer.draw(view, list);
  return renderer.capture();
}

uint64_t bytes_of_scene(const ChunkedScene& scene) {
  uint64_t bytes = 0;
  for (const SceneChunk& k : scene.chunks()) bytes += k.byte_size();
  return bytes;
}

TEST(ClusterStreamGL, SmallCacheEvictsAndLoadedFramesEqualTheWholePack) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  Walks w;
  auto on_disk = ChunkedScene::open(baked().scene_path);
  ASSERT_TRUE(on_disk);
  ASSERT_GT(on_disk->chunks().size(), 20u);
  ASSERT_NO_FATAL_FAILURE(load_walks(w, {"clusters.wait=1"}, bytes_of_scene(*on_disk) * 2 / 3));
  std::mt19937 rng(5);
  int complete = 0;
  for (int i = 0; i < 24; ++i) {
    const View view = looking_down(rng, baked().city.bounds);
    const Image reference = draw(*w.whole, *w.in_memory, view, uint64_t(i));
    const double coarser = test::figure(*w.from_disk, "coarser_frames");
    const Image image = draw(*w.streamed, *w.from_disk, view, uint64_t(i));
    if (test::figure(*w.from_disk, "coarser_frames") > coarser) continue;  // more than the cache
    ++complete;
    const ImageComparison c = compare_images(reference, image);
    EXPECT_TRUE(c.identical()) << "view " << i << ": " << c.differing_pixels
                               << " pixels differ, PSNR " << c.psnr_db;
  }
  EXPECT_GE(complete, 18);
  EXPECT_GT(test::figure(*w.from_disk, "cache_evictions"), 0) << "the cache was small enough to evict";
  EXPECT_LE(test::figure(*w.from_disk, "cache_peak_mb") * 1e6, double(w.cache));
  EXPECT_GT(test::figure(*w.from_disk, "pinned_mb"), 0);
  EXPECT_EQ(w.from_disk->failure(), "");
}

// Boxes (drawn where coarse is enough: at 64 px) come from the pack's pages cut into tiles on
// the loader thread: once their tiles are in, the frames are the whole pack's.
TEST(ClusterStreamGL, BoxesComeInTilesAndDrawAsTheWholePacks) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  Walks w;
  ASSERT_NO_FATAL_FAILURE(
      load_walks(w, {"clusters.wait=1"}, uint64_t(256) << 20, {"clusters.error_px=64"}));
  std::mt19937 rng(9);
  for (int i = 0; i < 6; ++i) {
    const View view = looking_down(rng, baked().city.bounds);
    const Image reference = draw(*w.whole, *w.in_memory, view, uint64_t(i));
    const Image image = draw(*w.streamed, *w.from_disk, view, uint64_t(i));
    const ImageComparison c = compare_images(reference, image);
    EXPECT_TRUE(c.identical()) << "view " << i << ": " << c.differing_pixels
                               << " pixels differ, PSNR " << c.psnr_db;
  }
  EXPECT_GT(test::figure(*w.from_disk, "mean_boxes_drawn"), 0.0);
  EXPECT_GT(test::figure(*w.from_disk, "box_tiles_in"), 0.0);
  EXPECT_LE(test::figure(*w.from_disk, "box_tiles_in"), test::figure(*w.from_disk, "box_tiles"));
  EXPECT_GE(test::figure(*w.from_disk, "box_bytes_read"),
            test::figure(*w.from_disk, "box_tiles_in") * 512 * 512 * 4);
  EXPECT_EQ(w.from_disk->failure(), "");
}

// Without waiting, the first frame has only the top of the hierarchy: it is drawn coarser,
// yet covers the city (no holes where the whole pack draws something); once the loads are
// in, the frame is the whole pack's.
TEST(ClusterStreamGL, NeverWaitsStandsInCoarserThenRefines) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  Walks w;
  ASSERT_NO_FATAL_FAILURE(load_walks(w, {}, uint64_t(256) << 20));
  View view;
  view.width = 160;
  view.height = 120;
  view.hfov_deg = 60.0f;
  const Bounds3& b = baked().city.bounds;
  view.pose = {{b.min.x - 20.0f, 60.0f, b.min.z - 20.0f}, 45.0f, -30.0f};
  const Image reference = draw(*w.whole, *w.in_memory, view, 0);
  const Image first = draw(*w.streamed, *w.from_disk, view, 0);
  EXPECT_EQ(test::figure(*w.from_disk, "coarser_frames"), 1);
  EXPECT_GT(test::figure(*w.from_disk, "stood_in"), 0);
  // Where the whole pack's frame shows the city, the first one does too (the sky is the
  // clear colour of the top-left pixel).
  auto sky = [](const Image& im, int x, int y) {
    return std::equal(im.pixel(x, y), im.pixel(x, y) + 3, im.pixel(0, 0));
  };
  int city = 0, covered = 0;
  for (int y = view.height / 2; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x)
      if (!sky(reference, x, y)) {
        ++city;
        covered += !sky(first, x, y);
      }
  ASSERT_GT(city, view.width * view.height / 4);
  EXPECT_GT(covered, city * 9 / 10) << "the top of the hierarchy stands in";
  Image image;
  for (int frame = 1; frame < 40; ++frame) {
    const double coarser = test::figure(*w.from_disk, "coarser_frames");
    image = draw(*w.streamed, *w.from_disk, view, uint64_t(frame));
    if (test::figure(*w.from_disk, "coarser_frames") == coarser) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const ImageComparison c = compare_images(draw(*w.whole, *w.in_memory, view, 40), image);
  EXPECT_TRUE(c.identical()) << c.differing_pixels << " pixels differ, PSNR " << c.psnr_db;
}

// In the street the walk from disk culls with the bake's boxes: fewer triangles than without
// occlusion, and the same as the walk from the whole pack.
TEST(ClusterStreamGL, CullsWithTheBakesOccluderBoxes) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  View view;
  view.width = 256;
  view.height = 192;
  view.pose = {{8.0f, 1.9f, 8.0f}, 0.0f, 0.0f};  // at the first crossing, along the street
  auto triangles = [&](std::initializer_list<const char*> streamed_settings,
                       bool whole_pack = false) {
    Walks w;
    load_walks(w, streamed_settings, uint64_t(256) << 20);
    DrawList list;
    test::select_view(whole_pack ? *w.in_memory : *w.from_disk, view, list);
    return list.triangle_count();
  };
  const uint64_t culled = triangles({"clusters.wait=1"});
  EXPECT_LT(culled, triangles({"clusters.wait=1", "clusters.occlusion=0"}));
  EXPECT_EQ(culled, triangles({}, true));
}

// Walking down a street, pages asked for ahead of the motion are loaded before the frames
// that draw them want them: fewer misses than without prefetching, the frames the same.
TEST(ClusterStreamGL, PrefetchingAlongTheMotionMissesLess) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  auto walk = [&](const char* prefetch, std::vector<Image>& frames) {
    Walks w;
    load_walks(w, {"clusters.wait=1", prefetch}, uint64_t(256) << 20);
    View view;
    view.width = 160;
    view.height = 120;
    for (int frame = 0; frame < 30; ++frame) {
      view.pose = {{8.0f, 1.9f, 8.0f + 3.0f * float(frame)}, 0.0f, 0.0f};
      frames.push_back(draw(*w.streamed, *w.from_disk, view, uint64_t(frame)));
    }
    EXPECT_EQ(test::figure(*w.from_disk, "coarser_frames"), 0);
    return std::pair(test::figure(*w.from_disk, "cache_misses"),
                     test::figure(*w.from_disk, "cache_prefetches"));
  };
  std::vector<Image> ahead_frames, plain_frames;
  const auto [ahead_misses, prefetches] = walk("clusters.prefetch_frames=15", ahead_frames);
  const auto [plain_misses, none] = walk("clusters.prefetch_frames=0", plain_frames);
  EXPECT_GT(prefetches, 0);
  EXPECT_EQ(none, 0);
  EXPECT_LT(ahead_misses, plain_misses);
  for (size_t f = 0; f < plain_frames.size(); ++f)
    EXPECT_TRUE(compare_images(ahead_frames[f], plain_frames[f]).identical()) << "frame " << f;
}

// A level's page or a box page whose bytes were damaged: named (pack and blob) as the walk
// reaches it.
TEST(ClusterStreamGL, ADamagedPageIsNamedWhileWalking) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  // Boxes are drawn where coarse is enough: a walk at 64 px.
  for (const auto& [blobs, error_px] :
       {std::pair<std::string, const char*>{"clusters/lod_page/", "clusters.error_px=1"},
        {"clusters/box_page_", "clusters.error_px=64"}}) {
    SCOPED_TRACE(blobs);
    test::TempDir dir;
    const std::string pack = dir.file("damaged.ffpack");
    std::filesystem::copy_file(baked().pack_path, pack);
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(pack.c_str(), &db), SQLITE_OK);
    const std::string damage =
        "UPDATE blobs SET data = zeroblob(length(data)) WHERE name LIKE '" + blobs + "%'";
    ASSERT_EQ(sqlite3_exec(db, damage.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
    EXPECT_GT(sqlite3_changes(db), 0);
    sqlite3_close(db);
    auto store = Store::open(pack, Store::Mode::kRead);
    ASSERT_TRUE(store);
    auto on_disk = ChunkedScene::open(baked().scene_path);
    ASSERT_TRUE(on_disk);
    auto renderer = gpu::Renderer::create(on_disk->index());
    ASSERT_TRUE(renderer);
    auto walker = make_technique("clusters", test::settings_of({"clusters.wait=1", error_px}));
    ASSERT_TRUE(walker);
    Progress silent(true);
    ASSERT_TRUE((*walker)->load(
        {on_disk->index(), &*store, **renderer, silent, &*on_disk, uint64_t(64) << 20}));
    std::mt19937 rng(3);
    for (int i = 0; i < 8 && (*walker)->failure().empty(); ++i)
      draw(**renderer, **walker, looking_down(rng, baked().city.bounds), uint64_t(i));
    const std::string failure = (*walker)->failure();
    EXPECT_NE(failure.find("damaged.ffpack"), std::string::npos) << failure;
    EXPECT_NE(failure.find(blobs), std::string::npos) << failure;
    if (blobs != "clusters/box_page_") continue;
    // The boxes' tiles never come: their average-colour boxes stand in for them, once what
    // else the view wants is in (until then the top of the hierarchy stands for all). A view
    // at 24 px that chooses boxes.
    walker = make_technique("clusters", test::settings_of({"clusters.error_px=24"}));
    ASSERT_TRUE(walker);
    ASSERT_TRUE((*walker)->load(
        {on_disk->index(), &*store, **renderer, silent, &*on_disk, uint64_t(64) << 20}));
    View view;
    view.width = 160;
    view.height = 120;
    view.hfov_deg = 60.0f;
    const Bounds3& b = baked().city.bounds;
    view.pose = {{b.min.x - 20.0f, 60.0f, b.min.z - 20.0f}, 45.0f, -30.0f};
    for (int i = 0; i < 100 && test::figure(**walker, "mean_average_boxes_drawn") == 0; ++i) {
      draw(**renderer, **walker, view, uint64_t(8 + i));
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    EXPECT_GT(test::figure(**walker, "mean_average_boxes_drawn"), 0);
  }
}

// Streaming needs a bake: refused, saying so, without one.
TEST(ClusterStreamGL, RefusedWithoutABake) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << "no GL context";
  auto on_disk = ChunkedScene::open(baked().scene_path);
  ASSERT_TRUE(on_disk);
  auto renderer = gpu::Renderer::create(on_disk->index());
  ASSERT_TRUE(renderer);
  auto walker = make_technique("clusters");
  ASSERT_TRUE(walker);
  Progress silent(true);
  auto loaded = (*walker)->load(
      {on_disk->index(), nullptr, **renderer, silent, &*on_disk, uint64_t(64) << 20});
  ASSERT_FALSE(loaded);
  EXPECT_NE(loaded.error().message.find("bake"), std::string::npos) << loaded.error().message;
}

}  // namespace
}  // namespace farfield
