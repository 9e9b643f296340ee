// A viewpoint's visible triangles as paper 003 stores them (Sec. 3.1.2): an occupancy bit
// vector, bit t set when triangle t is visible, compressed by one of two codecs:
//  - paper: run-length coding of the vector's bytes (a run of zero bytes becomes 0x00 and its
//    length, up to 255; other bytes stay as they are), then Huffman coding of the result
//    (canonical codes, at most 24 bits, their lengths in the header);
//  - zstd: the lengths of the vector's alternating runs of 0 and 1 bits (LEB128), then zstd.
// Decoding stops once every visible triangle has been found (Sec. 3.2: the header holds
// their number), and refuses a stream that is truncated, names triangles past the count, or
// decodes to another number of them.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "farfield/core/codec.hpp"
#include "farfield/core/result.hpp"

namespace farfield {

enum class OccupancyCodec : uint8_t { paper = 1, zstd = 2 };

// What each stage left, bytes (paper 003, Table 3: the run-length ratio is bit_vector /
// run_length, the Huffman ratio run_length / encoded, the total bit_vector / encoded).
struct OccupancySizes {
  uint64_t bit_vector = 0;  // ceil(triangles / 8)
  uint64_t run_length = 0;  // paper: the run-length coded bytes; zstd: the LEB128 run lengths
  uint64_t encoded = 0;     // the whole stream, header included
};

// `visible`: ascending, each below `triangles`.
Bytes encode_occupancy(std::span<const uint32_t> visible, uint32_t triangles,
                       OccupancyCodec codec, OccupancySizes* sizes = nullptr);
// Replaces `visible` with the triangles of `data` (ascending); `triangles` must be the count
// the stream was made for.
Result<void> decode_occupancy(std::span<const std::byte> data, uint32_t triangles,
                              std::vector<uint32_t>& visible);

}  // namespace farfield
