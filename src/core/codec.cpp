#include "farfield/core/codec.hpp"

#include <memory>
#include <string>

#include <turbojpeg.h>
#include <zstd.h>

#include "farfield/core/assert.hpp"

namespace farfield {

namespace {

void check_image(const Image& image, const char* caller) {
  FF_ASSERT(image.width > 0 && image.height > 0 &&
                image.rgb.size() == size_t(image.width) * size_t(image.height) * 3,
            "%s: image %dx%d holds %zu bytes", caller, image.width, image.height, image.rgb.size());
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

namespace {

// One frame that declares `raw_size` bytes and nothing after it (trailing bytes mean the blob
// is not what was written): checked before anything is allocated for what it declares.
Result<void> check_zstd_frame(std::span<const std::byte> compressed, uint64_t raw_size) {
  const unsigned long long declared =
      ZSTD_getFrameContentSize(compressed.data(), compressed.size());
  if (declared == ZSTD_CONTENTSIZE_ERROR) return make_error("not zstd data (bad frame header)");
  if (declared == ZSTD_CONTENTSIZE_UNKNOWN)
    return make_error("zstd frame does not declare its size");
  if (declared != raw_size)
    return make_error("zstd frame declares ", std::to_string(declared), " bytes, expected ",
                      std::to_string(raw_size));
  const size_t frame = ZSTD_findFrameCompressedSize(compressed.data(), compressed.size());
  if (ZSTD_isError(frame)) return make_error("corrupted zstd data: ", ZSTD_getErrorName(frame));
  if (frame != compressed.size())
    return make_error("zstd data has ", std::to_string(compressed.size() - frame),
                      " bytes after its frame");
  return {};
}

Result<void> decompress_checked(std::span<const std::byte> compressed, std::span<std::byte> out) {
  const size_t size = ZSTD_decompress(out.data(), out.size(), compressed.data(), compressed.size());
  if (ZSTD_isError(size)) return make_error("corrupted zstd data: ", ZSTD_getErrorName(size));
  if (size != out.size())
    return make_error("zstd data holds ", std::to_string(size), " bytes, expected ",
                      std::to_string(out.size()));
  return {};
}

}  // namespace

Result<Bytes> zstd_decompress(std::span<const std::byte> compressed, uint64_t raw_size) {
  if (auto ok = check_zstd_frame(compressed, raw_size); !ok) return ok.error();
  Bytes out(raw_size);
  if (auto ok = decompress_checked(compressed, out); !ok) return ok.error();
  return out;
}

Result<void> zstd_decompress_into(std::span<const std::byte> compressed, std::span<std::byte> out) {
  if (auto ok = check_zstd_frame(compressed, out.size()); !ok) return ok;
  return decompress_checked(compressed, out);
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
  if (auto ok = check_image_size(uint64_t(width), uint64_t(height), max_pixels); !ok)
    return make_error("JPEG ", ok.error().message);
  Image image(width, height);
  // STOPONWARNING: a truncated stream is an error, not a grey lower half. LIMITSCANS: a
  // crafted progressive JPEG with thousands of scans fails instead of taking minutes.
  if (tjDecompress2(tj.get(), data, jpeg.size(), image.rgb.data(), width, 0, height, TJPF_RGB,
                    TJFLAG_ACCURATEDCT | TJFLAG_STOPONWARNING | TJFLAG_LIMITSCANS) != 0)
    return make_error("corrupted JPEG: ", tjGetErrorStr2(tj.get()));
  return image;
}

}  // namespace farfield
