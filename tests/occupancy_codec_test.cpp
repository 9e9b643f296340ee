// Paper 003, Sec. 3.1.2 and 3.2: visible-triangle sets as occupancy bit vectors, run-length and
// Huffman coded (the paper's) or as zstd-packed run lengths; both give back the set, the
// decoder stops once every visible triangle is found, and damage is refused.
#include "farfield/core/occupancy_codec.hpp"

#include <gtest/gtest.h>

#include <random>

namespace farfield {
namespace {

// About `share` of `triangles` visible, in runs as an ID buffer sees them (neighbouring
// triangles of one surface).
std::vector<uint32_t> visible_set(uint32_t triangles, double share, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<uint32_t> out;
  for (uint32_t t = 0; t < triangles;) {
    const uint32_t run = 1 + uint32_t(u(rng) * 20);
    if (u(rng) < share)
      for (uint32_t k = 0; k < run && t + k < triangles; ++k) out.push_back(t + k);
    t += run;
  }
  return out;
}

TEST(OccupancyCodec, BothCodecsGiveTheSetBack) {
  for (const auto codec : {OccupancyCodec::paper, OccupancyCodec::zstd})
    for (const double share : {0.0, 0.02, 0.3, 1.0}) {
      const uint32_t triangles = 100003;
      const std::vector<uint32_t> visible = visible_set(triangles, share, 7);
      OccupancySizes sizes;
      const Bytes data = encode_occupancy(visible, triangles, codec, &sizes);
      EXPECT_EQ(sizes.bit_vector, 12501u);
      EXPECT_EQ(sizes.encoded, data.size());
      std::vector<uint32_t> back;
      ASSERT_TRUE(decode_occupancy(data, triangles, back)) << int(codec) << " " << share;
      EXPECT_EQ(back, visible) << int(codec) << " " << share;
      if (share == 0.02) {  // sparse: both compress well below the bit vector
        EXPECT_LT(sizes.encoded * 4, sizes.bit_vector) << int(codec);
        if (codec == OccupancyCodec::paper) {
          EXPECT_LT(sizes.run_length, sizes.bit_vector);
        }
      }
    }
}

// Sec. 3.2: the decoder stops once it has every visible triangle; what follows (the zero
// runs up to the last triangle) is never read.
TEST(OccupancyCodec, DecodingStopsOnceEveryVisibleTriangleIsFound) {
  const std::vector<uint32_t> visible = {3, 4, 10, 77};
  const uint32_t triangles = 1000000;
  const Bytes data = encode_occupancy(visible, triangles, OccupancyCodec::paper);
  std::vector<uint32_t> back;
  const Bytes head(data.begin(), data.begin() + (data.size() - 20));
  ASSERT_TRUE(decode_occupancy(head, triangles, back));
  EXPECT_EQ(back, visible);
}

TEST(OccupancyCodec, DamageIsRefused) {
  const uint32_t triangles = 5000;
  const std::vector<uint32_t> visible = visible_set(triangles, 0.3, 3);
  std::vector<uint32_t> back;
  for (const auto codec : {OccupancyCodec::paper, OccupancyCodec::zstd}) {
    const Bytes data = encode_occupancy(visible, triangles, codec);
    auto other = decode_occupancy(data, triangles + 1, back);
    ASSERT_FALSE(other);
    EXPECT_NE(other.error().message.find("made for 5000 triangles"), std::string::npos);
    const Bytes cut(data.begin(), data.begin() + data.size() / 2);
    EXPECT_FALSE(decode_occupancy(cut, triangles, back)) << int(codec);
    Bytes more = data;
    more[5] = std::byte(uint8_t(more[5]) + 1);  // one more visible triangle than there is
    EXPECT_FALSE(decode_occupancy(more, triangles, back)) << int(codec);
  }
  EXPECT_FALSE(decode_occupancy(Bytes(5), triangles, back));
  Bytes unknown = encode_occupancy(visible, triangles, OccupancyCodec::zstd);
  unknown[0] = std::byte(9);
  EXPECT_FALSE(decode_occupancy(unknown, triangles, back));
}

}  // namespace
}  // namespace farfield
