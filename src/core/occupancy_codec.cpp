#include "farfield/core/occupancy_codec.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <queue>
#include <string>

#include "farfield/core/assert.hpp"

namespace farfield {

namespace {

constexpr int kMaxCodeBits = 24;
constexpr size_t kHeaderBytes = 1 + 4 + 4;  // codec, triangles, visible

void put_u32(Bytes& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(std::byte(v >> (8 * i)));
}
uint32_t get_u32(std::span<const std::byte> in, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= uint32_t(in[at + i]) << (8 * i);
  return v;
}

std::vector<uint8_t> bit_vector(std::span<const uint32_t> visible, uint32_t triangles) {
  std::vector<uint8_t> bits((size_t(triangles) + 7) / 8, 0);
  for (uint32_t t : visible) {
    FF_ASSERT(t < triangles, "visible triangle %u of %u", t, triangles);
    bits[t / 8] |= uint8_t(1u << (t % 8));
  }
  return bits;
}

std::vector<uint8_t> run_length(const std::vector<uint8_t>& bytes) {
  std::vector<uint8_t> out;
  for (size_t i = 0; i < bytes.size();) {
    if (bytes[i] != 0) {
      out.push_back(bytes[i++]);
      continue;
    }
    size_t run = 0;
    while (i < bytes.size() && bytes[i] == 0 && run < 255) ++i, ++run;
    out.push_back(0);
    out.push_back(uint8_t(run));
  }
  return out;
}

// Huffman code lengths of the 256 symbols (0: absent), at most kMaxCodeBits: where the tree
// grows deeper, the counts are halved (rounding up, so none vanishes) and it is built again.
std::array<uint8_t, 256> code_lengths(std::array<uint64_t, 256> counts) {
  std::array<uint8_t, 256> lengths{};
  for (;;) {
    struct Node {  // the leaves first (their symbols in symbol_of), then the joins
      uint64_t count;
      int left, right;  // children; -1 for a leaf
    };
    std::vector<Node> nodes;
    std::vector<int> symbol_of;
    using Entry = std::pair<uint64_t, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap;
    for (int s = 0; s < 256; ++s)
      if (counts[s] > 0) {
        heap.push({counts[s], int(nodes.size())});
        nodes.push_back({counts[s], -1, -1});
        symbol_of.push_back(s);
      }
    lengths.fill(0);
    if (nodes.empty()) return lengths;
    if (nodes.size() == 1) {
      lengths[size_t(symbol_of[0])] = 1;
      return lengths;
    }
    while (heap.size() > 1) {
      const auto [ca, a] = heap.top();
      heap.pop();
      const auto [cb, b] = heap.top();
      heap.pop();
      heap.push({ca + cb, int(nodes.size())});
      nodes.push_back({ca + cb, a, b});
    }
    // Depths from the root (the last node) down.
    std::vector<int> depth(nodes.size(), 0);
    int deepest = 0;
    for (int n = int(nodes.size()) - 1; n >= 0; --n)
      if (nodes[size_t(n)].left >= 0) {
        depth[size_t(nodes[size_t(n)].left)] = depth[size_t(n)] + 1;
        depth[size_t(nodes[size_t(n)].right)] = depth[size_t(n)] + 1;
      } else {
        deepest = std::max(deepest, depth[size_t(n)]);
      }
    if (deepest <= kMaxCodeBits) {
      for (size_t leaf = 0; leaf < symbol_of.size(); ++leaf)
        lengths[size_t(symbol_of[leaf])] = uint8_t(depth[leaf]);
      return lengths;
    }
    for (uint64_t& c : counts)
      if (c > 0) c = (c + 1) / 2;
  }
}

// Canonical codes: symbols by (length, symbol), consecutive codes within a length.
struct Canonical {
  std::array<uint32_t, 256> code{};
  std::array<uint32_t, kMaxCodeBits + 2> first{}, count{}, offset{};
  std::vector<uint8_t> sorted;  // symbols by (length, symbol)
};
Canonical canonical(const std::array<uint8_t, 256>& lengths) {
  Canonical c;
  for (int len = 1; len <= kMaxCodeBits; ++len)
    for (int s = 0; s < 256; ++s)
      if (lengths[size_t(s)] == len) {
        c.sorted.push_back(uint8_t(s));
        ++c.count[size_t(len)];
      }
  uint32_t code = 0, offset = 0;
  for (int len = 1; len <= kMaxCodeBits; ++len) {
    c.first[size_t(len)] = code;
    c.offset[size_t(len)] = offset;
    code = (code + c.count[size_t(len)]) << 1;
    offset += c.count[size_t(len)];
  }
  std::array<uint32_t, kMaxCodeBits + 2> next = c.first;
  for (uint8_t s : c.sorted) c.code[s] = next[lengths[s]]++;
  return c;
}

void put_varint(std::vector<uint8_t>& out, uint64_t v) {
  while (v >= 0x80) {
    out.push_back(uint8_t(v | 0x80));
    v >>= 7;
  }
  out.push_back(uint8_t(v));
}

Result<void> corrupt(const char* what) {
  return make_error("visible-triangle stream: ", what);
}

}  // namespace

Bytes encode_occupancy(std::span<const uint32_t> visible, uint32_t triangles,
                       OccupancyCodec codec, OccupancySizes* sizes) {
  FF_ASSERT(std::is_sorted(visible.begin(), visible.end()), "visible triangles not ascending");
  Bytes out;
  out.push_back(std::byte(codec));
  put_u32(out, triangles);
  put_u32(out, uint32_t(visible.size()));
  OccupancySizes s;
  s.bit_vector = (uint64_t(triangles) + 7) / 8;
  if (codec == OccupancyCodec::paper) {
    const std::vector<uint8_t> rle = run_length(bit_vector(visible, triangles));
    s.run_length = rle.size();
    std::array<uint64_t, 256> counts{};
    for (uint8_t b : rle) ++counts[b];
    const std::array<uint8_t, 256> lengths = code_lengths(counts);
    const Canonical c = canonical(lengths);
    put_u32(out, uint32_t(rle.size()));
    for (uint8_t len : lengths) out.push_back(std::byte(len));
    uint64_t buffer = 0;
    int bits = 0;
    for (uint8_t b : rle) {
      buffer = (buffer << lengths[b]) | c.code[b];
      bits += lengths[b];
      while (bits >= 8) {
        out.push_back(std::byte(uint8_t(buffer >> (bits - 8))));
        bits -= 8;
      }
    }
    if (bits > 0) out.push_back(std::byte(uint8_t(buffer << (8 - bits))));
  } else {
    std::vector<uint8_t> runs;  // alternating runs of 0 and 1 bits, zeros first
    uint32_t at = 0;
    for (size_t k = 0; k < visible.size();) {
      size_t end = k + 1;
      while (end < visible.size() && visible[end] == visible[end - 1] + 1) ++end;
      put_varint(runs, visible[k] - at);
      put_varint(runs, end - k);
      at = visible[end - 1] + 1;
      k = end;
    }
    s.run_length = runs.size();
    const Bytes packed = zstd_compress(std::as_bytes(std::span(runs)), 19);
    put_u32(out, uint32_t(runs.size()));
    out.insert(out.end(), packed.begin(), packed.end());
  }
  s.encoded = out.size();
  if (sizes) *sizes = s;
  return out;
}

Result<void> decode_occupancy(std::span<const std::byte> data, uint32_t triangles,
                              std::vector<uint32_t>& visible) {
  visible.clear();
  if (data.size() < kHeaderBytes + 4) return corrupt("shorter than its header");
  const auto codec = OccupancyCodec(uint8_t(data[0]));
  if (get_u32(data, 1) != triangles)
    return corrupt(("made for " + std::to_string(get_u32(data, 1)) + " triangles, not " +
                    std::to_string(triangles))
                       .c_str());
  const uint32_t wanted = get_u32(data, 5);
  if (wanted > triangles) return corrupt("more visible triangles than triangles");
  const uint32_t raw = get_u32(data, 9);
  visible.reserve(wanted);
  // Paper 003, Sec. 3.2: stop as soon as every visible triangle has been found.
  auto add_byte = [&](size_t index, uint8_t byte) {
    for (int bit = 0; bit < 8 && byte != 0; ++bit, byte >>= 1)
      if (byte & 1) visible.push_back(uint32_t(index * 8 + size_t(bit)));
  };
  if (codec == OccupancyCodec::paper) {
    if (data.size() < kHeaderBytes + 4 + 256) return corrupt("shorter than its code table");
    std::array<uint8_t, 256> lengths;
    for (size_t s = 0; s < 256; ++s) lengths[s] = uint8_t(data[kHeaderBytes + 4 + s]);
    if (std::any_of(lengths.begin(), lengths.end(), [](uint8_t l) { return l > kMaxCodeBits; }))
      return corrupt("a code longer than 24 bits");
    const Canonical c = canonical(lengths);
    size_t at = kHeaderBytes + 4 + 256;
    int bit = 7;
    auto next_symbol = [&](int& symbol) {
      uint32_t code = 0;
      for (int len = 1; len <= kMaxCodeBits; ++len) {
        if (at >= data.size()) return false;
        code = (code << 1) | ((uint8_t(data[at]) >> bit) & 1u);
        if (--bit < 0) bit = 7, ++at;
        if (code - c.first[size_t(len)] < c.count[size_t(len)]) {
          symbol = c.sorted[c.offset[size_t(len)] + code - c.first[size_t(len)]];
          return true;
        }
      }
      return false;
    };
    size_t byte_index = 0;
    for (uint32_t read = 0; read < raw && visible.size() < wanted;) {
      int symbol = 0;
      if (!next_symbol(symbol)) return corrupt("truncated or not Huffman coded");
      ++read;
      if (symbol != 0) {
        add_byte(byte_index++, uint8_t(symbol));
        continue;
      }
      if (read >= raw || !next_symbol(symbol)) return corrupt("a zero run without its length");
      ++read;
      byte_index += size_t(symbol);
    }
  } else if (codec == OccupancyCodec::zstd) {
    auto runs = zstd_decompress(data.subspan(kHeaderBytes + 4), raw);
    if (!runs) return corrupt(runs.error().message.c_str());
    size_t at = 0;
    auto varint = [&](uint64_t& v) {
      v = 0;
      for (int shift = 0; shift < 64 && at < runs->size(); shift += 7) {
        const uint8_t b = uint8_t((*runs)[at++]);
        v |= uint64_t(b & 0x7f) << shift;
        if (!(b & 0x80)) return true;
      }
      return false;
    };
    uint64_t position = 0;
    while (visible.size() < wanted) {
      uint64_t zeros, ones;
      if (!varint(zeros) || !varint(ones)) return corrupt("truncated run lengths");
      position += zeros;
      if (ones == 0 || position + ones > triangles) return corrupt("a run past the triangles");
      for (uint64_t k = 0; k < ones && visible.size() < wanted; ++k)
        visible.push_back(uint32_t(position + k));
      position += ones;
    }
  } else {
    return corrupt("unknown codec");
  }
  if (visible.size() != wanted) return corrupt("fewer visible triangles than its header says");
  if (!visible.empty() && visible.back() >= triangles) return corrupt("a triangle past the count");
  return {};
}

}  // namespace farfield
