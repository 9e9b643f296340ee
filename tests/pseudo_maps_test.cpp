// Pseudo-texture maps (paper 001, Sec. 5.1): images shrunk by an alpha-weighted Gaussian
// until small enough, and the quads a side becomes (one per texel covered at least half,
// tiling the side).
#include "farfield/techniques/clusters/pseudo_maps.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

namespace farfield {
namespace {

constexpr uint32_t kRed = 0xff0000c8u;  // 200, 0, 0, opaque

TEST(PseudoMaps, ShrunkByHalvesKeepingColourAndCoverage) {
  // 16 x 8: the left half red, the right half empty.
  std::vector<uint32_t> image(16 * 8, 0);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) image[size_t(y) * 16 + size_t(x)] = kRed;
  int w = 16, h = 8;
  const std::vector<uint32_t> small = shrink_image(image, w, h, 4);
  EXPECT_EQ(w, 4);
  EXPECT_EQ(h, 4);
  ASSERT_EQ(small.size(), 16u);
  for (int y = 0; y < 4; ++y) {
    EXPECT_EQ(small[size_t(y) * 4 + 0], kRed) << y;  // wholly covered: the colour itself
    EXPECT_EQ(small[size_t(y) * 4 + 1], kRed) << y;
    EXPECT_EQ(small[size_t(y) * 4 + 3] >> 24, 0u) << y;  // wholly empty
    const uint32_t edge = small[size_t(y) * 4 + 2];      // the edge: partly covered, still red
    // The first halving leaves a texel a quarter covered beside the full ones; the second
    // weighs a full, that quarter and an empty one 1, 2, 1: 3/8 of 255.
    EXPECT_EQ(edge >> 24, 96u);
    EXPECT_EQ(edge & 0xffffffu, kRed & 0xffffffu);
  }
  // Already small enough: unchanged.
  int sw = 3, sh = 2;
  const std::vector<uint32_t> same(6, kRed);
  EXPECT_EQ(shrink_image(same, sw, sh, 4), same);
  EXPECT_EQ(sw, 3);
}

// A 2 x 1 x 3 m box whose top side's image (8 x 12 texels) is all red: shrunk to 4 x 3 at 4
// texels a side, seen from above, twelve quads tiling the 2 x 3 m top.
TEST(PseudoMaps, ASideIsAQuadPerCoveredTexelTilingIt) {
  BoxSet set;
  set.page_px = 16;
  set.page_count = 1;
  set.pages.assign(1, std::vector<uint8_t>(16 * 16 * 4, 0));
  TexturedBox box;
  box.bounds = {{0, 0, 0}, {2, 1, 3}};
  box.sides[2] = {0, 0, 8, 12};
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 8; ++x) {
      uint8_t* t = &set.pages[0][(size_t(y) * 16 + size_t(x)) * 4];
      t[0] = 200, t[3] = 255;
    }
  set.boxes = {box};
  const PseudoMaps maps = pseudo_maps(set, 4);
  ASSERT_EQ(maps.first.size(), 1u);
  EXPECT_EQ(maps.sizes[0][4], 4);
  EXPECT_EQ(maps.sizes[0][5], 3);
  TexturedMesh mesh;
  append_pseudo_box(set, maps, 0, {1, 50, 1.5f}, mesh);
  ASSERT_EQ(mesh.indices.size(), 12u * 6u);
  float area = 0;
  for (size_t q = 0; q < mesh.indices.size(); q += 6) {
    const glm::vec3 a = mesh.vertices[mesh.indices[q]].position,
                    b = mesh.vertices[mesh.indices[q + 1]].position,
                    c = mesh.vertices[mesh.indices[q + 2]].position;
    const glm::vec3 n = glm::cross(b - a, c - a);
    EXPECT_GT(n.y, 0.0f);  // facing up, counter-clockwise from above
    area += glm::length(n);
  }
  EXPECT_NEAR(area, 6.0f, 1e-3f);
  for (const TexturedVertex& v : mesh.vertices) {
    EXPECT_FLOAT_EQ(v.position.y, 1.0f);
    EXPECT_EQ(v.color, kRed);
  }
  // From below, nothing faces the eye.
  mesh = {};
  append_pseudo_box(set, maps, 0, {1, -50, 1.5f}, mesh);
  EXPECT_TRUE(mesh.vertices.empty());
}

}  // namespace
}  // namespace farfield
