// libFuzzer target for visible-triangle streams (core/occupancy_codec.hpp, the hybrid bake's
// blobs): any bytes, for the triangle count their header names (at most 2^20, so that a
// crafted count costs no memory). An accepted stream gives as many triangles as its header
// says, ascending, each below the count.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "farfield/core/occupancy_codec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  if (size < 9) return 0;
  uint32_t triangles = 0, visible_count = 0;
  for (int i = 0; i < 4; ++i) triangles |= uint32_t(data[1 + i]) << (8 * i);
  for (int i = 0; i < 4; ++i) visible_count |= uint32_t(data[5 + i]) << (8 * i);
  if (triangles > (1u << 20)) return 0;
  std::vector<uint32_t> visible;
  if (!farfield::decode_occupancy(bytes, triangles, visible)) return 0;
  if (visible.size() != visible_count) std::abort();
  for (size_t k = 0; k < visible.size(); ++k)
    if (visible[k] >= triangles || (k > 0 && visible[k] <= visible[k - 1])) std::abort();
  return 0;
}
