// Textures from image bytes (PNG and JPEG kept as they are, other formats stored as PNG) and
// their texels.
#include "farfield/scene/texture_image.hpp"

#include <gtest/gtest.h>

#include "farfield/core/codec.hpp"
#include "farfield/scene/texture_sampler.hpp"

namespace farfield {
namespace {

RgbaImage gradient(int w, int h, bool translucent) {
  RgbaImage image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* t = image.texel(x, y);
      t[0] = uint8_t(x * 255 / (w - 1));
      t[1] = uint8_t(y * 255 / (h - 1));
      t[2] = 77;
      t[3] = translucent && x == 0 ? 0 : 255;
    }
  return image;
}

std::span<const std::byte> bytes_of(const std::vector<std::byte>& v) {
  return v;
}

TEST(TextureImage, PngIsKeptAndDecodesToTheSameTexels) {
  const RgbaImage image = gradient(5, 3, true);
  auto png = encode_png(image);
  ASSERT_TRUE(png);
  auto texture = texture_from_image_bytes("g.png", bytes_of(*png));
  ASSERT_TRUE(texture) << texture.error().message;
  EXPECT_EQ(texture->codec, TextureCodec::png);
  EXPECT_EQ(texture->encoded, *png);
  EXPECT_EQ(texture->width, 5u);
  EXPECT_EQ(texture->height, 3u);
  EXPECT_TRUE(texture->has_alpha);
  auto texels = decode_texture(*texture);
  ASSERT_TRUE(texels);
  EXPECT_EQ(texels->rgba, image.rgba);
}

TEST(TextureImage, JpegIsKeptOpaque) {
  Image rgb(8, 8);
  auto jpeg = encode_jpeg(rgb, 90);
  ASSERT_TRUE(jpeg);
  auto texture = texture_from_image_bytes("black.jpg", bytes_of(*jpeg));
  ASSERT_TRUE(texture) << texture.error().message;
  EXPECT_EQ(texture->codec, TextureCodec::jpeg);
  EXPECT_FALSE(texture->has_alpha);
  auto texels = decode_texture(*texture);
  ASSERT_TRUE(texels);
  EXPECT_EQ(texels->texel(3, 3)[3], 255);
}

// An uncompressed 2 x 1 true-colour TGA, bottom-up as TGA stores it by default, through
// stb_image and stored as PNG.
TEST(TextureImage, OtherFormatsAreStoredAsPng) {
  std::vector<std::byte> tga(18, std::byte{0});
  tga[2] = std::byte{2};    // uncompressed true colour
  tga[12] = std::byte{2};   // width 2
  tga[14] = std::byte{1};   // height 1
  tga[16] = std::byte{32};  // bits per pixel, BGRA
  for (uint8_t b : {255, 0, 0, 255, 0, 0, 255, 128}) tga.push_back(std::byte{b});
  auto texture = texture_from_image_bytes("t.tga", tga);
  ASSERT_TRUE(texture) << texture.error().message;
  EXPECT_EQ(texture->codec, TextureCodec::png);
  EXPECT_TRUE(texture->has_alpha);
  auto texels = decode_texture(*texture);
  ASSERT_TRUE(texels);
  EXPECT_EQ(texels->texel(0, 0)[2], 255);  // blue
  EXPECT_EQ(texels->texel(1, 0)[0], 255);  // red
  EXPECT_EQ(texels->texel(1, 0)[3], 128);
}

TEST(TextureImage, CorruptImagesAreRefusedByName) {
  const std::string text = "definitely not an image";
  auto bad = texture_from_image_bytes("wall.bmp", std::as_bytes(std::span(text)));
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("wall.bmp"), std::string::npos);
  auto png = encode_png(gradient(4, 4, false));
  ASSERT_TRUE(png);
  png->resize(png->size() / 2);
  auto cut = texture_from_image_bytes("half.png", bytes_of(*png));
  ASSERT_FALSE(cut);
  EXPECT_NE(cut.error().message.find("half.png"), std::string::npos);
  // A TGA header claiming 16384 x 16384 texels of run-length data in 34 bytes: refused
  // before anything is decoded (the fuzzer found it taking 14 s and 1.1 GB).
  std::vector<std::byte> tga(34, std::byte{0});
  tga[2] = std::byte{10};     // run-length true colour
  tga[13] = std::byte{0x40};  // width 16384
  tga[15] = std::byte{0x40};  // height 16384
  tga[16] = std::byte{24};
  auto huge = texture_from_image_bytes("huge.tga", tga);
  ASSERT_FALSE(huge);
  EXPECT_NE(huge.error().message.find("huge.tga: claims 16384 x 16384 texels in 34 bytes"),
            std::string::npos)
      << huge.error().message;
  // A stored texture whose image is not the size it records.
  auto whole = encode_png(gradient(4, 4, false));
  Texture lying{
      .name = "lie.png", .codec = TextureCodec::png, .width = 8, .height = 4, .encoded = *whole};
  auto texels = decode_texture(lying);
  ASSERT_FALSE(texels);
  EXPECT_NE(texels.error().message.find("lie.png"), std::string::npos);
}

}  // namespace
}  // namespace farfield

namespace farfield {
namespace {

// The CPU sampler: the nearest texel of the top level for a small footprint, the box-filtered
// level matching a larger one, coordinates wrapped as the shader wraps them.
TEST(TextureSampler, LevelsFollowTheFootprintAndWrapModesApply) {
  RgbaImage image(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      uint8_t* t = image.texel(x, y);
      t[0] = (x + y) % 2 ? 255 : 0;
      t[3] = 255;
    }
  const TextureSampler sampler(image);
  EXPECT_FLOAT_EQ(sampler.sample({0.1f, 0.1f}, 1.0f, TextureWrap::repeat, TextureWrap::repeat).r,
                  0.0f);
  EXPECT_FLOAT_EQ(sampler.sample({0.3f, 0.1f}, 1.0f, TextureWrap::repeat, TextureWrap::repeat).r,
                  1.0f);
  // A footprint of 4 texels reads the 1 x 1 level: the checker's mean.
  EXPECT_NEAR(sampler.sample({0.1f, 0.1f}, 4.0f, TextureWrap::repeat, TextureWrap::repeat).r, 0.5f,
              0.01f);
  // 1.3 repeats to 0.3, clamps to 1 (the last texel), mirrors to 0.7.
  EXPECT_FLOAT_EQ(sampler.sample({1.3f, 0.1f}, 1.0f, TextureWrap::repeat, TextureWrap::repeat).r,
                  1.0f);
  EXPECT_FLOAT_EQ(sampler.sample({1.3f, 0.1f}, 1.0f, TextureWrap::clamp, TextureWrap::repeat).r,
                  1.0f);
  EXPECT_FLOAT_EQ(wrap_texture_coordinate(1.3f, TextureWrap::mirror), 0.7f);
  EXPECT_FLOAT_EQ(wrap_texture_coordinate(-0.25f, TextureWrap::repeat), 0.75f);
  EXPECT_FLOAT_EQ(wrap_texture_coordinate(-0.25f, TextureWrap::clamp), 0.0f);
}

}  // namespace
}  // namespace farfield
