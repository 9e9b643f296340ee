// The occlusion map any technique can cull with, and the occluder boxes inside objects: what
// the map calls hidden must lie behind an occluder along every line of sight, a box found
// inside an object must meet none of its triangles.
#include "farfield/spatial/occlusion_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>
#include <random>

#include "farfield/core/progress.hpp"
#include "farfield/scene/city_generator.hpp"
#include "farfield/spatial/occluders.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

View test_view() {
  View v;
  v.width = 160;
  v.height = 120;
  v.pose = {{0.0f, 1.5f, 0.0f}, 0.0f, 0.0f};  // looking along +X
  return v;
}

Bounds3 box_at(const glm::vec3& centre, const glm::vec3& size) {
  return Bounds3{centre - 0.5f * size, centre + 0.5f * size};
}

// Where a ray from `origin` along `dir` enters a box, along the ray; INFINITY where it misses.
float enters_at(const glm::vec3& origin, const glm::vec3& dir, const Bounds3& box) {
  float t0 = 0.0f, t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(dir[a]) < 1e-9f) {
      if (origin[a] < box.min[a] || origin[a] > box.max[a]) return INFINITY;
      continue;
    }
    float ta = (box.min[a] - origin[a]) / dir[a], tb = (box.max[a] - origin[a]) / dir[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 ? t0 : INFINITY;
}

// A random cuboid around the origin: 1 to 16 m a side, within 40 m across and 10 m up or down.
Bounds3 random_cuboid(std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const glm::vec3 c(-40.0f + 80.0f * unit(rng), -10.0f + 20.0f * unit(rng),
                    -40.0f + 80.0f * unit(rng));
  const glm::vec3 s(1.0f + 15.0f * unit(rng), 1.0f + 15.0f * unit(rng), 1.0f + 15.0f * unit(rng));
  return box_at(c, s);
}

// `count` random cuboids around the origin (those holding the eye left out), added to `map`.
std::vector<Bounds3> add_random_occluders(std::mt19937& rng, int count, const View& view,
                                          OcclusionMap& map) {
  std::vector<Bounds3> occluders;
  for (int k = 0; k < count; ++k) {
    const Bounds3 b = random_cuboid(rng);
    if (b.contains(view.pose.position)) continue;
    occluders.push_back(b);
    map.add_box(b);
  }
  return occluders;
}

TEST(OcclusionMap, AWallHidesWhatIsBehindItOnly) {
  const View view = test_view();
  OcclusionMap map;
  map.reset(view, 4);
  EXPECT_EQ(map.width(), 40);
  EXPECT_EQ(map.height(), 30);
  EXPECT_EQ(map.marked(), 0u);
  EXPECT_FALSE(map.hidden(box_at({50.0f, 1.5f, 0.0f}, glm::vec3(1.0f))));  // nothing marked

  map.add_box(box_at({20.0f, 1.5f, 0.0f}, {2.0f, 10.0f, 10.0f}));  // 10 m across at 19 m
  // 5 m either way at 19 m is 5.3 texels of 4 pixels each way: ~10 x 10 texels wholly covered.
  EXPECT_GE(map.marked(), 81u);
  EXPECT_LE(map.marked(), 121u);
  EXPECT_TRUE(map.hidden(box_at({50.0f, 1.5f, 0.0f}, glm::vec3(4.0f))));       // behind, smaller
  EXPECT_FALSE(map.hidden(box_at({10.0f, 1.5f, 0.0f}, glm::vec3(1.0f))));      // in front
  EXPECT_FALSE(map.hidden(box_at({19.0f, 1.5f, 0.0f}, glm::vec3(0.5f))));      // through its face
  EXPECT_TRUE(map.hidden(box_at({20.5f, 1.5f, 0.0f}, glm::vec3(0.5f))));       // behind its face
  EXPECT_FALSE(map.hidden(box_at({50.0f, 1.5f, 0.0f}, {1.0f, 1.0f, 60.0f})));  // wider
  // Crossing the near plane: never hidden.
  EXPECT_FALSE(map.hidden(box_at({0.0f, 1.5f, 0.0f}, glm::vec3(0.5f))));
}

TEST(OcclusionMap, AnOccluderAroundTheNearPlaneStillMarks) {
  // A wall the eye stands just in front of, larger than the view: clipped at the near plane.
  const View view = test_view();
  OcclusionMap map;
  map.reset(view, 4);
  map.add_box(box_at({0.5f, 1.5f, 0.0f}, {0.5f, 400.0f, 400.0f}));
  EXPECT_EQ(map.marked(), size_t(map.width()) * size_t(map.height()));
  EXPECT_TRUE(map.hidden(box_at({30.0f, 0.0f, 0.0f}, glm::vec3(10.0f))));
}

// Random occluders and boxes around random views: a box called hidden has, along the ray to
// each of many points on it that reach the screen, an occluder entered before the point.
TEST(OcclusionMap, WhatItHidesIsBehindAnOccluderAlongEverySightLine) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int hidden = 0, checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    View view = test_view();
    view.pose.yaw_deg = 360.0f * unit(rng);
    view.pose.pitch_deg = -30.0f + 60.0f * unit(rng);
    OcclusionMap map;
    map.reset(view, 2 + trial % 4);  // texel_px 1 samples pixel centres: the next test
    const std::vector<Bounds3> occluders = add_random_occluders(rng, 12, view, map);
    const glm::mat4 vp = view.view_projection();
    for (int q = 0; q < 300; ++q) {
      const glm::vec3 c(-60.0f + 120.0f * unit(rng), -20.0f + 40.0f * unit(rng),
                        -60.0f + 120.0f * unit(rng));
      const Bounds3 box = box_at(c, glm::vec3(0.5f + 4.0f * unit(rng)));
      if (!map.hidden(box)) continue;
      ++hidden;
      for (int p = 0; p < 64; ++p) {
        const glm::vec3 point =
            glm::mix(box.min, box.max, glm::vec3(unit(rng), unit(rng), unit(rng)));
        const glm::vec4 clip = vp * glm::vec4(point, 1.0f);
        if (clip.w <= 0.0f || std::abs(clip.x) > clip.w || std::abs(clip.y) > clip.w) continue;
        const glm::vec3 dir = point - view.pose.position;
        float first = INFINITY;
        for (const Bounds3& o : occluders)
          first = std::min(first, enters_at(view.pose.position, dir, o));
        ++checked;
        ASSERT_LT(first, 1.0f) << "trial " << trial << " box " << q;
      }
    }
  }
  EXPECT_GT(hidden, 100);  // the test tests something
  EXPECT_GT(checked, 1000);
}

// The map marks a texel exactly where one face of an occluder covers it wholly, with the
// face's farthest depth over it: checked against rays through every texel corner (the face a
// ray enters a box by, and its view depth there), up to rounding at the faces' edges.
TEST(OcclusionMap, MarksTheTexelsAFaceCoversWhollyAtItsFarthestDepth) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  size_t agreed = 0, disagreed = 0, covered = 0;
  for (int trial = 0; trial < 40; ++trial) {
    View view = test_view();
    view.pose.yaw_deg = 360.0f * unit(rng);
    view.pose.pitch_deg = -30.0f + 60.0f * unit(rng);
    const int texel_px = 2 + trial % 4;
    OcclusionMap map;
    map.reset(view, texel_px);
    const std::vector<Bounds3> occluders = add_random_occluders(rng, 6, view, map);
    const glm::mat4 to_view = view.view_matrix(), to_world = glm::inverse(to_view);
    const glm::mat4 projection = view.projection_matrix();
    const float texels_x = float(view.width) / float(texel_px),
                texels_y = float(view.height) / float(texel_px);
    const glm::vec3 eye = view.pose.position;
    // Per lattice corner and occluder: the face (axis * 2 + side) its ray enters by and the
    // view depth there; -1 where it misses.
    const int cols = map.width() + 1, rows = map.height() + 1;
    std::vector<int> face(size_t(cols) * rows * occluders.size(), -1);
    std::vector<float> depth(face.size(), 0.0f);
    for (int y = 0; y < rows; ++y)
      for (int x = 0; x < cols; ++x) {
        const glm::vec3 ray_view((2.0f * float(x) / texels_x - 1.0f) / projection[0][0],
                                 (2.0f * float(y) / texels_y - 1.0f) / projection[1][1], -1.0f);
        const glm::vec3 dir = glm::vec3(to_world * glm::vec4(ray_view, 0.0f));
        for (size_t o = 0; o < occluders.size(); ++o) {
          const float t = enters_at(eye, dir, occluders[o]);
          if (!std::isfinite(t) || t <= view.near_m) continue;
          const glm::vec3 p = eye + t * dir;
          int best = -1;
          float nearest = INFINITY;
          for (int a = 0; a < 3; ++a)
            for (int side = 0; side < 2; ++side) {
              const float d = std::abs(p[a] - (side ? occluders[o].max[a] : occluders[o].min[a]));
              if (d < nearest) nearest = d, best = a * 2 + side;
            }
          const size_t at = (size_t(y) * cols + x) * occluders.size() + o;
          face[at] = best;
          depth[at] = -(to_view * glm::vec4(p, 1.0f)).z;
        }
      }
    for (int y = 0; y < map.height(); ++y)
      for (int x = 0; x < map.width(); ++x) {
        float expected = INFINITY;
        for (size_t o = 0; o < occluders.size(); ++o) {
          const size_t corners[4] = {(size_t(y) * cols + x) * occluders.size() + o,
                                     (size_t(y) * cols + x + 1) * occluders.size() + o,
                                     (size_t(y + 1) * cols + x) * occluders.size() + o,
                                     (size_t(y + 1) * cols + x + 1) * occluders.size() + o};
          const int f = face[corners[0]];
          if (f < 0) continue;
          float farthest = 0.0f;
          bool whole = true;
          for (size_t c : corners) {
            whole = whole && face[c] == f;
            farthest = std::max(farthest, depth[c]);
          }
          if (whole) expected = std::min(expected, farthest);
        }
        const float got = map.depth_at(x, y);
        covered += std::isfinite(expected) ? 1 : 0;
        const bool same = std::isinf(expected)
                              ? std::isinf(got)
                              : std::abs(got - expected) <= 1e-3f * expected;
        (same ? agreed : disagreed) += 1;
      }
  }
  EXPECT_GT(covered, 4000u);  // the test tests something
  // Rounding decides texels with a corner on a face's edge: a few in a thousand at most.
  EXPECT_LE(disagreed, agreed / 500) << disagreed << " of " << agreed + disagreed << ", " << covered << " covered";
}

// At one pixel a texel the map samples pixel centres, and objects' own triangles occlude: a
// box called hidden has, along the ray through every pixel centre that meets it, an occluder
// triangle met first (both sides of each cuboid drawn: the test's rays meet any face).
TEST(OcclusionMap, MeshOccludersHideOnlyWhatEveryPixelCentreSeesBehindThem) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int hidden = 0, checked = 0;
  for (int trial = 0; trial < 30; ++trial) {
    View view = test_view();
    view.pose.yaw_deg = 360.0f * unit(rng);
    view.pose.pitch_deg = -30.0f + 60.0f * unit(rng);
    Scene scene;
    SceneBuilder b(scene);
    const uint32_t material = b.add_material({});
    std::vector<Bounds3> occluders;
    for (int k = 0; k < 12; ++k) {
      const Bounds3 box = random_cuboid(rng);
      if (box.contains(view.pose.position)) continue;
      b.begin_object("cuboid", ObjectKind::mesh, material);
      test::add_cuboid(b, box.min, box.max);
      b.end_object();
      occluders.push_back(box);
    }
    OcclusionMap map;
    map.reset(view, 1);
    for (uint32_t o = 0; o < scene.objects.size(); ++o) map.add_mesh(scene, o, true);
    map.finish();
    const glm::mat4 inverse = glm::inverse(view.view_projection());
    for (int q = 0; q < 300; ++q) {
      const glm::vec3 c(-60.0f + 120.0f * unit(rng), -20.0f + 40.0f * unit(rng),
                        -60.0f + 120.0f * unit(rng));
      const Bounds3 box = box_at(c, glm::vec3(0.5f + 4.0f * unit(rng)));
      if (!map.hidden(box)) continue;
      ++hidden;
      // Pixel centres within the box's screen rectangle (a hidden box is in front of the eye).
      glm::vec2 lo(INFINITY), hi(-INFINITY);
      for (int k = 0; k < 8; ++k) {
        const glm::vec4 clip =
            view.view_projection() * glm::vec4(k & 1 ? box.max.x : box.min.x,
                                               k & 2 ? box.max.y : box.min.y,
                                               k & 4 ? box.max.z : box.min.z, 1.0f);
        const glm::vec2 at((clip.x / clip.w + 1.0f) * 0.5f * float(view.width),
                           (clip.y / clip.w + 1.0f) * 0.5f * float(view.height));
        lo = glm::min(lo, at);
        hi = glm::max(hi, at);
      }
      lo = glm::max(lo, glm::vec2(0.0f));
      hi = glm::min(hi, glm::vec2(float(view.width), float(view.height)));
      for (int p = 0; p < 200; ++p) {
        const float px = std::floor(glm::mix(lo.x, hi.x, unit(rng))) + 0.5f;
        const float py = std::floor(glm::mix(lo.y, hi.y, unit(rng))) + 0.5f;
        const glm::vec4 far =
            inverse * glm::vec4(2.0f * px / float(view.width) - 1.0f,
                                2.0f * py / float(view.height) - 1.0f, 0.5f, 1.0f);
        const glm::vec3 dir = glm::normalize(glm::vec3(far) / far.w - view.pose.position);
        const float at = enters_at(view.pose.position, dir, box);
        if (!std::isfinite(at)) continue;
        float first = INFINITY;
        for (const Bounds3& o : occluders)
          first = std::min(first, enters_at(view.pose.position, dir, o));
        ++checked;
        ASSERT_LT(first, at) << "trial " << trial << " box " << q;
      }
    }
  }
  EXPECT_GT(hidden, 100);
  EXPECT_GT(checked, 5000);
}

TEST(Occluders, AClosedBoxHoldsABoxAndGlassNone) {
  const Scene scene = test::make_box_row(2);  // an opaque unit cube, then a glass one
  const std::optional<Bounds3> box = inscribed_box(scene, 0);
  ASSERT_TRUE(box);
  const Bounds3& b = scene.objects[0].bounds;
  EXPECT_GT(box->size().x, 0.9f * b.size().x);
  EXPECT_GE(box->min.x, b.min.x);
  EXPECT_LE(box->max.y, b.max.y);
  EXPECT_FALSE(inscribed_box(scene, 1));
}

TEST(Occluders, AnOpenTopHoldsNoBox) {
  // Four walls and a floor, open at the top: a ray upwards leaves without crossing.
  Scene scene;
  SceneBuilder b(scene);
  b.begin_object("tub", ObjectKind::mesh, b.add_material(Material{}));
  auto quad = [&](glm::vec3 o, glm::vec3 u, glm::vec3 v) {
    const glm::vec3 n = glm::normalize(glm::cross(u, v));
    const uint32_t base = b.vertex_count();
    b.add_vertex(o, n, 0xffffffffu);
    b.add_vertex(o + u, n, 0xffffffffu);
    b.add_vertex(o + u + v, n, 0xffffffffu);
    b.add_vertex(o + v, n, 0xffffffffu);
    b.add_triangle(base, base + 1, base + 2);
    b.add_triangle(base, base + 2, base + 3);
  };
  quad({0, 0, 0}, {0, 0, 4}, {4, 0, 0});  // floor
  quad({0, 0, 0}, {4, 0, 0}, {0, 4, 0});  // walls
  quad({4, 0, 0}, {0, 0, 4}, {0, 4, 0});
  quad({4, 0, 4}, {-4, 0, 0}, {0, 4, 0});
  quad({0, 0, 4}, {0, 0, -4}, {0, 4, 0});
  b.end_object();
  EXPECT_FALSE(inscribed_box(scene, 0));
}

// A generated city of blocks x blocks.
Scene city_of(uint32_t blocks, CityOptions o = {}) {
  o.blocks_x = o.blocks_z = blocks;
  Progress quiet(true);
  auto city = generate_city(o, quiet);
  EXPECT_TRUE(city);
  return city ? std::move(*city) : Scene{};
}

TEST(Occluders, TheCitysBuildingsHoldBoxesThatMeetNoTriangle) {
  const Scene scene = city_of(2);
  const Scene* city = &scene;
  int buildings = 0, found = 0;
  for (uint32_t i = 0; i < city->objects.size(); ++i) {
    const Object& object = city->objects[i];
    if (object.kind != ObjectKind::building) continue;
    ++buildings;
    const std::optional<Bounds3> box = inscribed_box(*city, i);
    if (!box) continue;
    ++found;
    // Inside the bounds, and no vertex of the object strictly inside the box.
    EXPECT_TRUE(object.bounds.contains(box->min) && object.bounds.contains(box->max));
    for (uint32_t v = 0; v < object.vertex_count; ++v) {
      const glm::vec3 p = city->vertices[object.first_vertex + v].position;
      const bool within =
          glm::all(glm::greaterThan(p, box->min)) && glm::all(glm::lessThan(p, box->max));
      ASSERT_FALSE(within) << city->object_name(object);
    }
  }
  ASSERT_GT(buildings, 20);
  // Glass buildings (15%) hold none; most of the rest do.
  EXPECT_GT(found, buildings / 2);
}

TEST(Occluders, AStreetViewMarksTheMapAndHidesTheCityBehind) {
  const CityOptions o;
  const Scene scene = city_of(3, o);
  const Scene* city = &scene;
  View view = test_view();
  // On the street between the first two rows of blocks, looking along it.
  view.pose = {
      {city->bounds.min.x + 2.0f, 1.7f, city->bounds.min.z + o.block_width + 0.5f * o.street_width},
      0.0f,
      0.0f};
  Occluders occluders(*city);
  OcclusionMap map;
  occluders.fill(map, view, Frustum(view));
  EXPECT_GT(map.occluders(), 0u);
  EXPECT_GT(map.marked(), size_t(map.width() * map.height()) / 10);
  EXPECT_GT(occluders.boxes_found(), 0u);
  int hidden = 0;
  for (const Object& object : city->objects) hidden += map.hidden(object.bounds);
  EXPECT_GT(hidden, 0);
}

TEST(Occluders, OneTheNearerOnesHideIsSkippedAndNotCounted) {
  // From the eye along +X: a wall, a box wholly behind it, and off to the side a farther box;
  // behind that one, a target that only it hides.
  Scene scene;
  SceneBuilder b(scene);
  const uint32_t opaque = b.add_material(Material{{0.8f, 0.2f, 0.1f, 1.0f}});
  auto cuboid = [&](const char* name, glm::vec3 lo, glm::vec3 hi) {
    b.begin_object(name, ObjectKind::building, opaque);
    test::add_cuboid(b, lo, hi);
    b.end_object();
  };
  cuboid("wall", {10, 0, -3}, {12, 6, 3});
  cuboid("behind", {20, 0, -2.5f}, {22, 3, 2.5f});
  cuboid("aside", {24, 0, 8}, {28, 6, 14});
  const Bounds3 target{{40, 2, 18}, {41, 3, 19}};
  const View view = test_view();
  const Frustum frustum(view);
  OcclusionMap map;
  Occluders one(scene, OccluderOptions{.per_frame = 1});
  one.fill(map, view, frustum);
  EXPECT_FALSE(map.hidden(target));  // the wall alone does not hide it
  Occluders two(scene, OccluderOptions{.per_frame = 2});
  two.fill(map, view, frustum);
  EXPECT_TRUE(map.hidden(scene.objects[1].bounds));
  EXPECT_EQ(map.occluders(), 2u);
  EXPECT_TRUE(map.hidden(target));  // "behind" skipped, "aside" taken as the second
}

}  // namespace
}  // namespace farfield
