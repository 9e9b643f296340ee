// The boxes' atlas in tiles (box_atlas.hpp): every box packed again into one tile of its
// page, its sides apart and inside the tile (a box too large for the usual tile in a larger
// one), the pixels cut from the page unchanged, the mesh's texture coordinates on the tile;
// and the upload cost learnt from frames (upload_cost.hpp). Without GL.
#include "farfield/techniques/clusters/box_atlas.hpp"

#include <gtest/gtest.h>

#include <random>

#include "farfield/techniques/clusters/upload_cost.hpp"

namespace farfield {
namespace {

// Boxes with sides of random sizes on two pages of 2048 (the sides' page positions do not
// matter to the tiling: each is its own colour on the page), and one box of three 256^2 sides.
struct Synthetic {
  BoxSet set;
  std::vector<std::vector<uint8_t>> colours;  // per box and side: the byte its texels hold
};
Synthetic synthetic_boxes() {
  Synthetic s;
  BoxSet& set = s.set;
  set.page_px = 2048;
  set.page_count = 2;
  set.pages.assign(2, std::vector<uint8_t>(size_t(2048) * 2048 * 4, 0));
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> size(4, 64), coin(0, 3);
  int x = 0, y = 0, row = 0;  // where the next side goes on its page
  uint32_t page = 0;
  for (uint32_t b = 0; b < 400; ++b) {
    TexturedBox box;
    box.bounds = {{float(b), 0, 0}, {float(b) + 1, 1, 1}};
    box.page = b < 200 ? 0 : 1;
    if (box.page != page) x = y = row = 0, page = box.page;
    std::vector<uint8_t> colours(6, 0);
    for (int side = 0; side < 6; ++side) {
      if (coin(rng) == 0) continue;  // not drawn
      const bool big = b == 123 && side < 3;
      const int w = big ? 256 : size(rng), h = big ? 256 : size(rng);
      if (x + w > 2048) x = 0, y += row, row = 0;
      EXPECT_LE(y + h, 2048) << "the synthetic page overflows";
      box.sides[side] = {uint16_t(x), uint16_t(y), uint16_t(w), uint16_t(h)};
      colours[side] = uint8_t(1 + (b * 6 + side) % 251);
      for (int yy = y; yy < y + h; ++yy)
        std::fill_n(&set.pages[page][(size_t(yy) * 2048 + size_t(x)) * 4], size_t(w) * 4,
                    colours[side]);
      x += w;
      row = std::max(row, h);
    }
    set.boxes.push_back(box);
    s.colours.push_back(colours);
  }
  return s;
}

TEST(BoxTiling, EveryBoxInOneTileOfItsPageItsSidesApartAndInside) {
  const Synthetic s = synthetic_boxes();
  const BoxTiling t = tile_boxes(s.set, 512);
  ASSERT_EQ(t.tiles.boxes.size(), s.set.boxes.size());
  ASSERT_EQ(t.tile_px.size(), t.page_of_tile.size());
  ASSERT_EQ(t.tile_first.size(), t.page_of_tile.size() + 1);
  EXPECT_EQ(t.tiles.page_count, t.page_of_tile.size());
  std::vector<std::vector<uint8_t>> taken;
  for (int px : t.tile_px) taken.emplace_back(size_t(px) * size_t(px), 0);
  std::vector<int> listed(s.set.boxes.size(), 0);
  for (uint32_t tile = 0; tile < t.page_of_tile.size(); ++tile)
    for (uint32_t b : t.boxes_of(tile)) {
      ++listed[b];
      EXPECT_EQ(t.tiles.boxes[b].page, tile);
      EXPECT_EQ(t.page_of_tile[tile], s.set.boxes[b].page) << "box " << b;
    }
  for (uint32_t b = 0; b < s.set.boxes.size(); ++b) {
    EXPECT_EQ(listed[b], 1) << "box " << b;
    const TexturedBox& box = t.tiles.boxes[b];
    const int px = t.tile_px[box.page];
    // The usual tile unless the box's sides cannot sit in one.
    EXPECT_EQ(px, b == 123 ? 1024 : 512) << "box " << b;
    for (int side = 0; side < 6; ++side) {
      const BoxSide& to = box.sides[side];
      EXPECT_EQ(to.w, s.set.boxes[b].sides[side].w);
      EXPECT_EQ(to.h, s.set.boxes[b].sides[side].h);
      if (to.w == 0) continue;
      ASSERT_LE(to.x + to.w, px);
      ASSERT_LE(to.y + to.h, px);
      for (int y = to.y; y < std::min(to.y + to.h + kBoxGutterPx, px); ++y)
        for (int x = to.x; x < std::min(to.x + to.w + kBoxGutterPx, px); ++x) {
          uint8_t& texel = taken[box.page][size_t(y) * size_t(px) + size_t(x)];
          ASSERT_EQ(texel, 0) << "tile " << box.page << " texel " << x << ", " << y;
          texel = 1;
        }
    }
  }
  // Neighbours together: the 400 boxes (about 1,200 texels a side) in a handful of tiles.
  EXPECT_LE(t.page_of_tile.size(), 20u);
}

TEST(BoxTiling, ATileHoldsItsBoxesPixelsAsTheirPageAndTheMeshPointsAtThem) {
  const Synthetic s = synthetic_boxes();
  const BoxTiling t = tile_boxes(s.set, 512);
  for (uint32_t tile = 0; tile < t.page_of_tile.size(); ++tile) {
    const int px = t.tile_px[tile];
    const std::vector<uint8_t> pixels = cut_tile(s.set, t, tile, s.set.pages[t.page_of_tile[tile]]);
    ASSERT_EQ(pixels.size(), size_t(px) * size_t(px) * 4);
    uint64_t drawn = 0, coloured = 0;
    for (uint32_t b : t.boxes_of(tile))
      for (int side = 0; side < 6; ++side) {
        const BoxSide& to = t.tiles.boxes[b].sides[side];
        drawn += uint64_t(to.w) * to.h * 4;
        for (int y = to.y; y < to.y + to.h; ++y)
          for (int x = to.x; x < to.x + to.w; ++x)
            for (int c = 0; c < 4; ++c)
              ASSERT_EQ(pixels[(size_t(y) * size_t(px) + size_t(x)) * 4 + size_t(c)],
                        s.colours[b][size_t(side)])
                  << "tile " << tile << " box " << b << " side " << side;
      }
    for (uint8_t v : pixels) coloured += v != 0;
    EXPECT_EQ(coloured, drawn) << "the gutters and the rest stay empty";
    // The mesh: four vertices a drawn side, the first at the side's top-left texel corner.
    const std::span<const uint32_t> boxes = t.boxes_of(tile);
    std::vector<uint32_t> first(boxes.size()), count(boxes.size());
    const TexturedMesh mesh = box_mesh(t.tiles, boxes, first, count, px);
    for (size_t i = 0; i < boxes.size(); ++i) {
      const TexturedBox& box = t.tiles.boxes[boxes[i]];
      EXPECT_EQ(count[i], 6 * box.side_count());
      for (const BoxSide& side : box.sides)
        if (side.w > 0) {
          const TexturedVertex& corner = mesh.vertices[mesh.indices[first[i]]];
          EXPECT_FLOAT_EQ(corner.uv.x, float(side.x) / float(px));
          EXPECT_FLOAT_EQ(corner.uv.y, float(side.y) / float(px));
          break;
        }
    }
  }
}

TEST(BoxTiling, TilesOfThePagesSizeAreThePages) {
  const Synthetic s = synthetic_boxes();
  for (int px : {0, 2048, 4096}) {
    const BoxTiling t = tile_boxes(s.set, px);
    EXPECT_TRUE(t.whole_pages);
    ASSERT_EQ(t.page_of_tile, (std::vector<uint32_t>{0, 1}));
    EXPECT_EQ(t.tile_px, (std::vector<int>{2048, 2048}));
    for (uint32_t b = 0; b < s.set.boxes.size(); ++b) {
      EXPECT_EQ(t.tiles.boxes[b].page, s.set.boxes[b].page);
      EXPECT_EQ(t.tiles.boxes[b].sides[0].x, s.set.boxes[b].sides[0].x);
    }
    EXPECT_EQ(t.boxes_of(0).size() + t.boxes_of(1).size(), s.set.boxes.size());
  }
}

// A side as wide as its page fits it as the bake placed it, but no tile with its gutter.
TEST(BoxTiling, ABoxThatFitsNoTileLeavesThePagesAsTheyAre) {
  BoxSet set;
  set.page_px = 64;
  set.page_count = 1;
  TexturedBox box;
  box.bounds = {{0, 0, 0}, {1, 1, 1}};
  box.sides[0] = {0, 0, 64, 10};
  set.boxes = {box, box};
  set.boxes[1].sides[0] = {0, 20, 8, 8};
  const BoxTiling t = tile_boxes(set, 32);
  EXPECT_TRUE(t.whole_pages);
  EXPECT_EQ(t.page_of_tile.size(), 1u);
  EXPECT_EQ(t.tiles.boxes[0].sides[0].w, 64);
  EXPECT_EQ(t.tiles.boxes[1].sides[0].y, 20);
}

TEST(BoxTiling, NoBoxesNoTiles) {
  BoxSet none;
  const BoxTiling t = tile_boxes(none, 512);
  EXPECT_TRUE(t.page_of_tile.empty());
  EXPECT_EQ(t.tile_first, std::vector<uint32_t>{0});
  EXPECT_EQ(t.tiles.page_count, 0u);
}

TEST(UploadCost, LearnsTheTimeAByteFromFramesThatTookSomeIn) {
  constexpr uint64_t MB = 1 << 20;
  UploadCost cost;
  EXPECT_EQ(cost.predict_ms({MB, 0}), 0.0) << "nothing measured: nothing foreseen";
  cost.observe({}, 5.0);  // a frame that took nothing in teaches nothing
  EXPECT_EQ(cost.predict_ms({MB, 0}), 0.0);
  for (int f = 0; f < 20; ++f) cost.observe({4 * MB, 0}, 14.4);  // 3.6 ms a MB
  EXPECT_NEAR(cost.predict_ms({MB, 0}), 3.6, 1e-9);
  EXPECT_NEAR(cost.predict_ms({0, MB}), 3.6, 1e-9) << "no texture seen yet: the pooled rate";
  EXPECT_EQ(cost.predict_ms({}), 0.0);
  for (int f = 0; f < 100; ++f) cost.observe({MB, 0}, 0.36);  // the machine got faster
  EXPECT_NEAR(cost.predict_ms({MB, 0}), 0.36, 0.01);
}

// Frames of meshes alone, of textures alone and of both: each kind at its own rate.
TEST(UploadCost, TellsTexturesFromMeshes) {
  constexpr uint64_t MB = 1 << 20;
  UploadCost cost;
  for (int f = 0; f < 30; ++f) {
    const UploadBytes bytes{uint64_t(f % 3) * MB, uint64_t((f / 3) % 2) * 2 * MB};
    cost.observe(bytes, 1.7 * double(bytes.meshes) / MB + 5.3 * double(bytes.textures) / MB);
  }
  EXPECT_NEAR(cost.ms_per_mesh_byte() * MB, 1.7, 1e-6);
  EXPECT_NEAR(cost.ms_per_texture_byte() * MB, 5.3, 1e-6);
  EXPECT_NEAR(cost.predict_ms({2 * MB, MB}), 2 * 1.7 + 5.3, 1e-6);
  // Always in the same proportion the two cannot be told apart: the pooled rate for both.
  UploadCost mixed;
  for (int f = 0; f < 30; ++f) mixed.observe({MB, MB}, 7.0);
  EXPECT_NEAR(mixed.ms_per_mesh_byte() * MB, 3.5, 1e-6);
  EXPECT_NEAR(mixed.ms_per_texture_byte() * MB, 3.5, 1e-6);
  // A fit that makes a kind free or cheaper than nothing (noise) is not believed either.
  UploadCost odd;
  for (int f = 0; f < 30; ++f) odd.observe(f % 2 ? UploadBytes{MB, MB} : UploadBytes{MB, 0}, f % 2 ? 1.0 : 2.0);
  EXPECT_NEAR(odd.ms_per_texture_byte() * MB, odd.ms_per_mesh_byte() * MB, 1e-9);
  EXPECT_GT(odd.ms_per_texture_byte(), 0.0);
}

}  // namespace
}  // namespace farfield
