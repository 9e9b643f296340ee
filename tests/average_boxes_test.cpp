// Average-colour boxes (paper 001, Sec. 4.1.2 and 5.1) from hand-made side images: the mean
// colour weighed by coverage, the share covered and its centre; the quads drawn (front sides
// only, of the covered area, within their side); the pack that keeps them.
#include "farfield/techniques/clusters/average_boxes.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

constexpr int kPage = 16;

// A 2 x 1 x 3 m box whose +Y side (8 x 12 texels at (0, 0)) shows red on its left half of
// full alpha and nothing elsewhere, and whose +X side (12 x 4 at (0, 12)) is grey, half of it
// at alpha 128; the other sides show nothing.
struct HandMade {
  TexturedBox box;
  std::vector<uint8_t> page = std::vector<uint8_t>(kPage * kPage * 4, 0);
};
HandMade hand_made() {
  HandMade h;
  h.box.bounds = {{0, 0, 0}, {2, 1, 3}};
  h.box.sides[2] = {0, 0, 8, 12};
  h.box.sides[0] = {0, 12, 12, 4};
  auto texel = [&](int x, int y) { return &h.page[(size_t(y) * kPage + size_t(x)) * 4]; };
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 4; ++x) {
      uint8_t* t = texel(x, y);
      t[0] = 200, t[1] = 10, t[2] = 20, t[3] = 255;
    }
  for (int y = 12; y < 16; ++y)
    for (int x = 0; x < 12; ++x) {
      uint8_t* t = texel(x, y);
      t[0] = t[1] = t[2] = x < 6 ? 100 : 200;
      t[3] = x < 6 ? 255 : 128;
    }
  return h;
}

TEST(AverageBoxes, ColourCoverageAndCentreFromTheSideImages) {
  const HandMade h = hand_made();
  const AverageBox a = average_box(h.box, h.page, kPage);
  const AverageSide& top = a.sides[2];
  EXPECT_EQ(top.r, 200);
  EXPECT_EQ(top.g, 10);
  EXPECT_EQ(top.b, 20);
  EXPECT_EQ(top.coverage, 128);  // half the side
  EXPECT_EQ(top.u, -64);         // the covered half's centre: half way to the left edge
  EXPECT_EQ(top.v, 0);
  const AverageSide& x = a.sides[0];
  // Grey 100 at alpha 255 and 200 at alpha 128: (100 * 255 + 200 * 128) / 383.
  EXPECT_EQ(x.r, 133);
  EXPECT_EQ(x.g, 133);
  EXPECT_EQ(x.coverage, 192);  // (255 + 128) / 2
  EXPECT_LT(x.u, 0);           // the heavier left half
  EXPECT_EQ(x.v, 0);
  for (int side : {1, 3, 4, 5}) EXPECT_EQ(a.sides[side].coverage, 0) << side;
}

// Seen from above, only the +Y side is drawn: a quad of half the side's area, the side's
// proportions, its centre moved left by a quarter of the side, its colour the average's.
TEST(AverageBoxes, DrawnAsTheCoveredShareOfTheFrontSides) {
  const HandMade h = hand_made();
  const AverageBox a = average_box(h.box, h.page, kPage);
  TexturedMesh mesh;
  append_average_box(h.box, a, {1.0f, 50.0f, 1.5f}, mesh);
  ASSERT_EQ(mesh.vertices.size(), 4u);
  ASSERT_EQ(mesh.indices.size(), 6u);
  const glm::vec3 p0 = mesh.vertices[0].position, p1 = mesh.vertices[1].position,
                  p2 = mesh.vertices[2].position;
  const glm::vec3 normal = glm::cross(p1 - p0, p2 - p0);
  EXPECT_GT(normal.y, 0.0f);  // counter-clockwise from above
  const float area = glm::length(normal);
  EXPECT_NEAR(area, 0.5f * 2.0f * 3.0f, 0.02f);
  glm::vec3 centre(0.0f);
  for (const TexturedVertex& v : mesh.vertices) {
    EXPECT_FLOAT_EQ(v.position.y, 1.0f);
    EXPECT_GE(v.position.x, -1e-5f);
    EXPECT_LE(v.position.x, 2.0f + 1e-5f);
    EXPECT_GE(v.position.z, -1e-5f);
    EXPECT_LE(v.position.z, 3.0f + 1e-5f);
    EXPECT_EQ(v.color, 0xff14'0ac8u);  // 200, 10, 20, opaque
    centre += 0.25f * v.position;
  }
  // The +Y side's right is +x: the centre moved left is at smaller x, held within the side.
  EXPECT_LT(centre.x, 1.0f);
  EXPECT_NEAR(centre.z, 1.5f, 1e-4f);
  // From the +X side and above: both sides that face the eye.
  mesh = {};
  append_average_box(h.box, a, {40.0f, 50.0f, 1.5f}, mesh);
  EXPECT_EQ(mesh.vertices.size(), 8u);
  // From below and -X: nothing it shows faces there.
  mesh = {};
  append_average_box(h.box, a, {-40.0f, -50.0f, 1.5f}, mesh);
  EXPECT_TRUE(mesh.vertices.empty());
}

TEST(AverageBoxes, KeptInAPackAndRefusedWhenNotOnePerBox) {
  const HandMade h = hand_made();
  BoxSet set;
  set.boxes = {h.box, h.box};
  const std::vector<AverageBox> averages = {average_box(h.box, h.page, kPage), AverageBox{}};
  test::TempDir dir;
  auto store = Store::open(dir.file("a.ffpack"), Store::Mode::kReadWrite);
  ASSERT_TRUE(store);
  auto none = load_average_boxes(*store, set);
  ASSERT_TRUE(none) << none.error().message;
  EXPECT_TRUE(none->empty());
  ASSERT_TRUE(save_average_boxes(averages, *store));
  auto back = load_average_boxes(*store, set);
  ASSERT_TRUE(back) << back.error().message;
  ASSERT_EQ(back->size(), 2u);
  EXPECT_EQ(std::memcmp(back->data(), averages.data(), 2 * sizeof(AverageBox)), 0);
  set.boxes.push_back(h.box);
  auto refused = load_average_boxes(*store, set);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("clusters/box_averages"), std::string::npos);
  EXPECT_NE(refused.error().message.find("2 for 3"), std::string::npos);
  // Saving the boxes again erases their averages with them.
  ASSERT_TRUE(save_box_set(BoxSet{}, *store));
  auto gone = load_average_boxes(*store, set);
  ASSERT_TRUE(gone);
  EXPECT_TRUE(gone->empty());
}

}  // namespace
}  // namespace farfield
