#include "farfield/scene/texture_image.hpp"

#include <cstring>
#include <memory>

#include "farfield/core/codec.hpp"
#include "farfield/core/text.hpp"

// stb_image for the formats libpng and libturbojpeg do not read; its size limit is set before
// it allocates, and its PNG and JPEG decoders are left out (those go through the libraries
// the project already uses, with their checks).
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_PNG
#define STBI_NO_JPEG
#define STBI_NO_HDR
#define STBI_NO_LINEAR
#define STBI_NO_STDIO
#define STBI_MAX_DIMENSIONS 16384  // kMaxTextureSide
#define STBI_FAILURE_USERMSG
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace farfield {

namespace {

constexpr uint64_t kMaxTexels = uint64_t(kMaxTextureSide) * kMaxTextureSide;
// Beyond a megatexel, an image file holding more texels a byte than this is refused unread.
constexpr uint64_t kMaxTexelsPerByte = 4096;

bool starts_with(std::span<const std::byte> bytes, std::initializer_list<uint8_t> magic) {
  if (bytes.size() < magic.size()) return false;
  size_t i = 0;
  for (uint8_t m : magic)
    if (uint8_t(bytes[i++]) != m) return false;
  return true;
}

bool is_png(std::span<const std::byte> b) {
  return starts_with(b, {0x89, 'P', 'N', 'G'});
}
bool is_jpeg(std::span<const std::byte> b) {
  return starts_with(b, {0xff, 0xd8, 0xff});
}

bool any_translucent(const RgbaImage& image) {
  for (size_t i = 3; i < image.rgba.size(); i += 4)
    if (image.rgba[i] != 255) return true;
  return false;
}

RgbaImage with_alpha(const Image& rgb) {
  RgbaImage out(rgb.width, rgb.height);
  for (size_t i = 0, n = size_t(rgb.width) * rgb.height; i < n; ++i) {
    std::memcpy(&out.rgba[i * 4], &rgb.rgb[i * 3], 3);
    out.rgba[i * 4 + 3] = 255;
  }
  return out;
}

Result<RgbaImage> decode(std::span<const std::byte> bytes) {
  if (is_png(bytes)) return decode_png_rgba(bytes, kMaxTexels);
  if (is_jpeg(bytes)) {
    auto rgb = decode_jpeg(bytes, kMaxTexels);
    if (!rgb) return rgb.error();
    return with_alpha(*rgb);
  }
  if (bytes.size() > size_t(INT32_MAX)) return make_error("image file over 2 GB");
  int w = 0, h = 0, channels = 0;
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  // A header is checked before a decode allocates what it claims: a few damaged bytes of TGA
  // claimed 16384 x 16384 texels, which stb_image then filled for 14 s and 1.1 GB. The
  // run-length codings of these formats give at most a few hundred texels a byte.
  if (stbi_info_from_memory(data, int(bytes.size()), &w, &h, &channels) &&
      uint64_t(w) * uint64_t(h) > kMaxTexelsPerByte * bytes.size() + (1u << 20))
    return make_error(
        formatted("claims %d x %d texels in %zu bytes: damaged or truncated", w, h, bytes.size()));
  std::unique_ptr<stbi_uc, void (*)(void*)> texels(
      stbi_load_from_memory(data, int(bytes.size()), &w, &h, &channels, 4), stbi_image_free);
  if (!texels)
    return make_error("not an image this build reads (PNG, JPEG, TGA, BMP, GIF, PSD, PNM): ",
                      stbi_failure_reason());
  if (auto ok = check_image_size(uint64_t(w), uint64_t(h), kMaxTexels); !ok) return ok.error();
  RgbaImage out(w, h);
  std::memcpy(out.rgba.data(), texels.get(), out.rgba.size());
  return out;
}

}  // namespace

Result<Texture> texture_from_image_bytes(std::string name, std::span<const std::byte> bytes) {
  auto image = decode(bytes);
  if (!image) return make_error(name, ": ", image.error().message);
  Texture t;
  t.width = uint32_t(image->width);
  t.height = uint32_t(image->height);
  t.has_alpha = any_translucent(*image);
  if (is_png(bytes) || is_jpeg(bytes)) {
    t.codec = is_png(bytes) ? TextureCodec::png : TextureCodec::jpeg;
    t.encoded.assign(bytes.begin(), bytes.end());
  } else {
    auto png = encode_png(*image);
    if (!png) return make_error(name, ": ", png.error().message);
    t.encoded = std::move(*png);
  }
  t.name = std::move(name);
  return t;
}

Result<Texels> decode_texture(const Texture& texture) {
  auto image = texture.codec == TextureCodec::jpeg ? [&]() -> Result<RgbaImage> {
    auto rgb = decode_jpeg(texture.encoded, kMaxTexels);
    if (!rgb) return rgb.error();
    return with_alpha(*rgb);
  }()
      : decode_png_rgba(texture.encoded, kMaxTexels);
  if (!image) return make_error("texture ", texture.name, ": ", image.error().message);
  if (uint32_t(image->width) != texture.width || uint32_t(image->height) != texture.height)
    return make_error("texture ", texture.name, ": the image is ", std::to_string(image->width),
                      "x", std::to_string(image->height), ", not the ",
                      std::to_string(texture.width), "x", std::to_string(texture.height),
                      " recorded");
  return image;
}

Result<Texture> texture_from_texels(std::string name, const Texels& texels) {
  auto png = encode_png(texels);
  if (!png) return make_error(name, ": ", png.error().message);
  Texture t;
  t.name = std::move(name);
  t.codec = TextureCodec::png;
  t.width = uint32_t(texels.width);
  t.height = uint32_t(texels.height);
  t.has_alpha = any_translucent(texels);
  t.encoded = std::move(*png);
  return t;
}

}  // namespace farfield
