#include "farfield/core/image.hpp"

#include <gtest/gtest.h>

#include "test_util.hpp"

namespace farfield {
namespace {

using test::TempDir;

Image gradient(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = image.pixel(x, y);
      p[0] = uint8_t(x * 40);
      p[1] = uint8_t(y * 70);
      p[2] = uint8_t(255 - x * y);
    }
  return image;
}

TEST(Image, PngRoundTripKeepsEveryByte) {
  TempDir dir;
  const Image image = gradient(5, 3);
  ASSERT_TRUE(write_png(image, dir.file("a.png")));
  auto read = read_png(dir.file("a.png"));
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(read->width, 5);
  EXPECT_EQ(read->height, 3);
  EXPECT_EQ(read->rgb, image.rgb);
  // The temporary file was renamed into place.
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"a.png"});
}

TEST(Image, WriteIntoMissingFolderFailsAndLeavesNothing) {
  TempDir dir;
  const std::string path = dir.file("missing/a.png");
  const Result<void> written = write_png(gradient(4, 4), path);
  ASSERT_FALSE(written);
  EXPECT_NE(written.error().message.find(path), std::string::npos) << written.error().message;
  EXPECT_TRUE(dir.entries().empty());
}

TEST(Image, ReadOfNonPngFailsCleanly) {
  TempDir dir;
  test::write_file(dir.file("text.png"), "this is not a PNG file at all");
  auto read = read_png(dir.file("text.png"));
  ASSERT_FALSE(read);
  EXPECT_NE(read.error().message.find("text.png"), std::string::npos) << read.error().message;

  // A PNG cut short: the header reads, the pixels do not.
  ASSERT_TRUE(write_png(gradient(64, 64), dir.file("whole.png")));
  const std::string bytes = test::read_file(dir.file("whole.png"));
  test::write_file(dir.file("cut.png"), bytes.substr(0, bytes.size() / 2));
  auto cut = read_png(dir.file("cut.png"));
  ASSERT_FALSE(cut);
  EXPECT_NE(cut.error().message.find("cut.png"), std::string::npos) << cut.error().message;

  auto missing = read_png(dir.file("none.png"));
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("none.png"), std::string::npos);
}

}  // namespace
}  // namespace farfield
