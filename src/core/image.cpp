#include "farfield/core/image.hpp"

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <type_traits>

#include <png.h>

#include "farfield/core/assert.hpp"
#include "farfield/core/atomic_file.hpp"
#include "farfield/core/codec.hpp"

namespace farfield {

namespace {

Error io_error(const std::string& path, const char* what) {
  return make_error(path, ": ", what, ": ", std::strerror(errno));
}

}  // namespace

Result<void> check_image_size(uint64_t width, uint64_t height, uint64_t max_pixels) {
  if (width == 0 || height == 0 || width > (1u << 15) || height > (1u << 15) ||
      width * height > max_pixels)
    return make_error("image of ", std::to_string(width), "x", std::to_string(height),
                      " pixels is outside 1..32768 per side or over ", std::to_string(max_pixels),
                      " pixels");
  return {};
}

namespace {

// libpng's simplified API keeps its setjmp error handling inside libpng, so no longjmp
// crosses C++ frames; its errors come back in png_image::message. `format` is
// PNG_FORMAT_RGB or PNG_FORMAT_RGBA, `channels` its bytes a pixel.
Result<std::vector<std::byte>> encode_png_pixels(int width, int height, const uint8_t* pixels,
                                                 size_t bytes, uint32_t format, int channels) {
  FF_ASSERT(width > 0 && height > 0 && bytes == size_t(width) * size_t(height) * channels,
            "image %dx%d holds %zu bytes", width, height, bytes);
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(width);
  png.height = png_uint_32(height);
  png.format = format;
  png_alloc_size_t size = 0;
  if (!png_image_write_get_memory_size(png, size, 0, pixels, 0, nullptr))
    return make_error("cannot encode PNG: ", png.message);
  std::vector<std::byte> out(size);
  if (!png_image_write_to_memory(&png, out.data(), &size, 0, pixels, 0, nullptr))
    return make_error("cannot encode PNG: ", png.message);
  out.resize(size);
  return out;
}

// libpng converts grey, palette and 16-bit to `format`, dropping alpha for RGB and making it
// opaque where the file has none for RGBA.
template <class Pixels>
Result<Pixels> decode_png_pixels(std::span<const std::byte> bytes, uint64_t max_pixels,
                                 uint32_t format) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()))
    return make_error("not a readable PNG: ", png.message);
  png.format = format;
  if (auto ok = check_image_size(png.width, png.height, max_pixels); !ok) {
    png_image_free(&png);
    return make_error("PNG ", ok.error().message);
  }
  Pixels image(int(png.width), int(png.height));
  uint8_t* data;
  if constexpr (std::is_same_v<Pixels, RgbaImage>)
    data = image.rgba.data();
  else
    data = image.rgb.data();
  if (!png_image_finish_read(&png, nullptr, data, 0, nullptr))
    return make_error("corrupted PNG: ", png.message);
  return image;
}

}  // namespace

Result<std::vector<std::byte>> encode_png(const Image& image) {
  return encode_png_pixels(image.width, image.height, image.rgb.data(), image.rgb.size(),
                           PNG_FORMAT_RGB, 3);
}

Result<Image> decode_png(std::span<const std::byte> bytes, uint64_t max_pixels) {
  return decode_png_pixels<Image>(bytes, max_pixels, PNG_FORMAT_RGB);
}

Result<std::vector<std::byte>> encode_png(const RgbaImage& image) {
  return encode_png_pixels(image.width, image.height, image.rgba.data(), image.rgba.size(),
                           PNG_FORMAT_RGBA, 4);
}

Result<RgbaImage> decode_png_rgba(std::span<const std::byte> bytes, uint64_t max_pixels) {
  return decode_png_pixels<RgbaImage>(bytes, max_pixels, PNG_FORMAT_RGBA);
}

Result<void> write_png(const Image& image, const std::string& path) {
  auto bytes = encode_png(image);
  if (!bytes) return make_error(path, ": ", bytes.error().message);
  return write_file_atomically(
      path, std::string_view(reinterpret_cast<const char*>(bytes->data()), bytes->size()));
}

namespace {

std::string lowercase_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

Result<void> check_image_name(const std::string& path) {
  const std::string ext = lowercase_extension(path);
  if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") return {};
  return make_error(path, ": an image file must end in .png, .jpg or .jpeg");
}

Result<void> write_image(const Image& image, const std::string& path) {
  if (auto ok = check_image_name(path); !ok) return ok;
  if (lowercase_extension(path) == ".png") return write_png(image, path);
  auto bytes = encode_jpeg(image, 95);
  if (!bytes) return make_error(path, ": ", bytes.error().message);
  return write_file_atomically(
      path, std::string_view(reinterpret_cast<const char*>(bytes->data()), bytes->size()));
}

Result<Image> read_png(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return io_error(path, "cannot open");
  const std::vector<char> bytes{std::istreambuf_iterator<char>(file),
                                std::istreambuf_iterator<char>()};
  if (file.bad()) return io_error(path, "read failed");
  auto image = decode_png(std::as_bytes(std::span(bytes)));
  if (!image) return make_error(path, ": ", image.error().message);
  return image;
}

}  // namespace farfield
