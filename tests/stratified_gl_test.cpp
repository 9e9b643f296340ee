// Stratified rendering (paper 000) end to end on a small generated city: bake the viewcells a
// street path needs, walk the path, compare with brute force; the render styles of Sec. 5.1;
// a damaged blob found while walking. GL, headless; skipped without a context.
#include <gtest/gtest.h>

#include <sqlite3.h>

#include <optional>
#include <set>

#include "farfield/core/camera_path.hpp"
#include "farfield/eval/bake_run.hpp"
#include "farfield/eval/image_metrics.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/city_generator.hpp"
#include "farfield/scene/path_generator.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

struct Walk {
  Scene city;
  CameraPath path;
  test::TempDir dir;
  std::string pack;
};

// A 3 x 3 block city, a 60-frame street path, and its stratified bake (box 120 m, 128 px).
std::unique_ptr<Walk> bake_walk(const std::vector<std::string>& extra = {}) {
  auto walk = std::make_unique<Walk>();
  CityOptions options;
  options.blocks_x = options.blocks_z = 3;
  Progress quiet(true);
  auto city = generate_city(options, quiet);
  EXPECT_TRUE(city);
  walk->city = std::move(*city);
  PathOptions po;
  po.frames = 60;
  auto path = generate_path(walk->city, po);
  EXPECT_TRUE(path);
  walk->path = std::move(*path);
  const std::string path_file = walk->dir.file("street.json");
  EXPECT_TRUE(write_camera_path(walk->path, path_file));
  TechniqueSettings settings;
  for (const std::string& s : std::vector<std::string>{
           "stratified.box=120", "stratified.resolution=128", "stratified.path=" + path_file})
    EXPECT_TRUE(settings.add(s));
  for (const std::string& s : extra) EXPECT_TRUE(settings.add(s));
  walk->pack = walk->dir.file("walk.ffpack");
  auto baked = run_bake(walk->city, "stratified", settings, walk->pack, quiet);
  EXPECT_TRUE(baked) << baked.error().message;
  return walk;
}

// A GL context, a renderer of the walk's city and its pack opened for reading; null members
// when one could not be made.
struct Drawing {
  std::unique_ptr<gpu::Context> context;  // destroyed last
  std::unique_ptr<gpu::Renderer> renderer;
  std::optional<Store> store;
};
Drawing draw_walk(const Walk& walk) {
  Drawing d;
  auto context = gpu::create_headless_context();
  if (!context) return d;
  d.context = std::move(*context);
  if (auto renderer = gpu::Renderer::create(walk.city)) d.renderer = std::move(*renderer);
  if (auto store = Store::open(walk.pack, Store::Mode::kRead)) d.store.emplace(std::move(*store));
  return d;
}

TEST(StratifiedGL, WalkMatchesBruteWithinTheBoundAndCrossesViewcells) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  auto walk = bake_walk();
  Drawing d = draw_walk(*walk);
  ASSERT_TRUE(d.renderer && d.store);
  gpu::Renderer* renderer = d.renderer.get();
  auto& store = d.store;
  auto brute = make_technique("brute");
  ASSERT_TRUE(test::load_technique(**brute, walk->city, renderer));
  auto stratified = make_technique("stratified");
  ASSERT_TRUE(stratified);
  ASSERT_TRUE(test::load_technique(**stratified, walk->city, renderer, &*store));
  auto unbaked = make_technique("stratified");
  EXPECT_FALSE(test::load_technique(**unbaked, walk->city, renderer));  // needs its bake

  DrawList all, list;
  double psnr_sum = 0;
  int compared = 0;
  uint64_t near_triangles = 0;
  for (size_t f = 0; f < walk->path.frames.size(); ++f) {
    View view;
    view.width = 256;
    view.height = 192;
    view.pose = walk->path.frames[f];
    renderer->set_offscreen(view.width, view.height);
    test::select_view(**stratified, view, list);
    ASSERT_FALSE(list.backdrop.empty()) << "frame " << f;
    near_triangles += list.triangle_count() - 2 * list.backdrop.size();
    renderer->draw(view, list);
    if (f % 6 != 0) continue;
    const Image image = renderer->capture();
    test::select_view(**brute, view, all);
    renderer->draw(view, all);
    const ImageComparison c = compare_images(renderer->capture(), image);
    psnr_sum += std::min(c.psnr_db, 60.0);
    ++compared;
    EXPECT_GT(c.psnr_db, 18.0) << "frame " << f;
  }
  EXPECT_GT(psnr_sum / compared, 24.0);
  EXPECT_EQ((*stratified)->failure(), "");
  EXPECT_GT(test::figure(**stratified, "crossings"), 5.0);
  EXPECT_EQ(test::figure(**stratified, "frames_in_unbaked_viewcells"), 0.0);
  // Near geometry is a small part of the city.
  EXPECT_LT(near_triangles / walk->path.frames.size(), walk->city.triangle_count() / 4);
}

// paper 000, Sec. 5.1: near only + far texture only = full; far objects and brute draw geometry.
TEST(StratifiedGL, RenderStylesSplitTheFrame) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  auto walk = bake_walk();
  auto context = gpu::create_headless_context();
  ASSERT_TRUE(context);
  auto store = Store::open(walk->pack, Store::Mode::kRead);
  ASSERT_TRUE(store);
  View view;
  view.width = 128;
  view.height = 96;
  view.pose = walk->path.frames[30];
  std::map<std::string, DrawList> lists;
  for (const std::string style : {"full", "near", "far-objects", "far-texture", "brute"}) {
    TechniqueSettings settings;
    ASSERT_TRUE(settings.add("stratified.style=" + style));
    auto t = make_technique("stratified", settings);
    ASSERT_TRUE(t);
    ASSERT_TRUE(test::load_technique(**t, walk->city, nullptr, &*store));
    test::select_view(**t, view, lists[style]);
  }
  EXPECT_EQ(lists["near"].opaque.size(), lists["full"].opaque.size());
  EXPECT_TRUE(lists["near"].backdrop.empty());
  EXPECT_TRUE(lists["far-texture"].opaque.empty());
  EXPECT_EQ(lists["far-texture"].backdrop.size(), lists["full"].backdrop.size());
  EXPECT_GT(lists["far-objects"].triangle_count(), lists["near"].triangle_count());
  EXPECT_TRUE(lists["far-objects"].backdrop.empty());
  EXPECT_EQ(lists["brute"].triangle_count(), walk->city.triangle_count());
}

// paper 000, Ch. 4: two shells; the inner far field carries coverage and is drawn over the
// outer one, the frame stays close to brute force.
TEST(StratifiedGL, TwoShellsNestTheirFarFields) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  auto walk =
      bake_walk({"stratified.shells=2", "stratified.spacing=linear", "stratified.factor=1.5"});
  Drawing d = draw_walk(*walk);
  ASSERT_TRUE(d.renderer && d.store);
  gpu::Renderer* renderer = d.renderer.get();
  auto& store = d.store;
  auto t = make_technique("stratified");
  ASSERT_TRUE(test::load_technique(**t, walk->city, renderer, &*store));
  EXPECT_DOUBLE_EQ(test::figure(**t, "shell1_box_m"), 180.0);
  EXPECT_GT(test::figure(**t, "shell1_viewcell_m"), test::figure(**t, "shell0_viewcell_m"));
  auto brute = make_technique("brute");
  ASSERT_TRUE(test::load_technique(**brute, walk->city, renderer));
  DrawList list, all;
  double psnr_sum = 0;
  int compared = 0;
  for (size_t f = 0; f < walk->path.frames.size(); f += 10) {
    View view;
    view.width = 256;
    view.height = 192;
    view.pose = walk->path.frames[f];
    renderer->set_offscreen(view.width, view.height);
    test::select_view(**t, view, list);
    // Textures come in sets of six sides, one set per viewcell, made in order by this
    // fresh renderer (handles 1, 2, ...): two viewcells, the outer first.
    std::set<uint32_t> sets;
    for (const TexturedQuad& q : list.backdrop) sets.insert((q.texture.id - 1) / 6);
    EXPECT_EQ(sets.size(), 2u) << "frame " << f;
    for (const TextureUpload& u : list.uploads) EXPECT_TRUE(u.channels == 3 || u.channels == 4);
    renderer->draw(view, list);
    const Image image = renderer->capture();
    test::select_view(**brute, view, all);
    renderer->draw(view, all);
    psnr_sum += compare_images(renderer->capture(), image).psnr_db;
    ++compared;
  }
  EXPECT_GT(psnr_sum / compared, 22.0);
  EXPECT_EQ((*t)->failure(), "");
}

TEST(StratifiedGL, DeltaCodedPngBakeDrawsTheSameAsPlainPng) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  auto plain = bake_walk({"stratified.codec=png"});
  auto delta = bake_walk({"stratified.codec=png", "stratified.delta=1"});
  auto a = Store::open(plain->pack, Store::Mode::kRead);
  auto b = Store::open(delta->pack, Store::Mode::kRead);
  ASSERT_TRUE(a && b);
  auto ta = make_technique("stratified"), tb = make_technique("stratified");
  ASSERT_TRUE(test::load_technique(**ta, plain->city, nullptr, &*a));
  ASSERT_TRUE(test::load_technique(**tb, delta->city, nullptr, &*b));
  DrawList la, lb;
  for (size_t f = 0; f < plain->path.frames.size(); f += 7) {
    View view;
    view.pose = plain->path.frames[f];
    test::select_view(**ta, view, la);
    test::select_view(**tb, view, lb);
    ASSERT_EQ(la.uploads.size(), lb.uploads.size());
    for (size_t i = 0; i < la.uploads.size(); ++i) {
      const TextureUpload &x = la.uploads[i], &y = lb.uploads[i];
      ASSERT_EQ(x.width * x.height * x.channels, y.width * y.height * y.channels);
      EXPECT_EQ(0, std::memcmp(x.pixels, y.pixels, size_t(x.width * x.height * x.channels)));
    }
  }
  auto bytes_a = a->total_bytes("stratified/"), bytes_b = b->total_bytes("stratified/");
  std::printf("png %llu bytes, png with delta coding %llu bytes\n", (unsigned long long)*bytes_a,
              (unsigned long long)*bytes_b);
  EXPECT_LT(*bytes_b, *bytes_a);
}

TEST(StratifiedGL, DamagedBlobIsNamedWhileWalking) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  auto walk = bake_walk();
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(walk->pack.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db,
                           "UPDATE blobs SET data = zeroblob(length(data)) "
                           "WHERE name LIKE 'stratified/s0/%/face0'",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  auto store = Store::open(walk->pack, Store::Mode::kRead);
  ASSERT_TRUE(store);
  auto t = make_technique("stratified");
  ASSERT_TRUE(test::load_technique(**t, walk->city, nullptr, &*store));
  View view;
  view.pose = walk->path.frames[0];
  DrawList list;
  test::select_view(**t, view, list);
  const std::string failure = (*t)->failure();
  EXPECT_NE(failure.find(walk->pack), std::string::npos) << failure;
  EXPECT_NE(failure.find("/face0' is corrupted"), std::string::npos) << failure;
  // The frame is still drawn, with every visible object instead of the far field.
  EXPECT_TRUE(list.backdrop.empty());
  EXPECT_GT(list.triangle_count(), 0u);
}

}  // namespace
}  // namespace farfield
