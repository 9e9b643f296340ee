// An 8-bit RGB image in rows from the top, and PNG files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "farfield/core/result.hpp"

namespace farfield {

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // width * height * 3 bytes, row 0 at the top

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0) {}
  uint8_t* pixel(int x, int y) { return rgb.data() + (size_t(y) * width + x) * 3; }
  const uint8_t* pixel(int x, int y) const { return rgb.data() + (size_t(y) * width + x) * 3; }
};

// Written atomically (temporary file, then rename).
Result<void> write_png(const Image& image, const std::string& path);
Result<Image> read_png(const std::string& path);

}  // namespace farfield
