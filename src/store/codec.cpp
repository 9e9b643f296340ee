#include "farfield/store/codec.hpp"

#include <memory>
#include <string>

#include <png.h>
#include <turbojpeg.h>
#include <zstd.h>

#include "farfield/core/assert.hpp"

namespace farfield {

namespace {

void check_image(const Image& image, const char* caller) {
  FF_ASSERT(image.width > 0 && image.height > 0 &&
                image.rgb.size() == size_t(image.width) * size_t(image.height) * 3,
            "%s: image %dx%d holds %zu bytes", caller, image.width, image.height,
            image.rgb.size());
}

// The size check shared by both image decoders, before any pixel is allocated.
Result<void> check_dimensions(uint64_t width, uint64_t height, uint64_t max_pixels) {
  if (width == 0 || height == 0 || width > (1u << 15) || height > (1u << 15) ||
      width * height > max_pixels)
    return make_error("image of ", std::to_string(width), "x", std::to_string(height),
                      " pixels is outside 1..32768 per side or over ", std::to_string(max_pixels),
                      " pixels");
  return {};
}

struct TjDeleter {
  void operator()(void* handle) const { tjDestroy(handle); }
};
using TjHandle = std::unique_ptr<void, TjDeleter>;

}  // namespace

Bytes zstd_compress(std::span<const std::byte> bytes, int level) {
  Bytes out(ZSTD_compressBound(bytes.size()));
  const size_t size = ZSTD_compress(out.data(), out.size(), bytes.data(), bytes.size(), level);
  // With a bound-sized buffer, zstd fails only on a bad level or no memory: programming errors.
  FF_ASSERT(!ZSTD_isError(size), "level %d, %zu bytes: %s", level, bytes.size(),
            ZSTD_getErrorName(size));
  out.resize(size);
  return out;
}

Result<Bytes> zstd_decompress(std::span<const std::byte> compressed, uint64_t raw_size) {
  const unsigned long long declared =
      ZSTD_getFrameContentSize(compressed.data(), compressed.size());
  if (declared == ZSTD_CONTENTSIZE_ERROR) return make_error("not zstd data (bad frame header)");
  if (declared == ZSTD_CONTENTSIZE_UNKNOWN)
    return make_error("zstd frame does not declare its size");
  if (declared != raw_size)
    return make_error("zstd frame declares ", std::to_string(declared), " bytes, expected ",
                      std::to_string(raw_size));
  // One frame and nothing after it: trailing bytes mean the blob is not what was written.
  const size_t frame = ZSTD_findFrameCompressedSize(compressed.data(), compressed.size());
  if (ZSTD_isError(frame)) return make_error("corrupted zstd data: ", ZSTD_getErrorName(frame));
  if (frame != compressed.size())
    return make_error("zstd data has ", std::to_string(compressed.size() - frame),
                      " bytes after its frame");
  Bytes out(raw_size);
  const size_t size = ZSTD_decompress(out.data(), out.size(), compressed.data(), compressed.size());
  if (ZSTD_isError(size)) return make_error("corrupted zstd data: ", ZSTD_getErrorName(size));
  if (size != raw_size)
    return make_error("zstd data holds ", std::to_string(size), " bytes, expected ",
                      std::to_string(raw_size));
  return out;
}

Result<Bytes> encode_jpeg(const Image& image, int quality) {
  check_image(image, __func__);
  FF_ASSERT(quality >= 1 && quality <= 100, "JPEG quality %d outside 1..100", quality);
  TjHandle tj(tjInitCompress());
  if (!tj) return make_error("cannot start the JPEG encoder: ", tjGetErrorStr2(nullptr));
  unsigned char* buffer = nullptr;  // allocated by libturbojpeg
  unsigned long size = 0;
  const int subsampling = quality >= 90 ? TJSAMP_444 : TJSAMP_420;
  if (tjCompress2(tj.get(), image.rgb.data(), image.width, 0, image.height, TJPF_RGB, &buffer,
                  &size, subsampling, quality, TJFLAG_ACCURATEDCT) != 0) {
    tjFree(buffer);
    return make_error("cannot encode JPEG: ", tjGetErrorStr2(tj.get()));
  }
  const auto* begin = reinterpret_cast<const std::byte*>(buffer);
  Bytes out(begin, begin + size);
  tjFree(buffer);
  return out;
}

Result<Image> decode_jpeg(std::span<const std::byte> jpeg, uint64_t max_pixels) {
  TjHandle tj(tjInitDecompress());
  if (!tj) return make_error("cannot start the JPEG decoder: ", tjGetErrorStr2(nullptr));
  const auto* data = reinterpret_cast<const unsigned char*>(jpeg.data());
  int width = 0, height = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(tj.get(), data, jpeg.size(), &width, &height, &subsampling,
                          &colorspace) != 0)
    return make_error("not a readable JPEG: ", tjGetErrorStr2(tj.get()));
  if (auto ok = check_dimensions(uint64_t(width), uint64_t(height), max_pixels); !ok)
    return make_error("JPEG ", ok.error().message);
  Image image(width, height);
  // STOPONWARNING: a truncated stream is an error, not a grey lower half. LIMITSCANS: a
  // crafted progressive JPEG with thousands of scans fails instead of taking minutes.
  if (tjDecompress2(tj.get(), data, jpeg.size(), image.rgb.data(), width, 0, height, TJPF_RGB,
                    TJFLAG_ACCURATEDCT | TJFLAG_STOPONWARNING | TJFLAG_LIMITSCANS) != 0)
    return make_error("corrupted JPEG: ", tjGetErrorStr2(tj.get()));
  return image;
}

// libpng's simplified API keeps its setjmp error handling inside libpng, so no longjmp
// crosses C++ frames; its errors come back in png_image::message.
Result<Bytes> encode_png(const Image& image) {
  check_image(image, __func__);
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.width);
  png.height = png_uint_32(image.height);
  png.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  if (!png_image_write_get_memory_size(png, size, 0, image.rgb.data(), 0, nullptr))
    return make_error("cannot encode PNG: ", png.message);
  Bytes out(size);
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
  if (auto ok = check_dimensions(png.width, png.height, max_pixels); !ok) {
    png_image_free(&png);
    return make_error("PNG ", ok.error().message);
  }
  Image image(int(png.width), int(png.height));
  if (!png_image_finish_read(&png, nullptr, image.rgb.data(), 0, nullptr))
    return make_error("corrupted PNG: ", png.message);
  return image;
}

}  // namespace farfield
