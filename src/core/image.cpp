#include "farfield/core/image.hpp"

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

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

// libpng's simplified API keeps its setjmp error handling inside libpng, so no longjmp
// crosses C++ frames; its errors come back in png_image::message.
Result<std::vector<std::byte>> encode_png(const Image& image) {
  FF_ASSERT(image.width > 0 && image.height > 0 &&
                image.rgb.size() == size_t(image.width) * size_t(image.height) * 3,
            "image %dx%d holds %zu bytes", image.width, image.height, image.rgb.size());
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.width);
  png.height = png_uint_32(image.height);
  png.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  if (!png_image_write_get_memory_size(png, size, 0, image.rgb.data(), 0, nullptr))
    return make_error("cannot encode PNG: ", png.message);
  std::vector<std::byte> out(size);
  if (!png_image_write_to_memory(&png, out.data(), &size, 0, image.rgb.data(), 0, nullptr))
    return make_error("cannot encode PNG: ", png.message);
  out.resize(size);
  return out;
}

Result<Image> decode_png(std::span<const std::byte> bytes, uint64_t max_pixels) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()))
    return make_error("not a readable PNG: ", png.message);
  png.format = PNG_FORMAT_RGB;  // libpng converts grey, palette, 16-bit and drops alpha
  if (auto ok = check_image_size(png.width, png.height, max_pixels); !ok) {
    png_image_free(&png);
    return make_error("PNG ", ok.error().message);
  }
  Image image(int(png.width), int(png.height));
  if (!png_image_finish_read(&png, nullptr, image.rgb.data(), 0, nullptr))
    return make_error("corrupted PNG: ", png.message);
  return image;
}

Result<std::vector<std::byte>> encode_png(const RgbaImage& image) {
  FF_ASSERT(image.width > 0 && image.height > 0 &&
                image.rgba.size() == size_t(image.width) * size_t(image.height) * 4,
            "image %dx%d holds %zu bytes", image.width, image.height, image.rgba.size());
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.width);
  png.height = png_uint_32(image.height);
  png.format = PNG_FORMAT_RGBA;
  png_alloc_size_t size = 0;
  if (!png_image_write_get_memory_size(png, size, 0, image.rgba.data(), 0, nullptr))
    return make_error("cannot encode PNG: ", png.message);
  std::vector<std::byte> out(size);
  if (!png_image_write_to_memory(&png, out.data(), &size, 0, image.rgba.data(), 0, nullptr))
    return make_error("cannot encode PNG: ", png.message);
  out.resize(size);
  return out;
}

Result<RgbaImage> decode_png_rgba(std::span<const std::byte> bytes, uint64_t max_pixels) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()))
    return make_error("not a readable PNG: ", png.message);
  png.format = PNG_FORMAT_RGBA;
  if (auto ok = check_image_size(png.width, png.height, max_pixels); !ok) {
    png_image_free(&png);
    return make_error("PNG ", ok.error().message);
  }
  RgbaImage image(int(png.width), int(png.height));
  if (!png_image_finish_read(&png, nullptr, image.rgba.data(), 0, nullptr))
    return make_error("corrupted PNG: ", png.message);
  return image;
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
