#include "farfield/eval/image_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "farfield/core/image_pyramid.hpp"

namespace farfield {
namespace {

TEST(ImageMetrics, IdenticalImagesHaveInfinitePsnrAndGreyDifference) {
  Image a(4, 3);
  for (size_t i = 0; i < a.rgb.size(); ++i) a.rgb[i] = uint8_t(i * 7);
  const ImageComparison c = compare_images(a, a);
  EXPECT_TRUE(c.identical());
  EXPECT_TRUE(std::isinf(c.psnr_db));
  const Image d = difference_image(a, a);
  for (uint8_t v : d.rgb) EXPECT_EQ(v, 128);
}

TEST(ImageMetrics, PsnrAndDifferenceFollowTheDefinitions) {
  Image a(2, 2), b(2, 2);
  b.pixel(1, 0)[0] = 10;   // one channel of one pixel off by 10
  b.pixel(0, 1)[2] = 200;  // and one far off: the difference image clamps at 255
  const ImageComparison c = compare_images(a, b);
  EXPECT_EQ(c.differing_pixels, 2u);
  EXPECT_DOUBLE_EQ(c.mse, (100.0 + 40000.0) / 12.0);
  EXPECT_NEAR(c.psnr_db, 10 * std::log10(255.0 * 255.0 / c.mse), 1e-9);
  const Image d = difference_image(a, b);
  EXPECT_EQ(d.pixel(1, 0)[0], 138);
  EXPECT_EQ(d.pixel(0, 1)[2], 255);
  EXPECT_EQ(difference_image(b, a).pixel(1, 0)[0], 118);
}

TEST(ImageMetrics, BoxDownsampleAveragesEachBlock) {
  Image a(4, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      a.pixel(x, y)[0] = (x + y) % 2 ? 255 : 0;  // a checkerboard averages to mid grey
      a.pixel(x, y)[1] = uint8_t(10 * x);
      a.pixel(x, y)[2] = 7;
    }
  const Image d = box_downsample(a, 2);
  ASSERT_EQ(d.width, 2);
  ASSERT_EQ(d.height, 1);
  EXPECT_EQ(d.pixel(0, 0)[0], 128);  // 510 / 4 rounded to nearest
  EXPECT_EQ(d.pixel(1, 0)[0], 128);
  EXPECT_EQ(d.pixel(0, 0)[1], 5);
  EXPECT_EQ(d.pixel(1, 0)[1], 25);
  EXPECT_EQ(d.pixel(1, 0)[2], 7);
  EXPECT_EQ(box_downsample(a, 1).rgb, a.rgb);
}

}  // namespace
}  // namespace farfield
