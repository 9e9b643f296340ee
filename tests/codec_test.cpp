#include "farfield/core/codec.hpp"

#include <gtest/gtest.h>

#include <random>

#include "farfield/eval/image_metrics.hpp"

namespace farfield {
namespace {

Bytes random_bytes(size_t size, uint32_t seed) {
  std::mt19937 random(seed);
  Bytes bytes(size);
  for (auto& b : bytes) b = std::byte(random() & 0xFF);
  return bytes;
}

Bytes as_bytes(std::string_view text) {
  const auto* p = reinterpret_cast<const std::byte*>(text.data());
  return Bytes(p, p + text.size());
}

// Smooth colour ramps with a few hard edges: what a rendered far-field texture looks like.
Image test_picture(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = image.pixel(x, y);
      const bool building = (x / 16 + y / 24) % 3 == 0;
      p[0] = uint8_t(building ? 180 : x * 255 / w);
      p[1] = uint8_t(building ? 170 : y * 255 / h);
      p[2] = uint8_t(building ? 150 : 128 + (x - y) / 4);
    }
  return image;
}

TEST(Codec, ZstdRoundTripsAndShrinksRedundantData) {
  for (const Bytes& original : {Bytes{}, random_bytes(1000, 1), Bytes(100000, std::byte{7})}) {
    const Bytes compressed = zstd_compress(original);
    auto back = zstd_decompress(compressed, original.size());
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(*back, original);
  }
  EXPECT_LT(zstd_compress(Bytes(100000, std::byte{7})).size(), 100u);
}

TEST(Codec, ZstdRefusesWrongSizeGarbageAndTrailingBytes) {
  const Bytes original = random_bytes(5000, 2);
  Bytes compressed = zstd_compress(original);
  EXPECT_FALSE(zstd_decompress(compressed, original.size() + 1));
  EXPECT_FALSE(zstd_decompress(as_bytes("not zstd at all"), 15));
  EXPECT_FALSE(zstd_decompress({}, 0));
  // Cut short: the declared size is there, the data is not.
  EXPECT_FALSE(
      zstd_decompress(std::span(compressed).first(compressed.size() / 2), original.size()));
  compressed.push_back(std::byte{0});
  auto trailing = zstd_decompress(compressed, original.size());
  ASSERT_FALSE(trailing);
  EXPECT_NE(trailing.error().message.find("after its frame"), std::string::npos)
      << trailing.error().message;
}

TEST(Codec, PngRoundTripIsExact) {
  const Image image = test_picture(67, 45);
  auto png = encode_png(image);
  ASSERT_TRUE(png) << png.error().message;
  auto back = decode_png(*png);
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(back->width, 67);
  EXPECT_EQ(back->height, 45);
  EXPECT_EQ(back->rgb, image.rgb);
}

TEST(Codec, JpegRoundTripIsWithinItsQuality) {
  const Image image = test_picture(128, 96);
  for (auto [quality, min_psnr_db] : {std::pair{50, 28.0}, {75, 31.0}, {95, 38.0}}) {
    auto jpeg = encode_jpeg(image, quality);
    ASSERT_TRUE(jpeg) << jpeg.error().message;
    EXPECT_LT(jpeg->size(), image.rgb.size() / 4) << "quality " << quality;
    auto back = decode_jpeg(*jpeg);
    ASSERT_TRUE(back) << back.error().message;
    ASSERT_EQ(back->width, 128);
    ASSERT_EQ(back->height, 96);
    EXPECT_GT(compare_images(image, *back).psnr_db, min_psnr_db) << "quality " << quality;
  }
}

TEST(Codec, ImageDecodersRefuseDamageAndOversizeImages) {
  const Image image = test_picture(64, 64);
  const Bytes png = encode_png(image).value();
  const Bytes jpeg = encode_jpeg(image, 80).value();
  EXPECT_FALSE(decode_png(as_bytes("plain text")));
  EXPECT_FALSE(decode_jpeg(as_bytes("plain text")));
  EXPECT_FALSE(decode_png(std::span(png).first(png.size() / 2)));
  auto cut = decode_jpeg(std::span(jpeg).first(jpeg.size() / 2));
  ASSERT_FALSE(cut);  // a warning (premature end) is an error, not a grey lower half
  EXPECT_NE(cut.error().message.find("JPEG"), std::string::npos) << cut.error().message;
  // The bound is checked from the header, before the pixels are allocated.
  auto big = decode_png(png, 64 * 64 - 1);
  ASSERT_FALSE(big);
  EXPECT_NE(big.error().message.find("64x64"), std::string::npos) << big.error().message;
  EXPECT_FALSE(decode_jpeg(jpeg, 100));
  EXPECT_TRUE(decode_jpeg(jpeg, 64 * 64));
}

}  // namespace
}  // namespace farfield
