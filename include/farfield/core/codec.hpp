// In-memory codecs of the .ffpack store (docs/ffpack.md): zstd for bytes, JPEG (libturbojpeg)
// and PNG (libpng) for images. Pure functions, safe to call from any thread.
//
// Decoders take the size they expect, or a bound, and check the stream's own header against it
// before allocating, so a corrupted or crafted stream cannot make them allocate more than the
// caller allowed. Their error messages say what is wrong but not where the bytes came from:
// the caller prefixes the file and blob name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "farfield/core/image.hpp"
#include "farfield/core/result.hpp"

namespace farfield {

using Bytes = std::vector<std::byte>;

// zstd at `level` (1..19; 3 is zstd's default, fast with a fair ratio). The frame records the
// uncompressed size, which zstd_decompress checks.
Bytes zstd_compress(std::span<const std::byte> bytes, int level = 3);
// Fails unless `compressed` is exactly one zstd frame that declares and holds `raw_size` bytes.
Result<Bytes> zstd_decompress(std::span<const std::byte> compressed, uint64_t raw_size);
// The same into `out`, whose size is the raw size expected (memory a caller reuses: a fresh
// buffer costs a page fault a page).
Result<void> zstd_decompress_into(std::span<const std::byte> compressed, std::span<std::byte> out);

// Baseline JPEG of quality 1..100. Chroma is subsampled 4:2:0 below quality 90 and kept whole
// (4:4:4) from 90 up, where subsampling's colour bleeding would dominate the error.
Result<Bytes> encode_jpeg(const Image& image, int quality);
// Any JPEG libjpeg-turbo reads (grey, CMYK converted to RGB); a warning such as a truncated
// stream is an error rather than a half-grey image.
Result<Image> decode_jpeg(std::span<const std::byte> jpeg, uint64_t max_pixels = kMaxImagePixels);

// PNG: encode_png and decode_png of core/image.hpp.

}  // namespace farfield
