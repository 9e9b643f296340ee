// libFuzzer target for the .ffpack reader: the fuzzed bytes are written to a file, which
// Store::open reads read-only; an accepted pack then has every blob and meta entry read and is
// verified. A blob's checksum stops nearly every mutation of its bytes before the decoders, so
// the same bytes also go to the decoders directly, each with a small allocation bound.
//
// Seeds (fuzz/corpus/store): small.ffpack, written by Store (a zstd blob, a raw blob, a PNG
// and a JPEG image, two meta entries) and then shrunk with the sqlite3 shell
// (`PRAGMA page_size = 512; VACUUM;`); a zstd frame, a PNG and a JPEG on their own.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include <zstd.h>

#include "farfield/core/codec.hpp"
#include "farfield/store/store.hpp"

namespace {

constexpr uint64_t kMaxPixels = 1 << 20;
constexpr uint64_t kMaxRawBytes = 1 << 22;

const std::string& pack_path() {
  static const std::string path =
      (std::filesystem::temp_directory_path() /
       ("farfield-fuzz-store-" + std::to_string(::getpid()) + ".ffpack"))
          .string();
  return path;
}

void read_pack(const std::string& path) {
  using farfield::Codec;
  auto store = farfield::Store::open(path, farfield::Store::Mode::kRead);
  if (!store) return;
  uint64_t sum = 0;
  if (auto blobs = store->list(); blobs) {
    for (const farfield::BlobInfo& blob : *blobs) {
      if (blob.codec == Codec::kJpeg || blob.codec == Codec::kPng) {
        if (auto image = store->get_image(blob.name)) sum += image->rgb.size();
      } else if (auto bytes = store->get(blob.name)) {
        sum += bytes->size();
      }
      (void)store->contains(blob.name);
    }
  }
  if (auto meta = store->list_meta()) sum += meta->size();
  if (auto total = store->total_bytes()) sum += *total;
  (void)store->get_meta("scene.fingerprint");
  (void)store->verify();
  volatile uint64_t sink = sum;
  (void)sink;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = pack_path();
  if (FILE* file = std::fopen(path.c_str(), "wb")) {
    const bool written = std::fwrite(data, 1, size, file) == size;
    if (std::fclose(file) == 0 && written) read_pack(path);
  }
  // A fuzzed header may ask for WAL mode; a read-only open then leaves its side files.
  for (const char* suffix : {"", "-journal", "-wal", "-shm"}) ::unlink((path + suffix).c_str());

  const auto bytes = std::as_bytes(std::span(data, size));
  const unsigned long long declared = ZSTD_getFrameContentSize(data, size);
  (void)farfield::zstd_decompress(bytes, declared <= kMaxRawBytes ? declared : 0);
  (void)farfield::decode_jpeg(bytes, kMaxPixels);
  (void)farfield::decode_png(bytes, kMaxPixels);
  return 0;
}
