// The software occlusion buffer the colorcube walk culls with: what it marks must be covered,
// what it calls hidden must be behind marks.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/spatial/occlusion_buffer.hpp"

namespace farfield {
namespace {

View small_view() {
  View v;
  v.width = 128;
  v.height = 96;
  v.pose = {{0.0f, 0.0f, 0.0f}, 0.0f, 0.0f};
  return v;
}

Bounds3 box_at(const glm::vec3& centre, const glm::vec3& size) {
  Bounds3 b;
  b.min = centre - 0.5f * size;
  b.max = centre + 0.5f * size;
  return b;
}

// A wall of 3 m x 3 m x 1 m boxes (the view looks along an axis), 3 x 3, facing the eye at `distance`, marked one by one.
void mark_wall(OcclusionBuffer& buffer, const View& view, float distance) {
  const glm::vec3 f = view.pose.forward(), r = view.pose.right(), u = view.pose.up();
  for (int by = -1; by <= 1; ++by)
    for (int bx = -1; bx <= 1; ++bx) {
      const Bounds3 box = box_at(f * distance + r * float(3 * bx) + u * float(3 * by),
                                 glm::abs(r) * 3.0f + glm::abs(u) * 3.0f + glm::abs(f));
      buffer.add_boxes(box, std::span(&box, 1));
    }
}

// The ray through a pixel's centre (row 0 at the bottom), as a unit direction.
glm::vec3 pixel_ray(const View& view, int x, int y) {
  const float t = std::tan(glm::radians(view.hfov_deg) * 0.5f);
  const float nx = (2.0f * (float(x) + 0.5f) / float(view.width) - 1.0f) * t;
  const float ny = (2.0f * (float(y) + 0.5f) / float(view.height) - 1.0f) * t / view.aspect();
  return glm::normalize(view.pose.forward() + nx * view.pose.right() + ny * view.pose.up());
}

// The view depth at which a ray from the eye enters a box, or INFINITY.
float enters_at(const View& view, const glm::vec3& dir, const Bounds3& box) {
  float t0 = 0.0f, t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const float o = view.pose.position[a], d = dir[a];
    if (std::abs(d) < 1e-9f) {
      if (o < box.min[a] || o > box.max[a]) return INFINITY;
      continue;
    }
    float ta = (box.min[a] - o) / d, tb = (box.max[a] - o) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 ? t0 * glm::dot(dir, view.pose.forward()) : INFINITY;
}

TEST(OcclusionBuffer, AWallHidesWhatIsBehindItOnly) {
  const View view = small_view();
  OcclusionBuffer buffer;
  buffer.reset(view);
  EXPECT_EQ(buffer.marked(), 0u);
  mark_wall(buffer, view, 60.0f);
  // The wall spans 9 m at 60 m: 9 / 60 * 64 = 9.6 pixels across, ~92 pixels; all but
  // those within the margin of the boxes' edges are marked.
  EXPECT_GT(buffer.marked(), 50u);
  EXPECT_LE(buffer.marked(), 100u);
  const glm::vec3 f = view.pose.forward(), r = view.pose.right();
  EXPECT_TRUE(buffer.hidden(box_at(f * 100.0f, glm::vec3(3.0f))));  // ~2 pixels, behind
  EXPECT_FALSE(buffer.hidden(box_at(f * 40.0f, glm::vec3(3.0f))));   // in front of the wall
  EXPECT_FALSE(buffer.hidden(box_at(f * 60.0f, glm::vec3(2.0f))));   // within the wall's layer
  EXPECT_FALSE(buffer.hidden(box_at(f * 100.0f + r * 20.0f, glm::vec3(3.0f))));  // beside it
  EXPECT_FALSE(buffer.hidden(box_at(f * 100.0f, glm::vec3(30.0f))));  // larger than it
  EXPECT_FALSE(buffer.hidden(box_at(glm::vec3(0.0f), glm::vec3(1.0f))));  // around the eye
  // A box too small to cover any pixel centre draws nothing, wherever it is.
  EXPECT_TRUE(buffer.hidden(box_at(f * 40.0f + glm::vec3(0.0f, 0.0f, 0.0f), glm::vec3(0.01f))));
  // A new frame forgets the wall.
  buffer.reset(view);
  EXPECT_EQ(buffer.marked(), 0u);
  EXPECT_FALSE(buffer.hidden(box_at(f * 100.0f, glm::vec3(3.0f))));
}

TEST(OcclusionBuffer, MarksOnlyPixelsItsBoxesCoverAndHidesOnlyBehindThem) {
  // Random clusters of small boxes; every marked pixel's ray must enter a box no farther than
  // the mark, and every box called hidden must be behind the marks on each ray that meets it.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), far(20.0f, 120.0f);
  View view = small_view();
  view.pose = {{3.0f, 2.0f, -1.0f}, 30.0f, -5.0f};
  OcclusionBuffer buffer;
  buffer.reset(view);
  std::vector<Bounds3> boxes;
  for (int cluster = 0; cluster < 60; ++cluster) {
    const float d = far(rng);
    const glm::vec3 centre = view.pose.position + view.pose.forward() * d +
                             view.pose.right() * unit(rng) * 0.8f * d +
                             view.pose.up() * unit(rng) * 0.6f * d;
    const glm::vec3 size = glm::vec3(0.02f * d * (1.0f + 0.5f * unit(rng)));
    std::vector<Bounds3> cluster_boxes;
    Bounds3 region;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 c = centre + size * glm::vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
      cluster_boxes.push_back(box_at(c, size * (k == 7 ? glm::vec3(1.0f, 0.5f, 2.0f) : glm::vec3(1.0f))));
      region.expand(cluster_boxes.back());
    }
    buffer.add_boxes(region, cluster_boxes);
    boxes.insert(boxes.end(), cluster_boxes.begin(), cluster_boxes.end());
  }
  ASSERT_GT(buffer.marked(), 100u);
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const float mark = buffer.depth_at(x, y);
      if (mark == INFINITY) continue;
      const glm::vec3 dir = pixel_ray(view, x, y);
      float nearest = INFINITY;
      for (const Bounds3& b : boxes) nearest = std::min(nearest, enters_at(view, dir, b));
      ASSERT_LE(nearest, mark * 1.0001f) << "pixel " << x << ", " << y << " marked without a box";
    }
  int hidden = 0;
  for (int k = 0; k < 2000; ++k) {
    const float d = far(rng) * 1.5f;
    const Bounds3 box = box_at(view.pose.position + view.pose.forward() * d +
                                   view.pose.right() * unit(rng) * 0.8f * d +
                                   view.pose.up() * unit(rng) * 0.6f * d,
                               glm::vec3(0.01f * d));
    if (!buffer.hidden(box)) continue;
    ++hidden;
    for (int y = 0; y < view.height; ++y)
      for (int x = 0; x < view.width; ++x) {
        const float enters = enters_at(view, pixel_ray(view, x, y), box);
        if (enters == INFINITY) continue;
        ASSERT_LT(buffer.depth_at(x, y), enters) << "a hidden box shows at " << x << ", " << y;
      }
  }
  EXPECT_GT(hidden, 0);
}

}  // namespace
}  // namespace farfield
