// An 8-bit RGB image in rows from the top, and PNG files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
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

// An 8-bit RGBA image in rows from the top (textures).
struct RgbaImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4 bytes, row 0 at the top

  RgbaImage() = default;
  RgbaImage(int w, int h) : width(w), height(h), rgba(size_t(w) * size_t(h) * 4, 0) {}
  uint8_t* texel(int x, int y) { return rgba.data() + (size_t(y) * width + x) * 4; }
  const uint8_t* texel(int x, int y) const { return rgba.data() + (size_t(y) * width + x) * 4; }
};

// Images of 1..32768 pixels per side and at most this many pixels (768 MiB of RGB).
inline constexpr uint64_t kMaxImagePixels = uint64_t(1) << 28;

// The size check of every image decoder, before any pixel is allocated.
Result<void> check_image_size(uint64_t width, uint64_t height, uint64_t max_pixels);

// PNG in memory (libpng's simplified API). Lossless: decode_png(encode_png(i)) == i byte for
// byte; grey, palette, 16-bit and alpha PNGs are converted to 8-bit RGB. Messages say what is
// wrong, not where the bytes came from.
Result<std::vector<std::byte>> encode_png(const Image& image);
Result<Image> decode_png(std::span<const std::byte> png, uint64_t max_pixels = kMaxImagePixels);

// The same with alpha kept (an opaque PNG decodes with alpha 255).
Result<std::vector<std::byte>> encode_png(const RgbaImage& image);
Result<RgbaImage> decode_png_rgba(std::span<const std::byte> png,
                                  uint64_t max_pixels = kMaxImagePixels);

// PNG files; written atomically (temporary file, then rename). Messages name the file.
Result<void> write_png(const Image& image, const std::string& path);
Result<Image> read_png(const std::string& path);

// An image file in the format its name ends with: .png, or .jpg / .jpeg (quality 95);
// refused for any other name before anything is written (check_image_name says so first).
Result<void> check_image_name(const std::string& path);
Result<void> write_image(const Image& image, const std::string& path);

}  // namespace farfield
