// Paper 003's hybrid renderer: the triangles a frame shows (the renderer's visibility pass),
// and the hybrid technique baked and drawn: at a viewpoint its frame is brute's, pixel for
// pixel, from a fraction of the triangles; its bake resumes, reports Table 3 and names damage.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "farfield/core/view_sphere.hpp"
#include "farfield/eval/bake_run.hpp"
#include "farfield/eval/image_metrics.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/path_generator.hpp"
#include "farfield/scene/tree_generator.hpp"
#include "farfield/spatial/ray_caster.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// The triangles of `object` facing `normal`.
std::vector<uint32_t> face(const Scene& scene, uint32_t object, const glm::vec3& normal) {
  std::vector<uint32_t> out;
  const Object& o = scene.objects[object];
  for (uint32_t i = o.first_index; i < o.first_index + o.index_count; i += 3) {
    const glm::vec3 a = scene.vertices[scene.indices[i]].position,
                    b = scene.vertices[scene.indices[i + 1]].position,
                    c = scene.vertices[scene.indices[i + 2]].position;
    if (glm::dot(glm::normalize(glm::cross(b - a, c - a)), normal) > 0.99f) out.push_back(i / 3);
  }
  return out;
}

bool holds(const std::vector<uint32_t>& set, const std::vector<uint32_t>& part) {
  return std::all_of(part.begin(), part.end(), [&](uint32_t t) {
    return std::binary_search(set.begin(), set.end(), t);
  });
}
bool misses(const std::vector<uint32_t>& set, const std::vector<uint32_t>& part) {
  return std::none_of(part.begin(), part.end(), [&](uint32_t t) {
    return std::binary_search(set.begin(), set.end(), t);
  });
}

// An opaque box hides what is behind it; a glass box hides nothing, and shows its far side.
TEST(VisibleTrianglesGL, OpaqueSurfacesHideAndGlassDoesNot) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  const Scene scene = test::make_box_row(2);  // box 0 opaque at x 0..1, box 1 glass at 2..3
  auto renderer = gpu::Renderer::create(scene);
  ASSERT_TRUE(renderer);
  ObjectSet all(scene);
  all.insert_all();
  DrawList list;
  all.emit(list);
  View view;
  view.width = 160;
  view.height = 120;
  view.hfov_deg = 60;
  (*renderer)->set_offscreen(view.width, view.height);
  // From -X along the row: box 0's near face, nothing of box 1.
  view.pose.position = {-3.0f, 0.5f, 0.5f};
  view.pose.yaw_deg = 0.0f;
  std::vector<uint32_t> seen = (*renderer)->visible_triangles(view, list);
  EXPECT_TRUE(holds(seen, face(scene, 0, {-1, 0, 0})));
  EXPECT_TRUE(misses(seen, face(scene, 0, {1, 0, 0})));
  for (uint32_t t : seen) EXPECT_LT(t, scene.objects[1].first_index / 3) << "box 1 is hidden";
  // From +X: the glass box's near and far faces, and box 0's face through it.
  view.pose.position = {6.0f, 0.5f, 0.5f};
  view.pose.yaw_deg = 180.0f;
  seen = (*renderer)->visible_triangles(view, list);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_TRUE(holds(seen, face(scene, 1, {1, 0, 0})));
  EXPECT_TRUE(holds(seen, face(scene, 1, {-1, 0, 0})));
  EXPECT_TRUE(holds(seen, face(scene, 0, {1, 0, 0})));
  EXPECT_TRUE(misses(seen, face(scene, 0, {-1, 0, 0})));
}

// The frame of coarse()'s viewpoints (its width and height), with the scene's near plane.
View coarse_view(const Scene& scene) {
  View view;
  view.width = 128;
  view.height = 96;
  view.near_m = near_plane_for(scene.bounds);
  return view;
}

TechniqueSettings coarse(std::initializer_list<const char*> more = {}) {
  TechniqueSettings s = test::settings_of(
      {"hybrid.d_theta=90", "hybrid.d_phi=45", "hybrid.width=128", "hybrid.height=96"});
  for (const char* m : more) EXPECT_TRUE(s.add(m));
  return s;
}

// At a viewpoint, with the walk's view, the frame is brute's, from a part of the triangles;
// with either codec and with the union of the viewpoints around.
TEST(HybridGL, AtAViewpointTheFrameIsBrutes) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  Progress quiet(true);
  TreeOptions tree;
  auto scene = generate_tree(tree, quiet);
  ASSERT_TRUE(scene);
  test::TempDir dir;
  for (const char* codec : {"hybrid.codec=paper", "hybrid.codec=zstd"}) {
    const std::string pack = dir.file(std::string(codec + 13) + ".ffpack");
    auto baked = run_bake(*scene, "hybrid", coarse({codec}), pack, quiet);
    ASSERT_TRUE(baked) << baked.error().message;
    auto context = gpu::create_headless_context();
    ASSERT_TRUE(context);
    auto renderer = gpu::Renderer::create(*scene);
    ASSERT_TRUE(renderer);
    auto store = Store::open(pack, Store::Mode::kRead);
    ASSERT_TRUE(store);
    const ViewSphere sphere = ViewSphere::with_steps(
        scene->bounds.center(), float(whole_view_distance(scene->bounds)), 90, 45);
    View view = coarse_view(*scene);
    auto brute = make_technique("brute");
    ASSERT_TRUE(brute);
    ASSERT_TRUE(test::load_technique(**brute, *scene, renderer->get()));
    (*renderer)->set_offscreen(view.width, view.height);
    for (const char* join : {"hybrid.union=nearest", "hybrid.union=around"}) {
      auto hybrid = make_technique("hybrid", coarse({codec, join}));
      ASSERT_TRUE(hybrid);
      ASSERT_TRUE(test::load_technique(**hybrid, *scene, renderer->get(), &*store));
      for (uint32_t id : {9u, 14u}) {  // above the horizon, and looking down at 45 degrees
        view.pose = sphere.pose(id);
        DrawList list;
        test::select_view(**brute, view, list);
        (*renderer)->draw(view, list);
        const Image reference = (*renderer)->capture();
        test::select_view(**hybrid, view, list);
        EXPECT_LT(list.triangle_count(), scene->triangle_count() / 2) << codec << " " << id;
        (*renderer)->draw(view, list);
        const ImageComparison c = compare_images(reference, (*renderer)->capture());
        EXPECT_TRUE(c.identical()) << codec << " " << join << " viewpoint " << id << ": "
                                   << c.differing_pixels << " pixels differ";
      }
      EXPECT_TRUE((*hybrid)->failure().empty());
    }
  }
}

// Sec. 3.2's finer frame: between viewpoints the eye sees triangles smaller than a pixel
// that no viewpoint's frame at the walk's resolution saw; at three times it sees more of them,
// so fewer pixels are missing. An even multiple is refused (its pixel centres miss the walk's).
TEST(HybridGL, AFinerFrameMissesLessBetweenViewpoints) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  Progress quiet(true);
  auto scene = generate_tree(TreeOptions{}, quiet);
  ASSERT_TRUE(scene);
  test::TempDir dir;
  View view = coarse_view(*scene);
  view.pose = pose_on_sphere(scene->bounds.center(), float(whole_view_distance(scene->bounds)),
                             30.0f, 20.0f);
  uint64_t missing[2] = {0, 0}, drawn[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const char* scale = k == 0 ? "hybrid.scale=1" : "hybrid.scale=3";
    const std::string pack = dir.file(std::to_string(k) + ".ffpack");
    ASSERT_TRUE(run_bake(*scene, "hybrid", coarse({scale}), pack, quiet));
    auto context = gpu::create_headless_context();
    ASSERT_TRUE(context);
    auto renderer = gpu::Renderer::create(*scene);
    ASSERT_TRUE(renderer);
    auto store = Store::open(pack, Store::Mode::kRead);
    ASSERT_TRUE(store);
    auto brute = make_technique("brute");
    auto hybrid = make_technique("hybrid", coarse({scale}));
    ASSERT_TRUE(brute && hybrid);
    ASSERT_TRUE(test::load_technique(**brute, *scene, renderer->get()));
    ASSERT_TRUE(test::load_technique(**hybrid, *scene, renderer->get(), &*store));
    (*renderer)->set_offscreen(view.width, view.height);
    DrawList list;
    test::select_view(**brute, view, list);
    (*renderer)->draw(view, list);
    const Image reference = (*renderer)->capture();
    test::select_view(**hybrid, view, list);
    drawn[k] = list.triangle_count();
    (*renderer)->draw(view, list);
    missing[k] = compare_images(reference, (*renderer)->capture()).differing_pixels;
  }
  std::printf("between viewpoints: %llu pixels differ at scale 1 (%llu triangles), %llu at 3 "
              "(%llu)\n", (unsigned long long)missing[0], (unsigned long long)drawn[0],
              (unsigned long long)missing[1], (unsigned long long)drawn[1]);
  EXPECT_GT(drawn[1], drawn[0]);
  EXPECT_LT(missing[1], missing[0]);
  EXPECT_GT(missing[0], 0u) << "nothing missing at the walk's resolution: the view is no test";
  EXPECT_FALSE(make_technique("hybrid", test::settings_of({"hybrid.scale=2"})));
}

// Paper 003, Sec. 3: the hybrid frame is the scene's own geometry, so a new light lights it as
// it lights brute's; and a pixel picks the triangle a CPU ray through it meets first.
TEST(HybridGL, RelightsAndPicksAsTheScene) {
  if (!gpu::create_headless_context()) GTEST_SKIP() << "no GL context";
  Progress quiet(true);
  auto scene = generate_tree(TreeOptions{}, quiet);
  ASSERT_TRUE(scene);
  test::TempDir dir;
  const std::string pack = dir.file("h.ffpack");
  ASSERT_TRUE(run_bake(*scene, "hybrid", coarse(), pack, quiet));
  auto context = gpu::create_headless_context();
  ASSERT_TRUE(context);
  auto renderer = gpu::Renderer::create(*scene);
  ASSERT_TRUE(renderer);
  auto store = Store::open(pack, Store::Mode::kRead);
  ASSERT_TRUE(store);
  const ViewSphere sphere = ViewSphere::with_steps(
      scene->bounds.center(), float(whole_view_distance(scene->bounds)), 90, 45);
  View view = coarse_view(*scene);
  view.pose = sphere.pose(9);
  auto brute = make_technique("brute");
  auto hybrid = make_technique("hybrid", coarse());
  ASSERT_TRUE(brute && hybrid);
  ASSERT_TRUE(test::load_technique(**brute, *scene, renderer->get()));
  ASSERT_TRUE(test::load_technique(**hybrid, *scene, renderer->get(), &*store));
  (*renderer)->set_offscreen(view.width, view.height);
  DrawList brute_list, hybrid_list;
  test::select_view(**brute, view, brute_list);
  test::select_view(**hybrid, view, hybrid_list);
  (*renderer)->draw(view, brute_list);
  const Image before = (*renderer)->capture();
  (*renderer)->set_light(120.0f, 50.0f);
  (*renderer)->draw(view, brute_list);
  const Image relit = (*renderer)->capture();
  (*renderer)->draw(view, hybrid_list);
  EXPECT_TRUE(compare_images(relit, (*renderer)->capture()).identical());
  EXPECT_GT(compare_images(before, relit).differing_pixels, 100u) << "the light did not change";
  // Picking: 100 pixels spread over the tree, against the CPU ray caster (faces as drawn:
  // the tree's leaves are two triangles back to back). Where they differ, the pixel's centre
  // lies on a border where either answer is right: two triangles that share a vertex or an
  // edge, or, where the ray meets nothing, the picked triangle's outline within 1/256 of a
  // pixel of the centre (the rasteriser snaps corners to 1/256 of a pixel: such a centre is
  // inside the triangle it draws, and a hair outside the triangle the ray meets).
  const RayCaster caster(*scene);
  const glm::mat4 inverse = glm::inverse(view.view_projection());
  std::vector<glm::ivec2> covered;  // pixels that show the tree
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x)
      if (!std::equal(relit.pixel(x, y), relit.pixel(x, y) + 3, relit.pixel(0, 0)))
        covered.push_back({x, y});
  ASSERT_GT(covered.size(), 500u);
  // How far the pixel centre (x, y) lies outside triangle t as the frame projects it, pixels.
  auto outside_px = [&](uint32_t t, int x, int y) {
    glm::vec2 w[3];
    for (int k = 0; k < 3; ++k) {
      const glm::vec4 c = view.view_projection() *
                          glm::vec4(scene->vertices[scene->indices[3 * t + k]].position, 1.0f);
      w[k] = {(c.x / c.w * 0.5f + 0.5f) * float(view.width),
              (0.5f - c.y / c.w * 0.5f) * float(view.height)};
    }
    const glm::vec2 p(float(x) + 0.5f, float(y) + 0.5f);
    const float area =
        (w[1].x - w[0].x) * (w[2].y - w[0].y) - (w[1].y - w[0].y) * (w[2].x - w[0].x);
    float outside = 0.0f;
    for (int k = 0; k < 3; ++k) {
      const glm::vec2 a = w[k], b = w[(k + 1) % 3];
      const float edge = ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)) *
                         (area > 0 ? 1.0f : -1.0f) / glm::length(b - a);
      outside = std::max(outside, -edge);
    }
    return outside;
  };
  int agree = 0, shared = 0, outline = 0, other = 0, sky = 0;
  for (int k = 0; k < 100; ++k) {
    const int x = covered[k * covered.size() / 100].x, y = covered[k * covered.size() / 100].y;
    const std::optional<uint32_t> picked = (*renderer)->pick(*scene, view, hybrid_list, x, y);
    const glm::vec2 ndc((float(x) + 0.5f) / float(view.width) * 2.0f - 1.0f,
                        1.0f - (float(y) + 0.5f) / float(view.height) * 2.0f);
    const glm::vec4 a = inverse * glm::vec4(ndc, 1.0f, 1.0f), b = inverse * glm::vec4(ndc, 0.5f, 1.0f);
    const glm::vec3 origin = glm::vec3(a) / a.w;
    const auto hit = caster.cast(origin, glm::normalize(glm::vec3(b) / b.w - origin), 1e6f,
                                 RayCaster::Faces::as_drawn);
    if (!picked && !hit) {
      ++sky;
    } else if (picked && hit && *picked == hit->triangle) {
      ++agree;
    } else if (picked && hit) {
      auto corners = [&](uint32_t t) {
        return std::vector<glm::vec3>{scene->vertices[scene->indices[3 * t]].position,
                                      scene->vertices[scene->indices[3 * t + 1]].position,
                                      scene->vertices[scene->indices[3 * t + 2]].position};
      };
      const auto p = corners(*picked), q = corners(hit->triangle);
      const bool touch = std::any_of(p.begin(), p.end(), [&](const glm::vec3& v) {
        return std::any_of(q.begin(), q.end(),
                           [&](const glm::vec3& w) { return glm::length(v - w) < 1e-5f; });
      });
      ++(touch ? shared : other);
    } else if (picked && !hit && outside_px(*picked, x, y) < 1.0f / 256.0f) {
      ++outline;
    } else {
      ++other;
    }
  }
  std::printf(
      "picking, 100 pixels: %d agree with the ray cast, %d on a shared vertex or edge, "
      "%d on the picked triangle's outline, %d sky, %d otherwise\n",
      agree, shared, outline, sky, other);
  EXPECT_GE(agree, 90);
  EXPECT_LE(sky, 2);
  EXPECT_EQ(other, 0);
}

TEST(HybridCli, ABakeGoesOnFromItsViewpointsReportsTable3AndNamesDamage) {
  test::TempDir dir;
  const std::string cwd = dir.path().string();
  using test::run_farfield;
  ASSERT_EQ(run_farfield("generate tree -q --out t.ffscene", cwd).exit_status, 0);
  const std::string args =
      "bake t.ffscene -t hybrid --set hybrid.d_theta=45 --set hybrid.d_phi=45 "
      "--set hybrid.width=64 --set hybrid.height=48 --out t.ffpack";
  auto r = run_farfield(args, cwd);
  ASSERT_EQ(r.exit_status, 0) << r.output;
  {
    auto store = Store::open(dir.file("t.ffpack"), Store::Mode::kReadWrite);
    ASSERT_TRUE(store);
    ASSERT_TRUE(store->erase("hybrid/view/00005/"));  // as if killed before its transaction
  }
  r = run_farfield(args, cwd);
  ASSERT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("hybrid: 31 of 32 viewpoints already kept"), std::string::npos)
      << r.output;
  r = run_farfield("info t.ffpack", cwd);
  EXPECT_NE(r.output.find("hybrid: 32 viewpoints"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("run-length ratio"), std::string::npos) << r.output;
  {
    auto store = Store::open(dir.file("t.ffpack"), Store::Mode::kReadWrite);
    ASSERT_TRUE(store);
    const std::vector<std::byte> junk(20, std::byte{1});
    ASSERT_TRUE(store->put("hybrid/view/00008/set", junk, Codec::kNone));  // frame 0 meets it
  }
  ASSERT_EQ(run_farfield("path t.ffscene --kind orbit --frames 3 --out o.json", cwd).exit_status,
            0);
  r = run_farfield(
      "bench t.ffscene --store t.ffpack --path o.json -t hybrid --width 64 --height 48 "
      "--no-plot -q --out b",
      cwd);
  EXPECT_NE(r.exit_status, 0);
  EXPECT_NE(r.output.find("hybrid: viewpoint 8"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace farfield
