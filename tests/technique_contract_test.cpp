// What every technique promises through the Technique interface and its descriptor,
// whichever it is: every registered technique is checked, stratified and composite included.
#include <gtest/gtest.h>

#include "farfield/core/camera_path.hpp"
#include "farfield/eval/bake_run.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// select() appends: what another technique (or an earlier part of a composite) put in the
// list stays, and something of its own is added. Techniques that need a bake get one.
TEST(TechniqueContractGL, SelectAppendsToWhatTheListHolds) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  const Scene scene = test::make_box_row(4);
  test::TempDir dir;
  const std::string pack = dir.file("all.ffpack");
  Progress quiet(true);
  // The whole row is the navigable region; small boxes so that something is far.
  const TechniqueSettings settings =
      test::settings_of({"stratified.band=all", "stratified.box=2", "stratified.viewcell=1",
                         "ibr.d_theta=90", "ibr.d_phi=90", "ibr.resolution=32",
                         "hybrid.d_theta=90", "hybrid.d_phi=90", "hybrid.width=64",
                         "hybrid.height=48"});
  for (const TechniqueDescriptor* d : technique_descriptors())
    if (d->bake == BakeUse::required) {
      TechniqueSettings mine;
      for (const auto& [key, value] : settings.for_technique(d->name))
        mine.values[std::string(d->name) + "." + key] = value;
      auto baked = run_bake(scene, std::string(d->name), mine, pack, quiet);
      ASSERT_TRUE(baked) << d->name << ": " << baked.error().message;
    }
  // The bakes made and dropped their own contexts: this one is made after them.
  auto context = gpu::create_headless_context();
  ASSERT_TRUE(context);
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  auto store = Store::open(pack, Store::Mode::kRead);
  ASSERT_TRUE(store) << store.error().message;
  for (const TechniqueDescriptor* d : technique_descriptors()) {
    auto technique = make_technique(d->name, settings);
    ASSERT_TRUE(technique) << d->name << ": " << technique.error().message;
    EXPECT_EQ((*technique)->name(), d->name);
    ASSERT_TRUE(test::load_technique(**technique, scene, renderer->get(), &*store)) << d->name;
    DrawList list;
    list.lines.push_back({{0, 0, 0}, {1, 1, 1}, 0xffffffffu});
    list.opaque.push_back({0, 36, 0});
    View view;
    view.pose.position = {0.5f, 0.5f, -3.0f};
    view.pose.yaw_deg = 90;
    (*technique)->select({view, 0, Region::everything(), {}}, list);
    ASSERT_EQ(list.lines.size(), 1u) << d->name;
    ASSERT_GE(list.opaque.size(), 1u) << d->name;
    EXPECT_EQ(list.opaque[0].first_index, 0u) << d->name;
    EXPECT_GT(list.triangle_count(), 12u) << d->name << " added nothing";
    (*renderer)->set_offscreen(view.width, view.height);
    (*renderer)->draw(view, list);
    (*technique)->frame_done(0);
    EXPECT_TRUE((*technique)->failure().empty()) << d->name;
  }
}

// Every descriptor's defaults parse, its settings are described, and help names them all.
TEST(TechniqueContract, DescriptorsParseTheirDefaultsAndDescribeEverySetting) {
  const std::string help = techniques_help();
  for (const TechniqueDescriptor* d : technique_descriptors()) {
    EXPECT_FALSE(d->summary.empty()) << d->name;
    ASSERT_NE(d->make, nullptr) << d->name;
    auto values = parse_settings(*d, {});
    ASSERT_TRUE(values) << d->name << ": " << values.error().message;
    for (const SettingSpec& s : d->settings) {
      EXPECT_FALSE(s.help.empty()) << d->name << "." << s.key;
      EXPECT_NE(help.find(std::string(d->name) + "." + std::string(s.key) + ":"), std::string::npos)
          << d->name << "." << s.key;
      EXPECT_FALSE(values->given(s.key));
    }
    if (d->bake != BakeUse::none) {
      EXPECT_GT(d->bake_format, 0) << d->name;
    }
  }
}

// One parser, one set of rules: whole numbers are whole, ranges hold, choices are choices,
// unknown keys and technique names are refused with the setting named.
TEST(TechniqueContract, OneParserRefusesWhatNoTechniqueTakes) {
  struct Case {
    const char* assignment;
    const char* named;
  };
  for (const Case& c :
       {Case{"colorcube.depth=6.7", "colorcube.depth"},
        Case{"colorcube.depth=13", "colorcube.depth"},
        Case{"colorcube.depth=six", "colorcube.depth"},
        Case{"colorcube.occlusion=2", "colorcube.occlusion"},
        Case{"colorcube.inner_faces=sometimes", "colorcube.inner_faces"},
        Case{"colorcube.pixels=0", "colorcube.pixels"},
        Case{"stratified.alpha=90", "stratified.alpha"},
        Case{"stratified.resolution=512.5", "stratified.resolution"},
        Case{"stratified.band=1,0", "stratified.band"}, Case{"octree.warp=1", "octree.warp"},
        Case{"brute.depth=1", "brute.depth"}, Case{"composite.near=colorcube", "composite.near"}}) {
    TechniqueSettings settings;
    ASSERT_TRUE(settings.add(c.assignment)) << c.assignment;
    const std::string technique =
        std::string(c.assignment).substr(0, std::string(c.assignment).find('.'));
    auto t = make_technique(technique, settings);
    ASSERT_FALSE(t) << c.assignment << " was taken";
    EXPECT_NE(t.error().message.find(c.named), std::string::npos) << t.error().message;
  }
  TechniqueSettings settings;
  auto misspelt = settings.add("colourcube.depth=6");
  ASSERT_FALSE(misspelt);
  EXPECT_NE(misspelt.error().message.find("colourcube"), std::string::npos);
  EXPECT_FALSE(settings.add("depth=3"));  // no technique name
  // Whole-number spellings of whole numbers are whole.
  ASSERT_TRUE(settings.add("colorcube.depth=6.0"));
  EXPECT_TRUE(make_technique("colorcube", settings));
}

}  // namespace
}  // namespace farfield

namespace farfield {
namespace {

// A technique's render resources live on the device it loaded with and go with it: colorcube
// makes one mesh, the mesh its cube faces, and frees it when destroyed; its draws name it.
TEST(TechniqueContract, ResourcesAreMadeOnTheDeviceAndFreedWithTheTechnique) {
  const Scene scene = test::make_box_row(4);
  gpu::MemoryDevice device;
  {
    auto technique = make_technique("colorcube", test::settings_of({"colorcube.depth=2"}));
    ASSERT_TRUE(technique) << technique.error().message;
    ASSERT_TRUE(test::load_technique(**technique, scene, &device));
    ASSERT_EQ(device.live_meshes(), 1u);
    EXPECT_EQ(device.live_textures(), 0u);
    View view;
    view.pose.position = {0.5f, 0.5f, -3.0f};
    view.pose.yaw_deg = 90;
    DrawList list;
    test::select_view(**technique, view, list);
    ASSERT_FALSE(list.meshes.empty());
    const ProxyMesh& mesh = device.mesh(list.meshes[0].mesh);
    for (const MeshDraw& d : list.meshes) {
      EXPECT_EQ(d.mesh, list.meshes[0].mesh);
      EXPECT_LE(uint64_t(d.first_index) + d.index_count, mesh.indices.size());
    }
    EXPECT_GT(device.resource_bytes(), 0u);
  }
  EXPECT_EQ(device.live_meshes(), 0u);
}

}  // namespace
}  // namespace farfield
