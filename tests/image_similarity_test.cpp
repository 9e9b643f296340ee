// The accuracy comparators (paper 001, Sec. 3.2, and SSIM) on hand-made images.
#include "farfield/core/image_similarity.hpp"

#include <gtest/gtest.h>

#include <random>

namespace farfield {
namespace {

// Dark rectangles of different sizes on a light ground: plenty of edges.
Image rectangles(int shift_x = 0) {
  Image image(96, 64);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const int sx = x - shift_x;
      const bool dark = (sx >= 8 && sx < 30 && y >= 6 && y < 40) ||
                        (sx >= 44 && sx < 52 && y >= 20 && y < 58) ||
                        (sx >= 62 && sx < 90 && y >= 10 && y < 18);
      uint8_t* p = image.pixel(x, y);
      p[0] = p[1] = p[2] = dark ? 30 : 220;
    }
  return image;
}

Image noise(uint32_t seed) {
  Image image(96, 64);
  std::mt19937 random(seed);
  for (uint8_t& c : image.rgb) c = uint8_t(random() & 0xff);
  return image;
}

TEST(ImageSimilarity, IdenticalImagesScoreOne) {
  const Image a = rectangles();
  EXPECT_DOUBLE_EQ(edge_similarity(a, a), 1.0);
  EXPECT_NEAR(structural_similarity(a, a), 1.0, 1e-9);
  const Image flat(32, 32);  // no edges at all
  EXPECT_DOUBLE_EQ(edge_similarity(flat, flat), 1.0);
}

TEST(ImageSimilarity, UnrelatedImagesScoreLow) {
  EXPECT_LT(edge_similarity(rectangles(), noise(1)), 0.3);
  EXPECT_LT(structural_similarity(rectangles(), noise(1)), 0.1);
  EXPECT_LT(structural_similarity(noise(1), noise(2)), 0.1);
  EXPECT_LT(edge_similarity(rectangles(), Image(96, 64)), 0.05);  // edges against none
}

// The paper's blur is there for this: a one-pixel shift keeps the edges close, so the blurred
// maps still match; compared pixel by pixel without it, they hardly do.
TEST(ImageSimilarity, AOnePixelShiftScoresHighWithTheBlurAndLowWithout) {
  const Image a = rectangles(), shifted = rectangles(1);
  EXPECT_GT(edge_similarity(a, shifted), 0.7);
  EXPECT_LT(edge_similarity(a, shifted, {.blur_radius = 0}), 0.6);
  EXPECT_GT(edge_similarity(a, shifted), edge_similarity(a, shifted, {.blur_radius = 0}) + 0.2);
  EXPECT_GT(structural_similarity(a, shifted), 0.5);
  EXPECT_LT(structural_similarity(a, shifted), 1.0);
}

}  // namespace
}  // namespace farfield
