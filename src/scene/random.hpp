// Deterministic random numbers for the generators: the same seed draws the same numbers on
// every platform and standard library (std::uniform_*_distribution are implementation-defined,
// so they are not used). Private to src/scene.
#pragma once

#include <cstddef>
#include <cstdint>

namespace farfield::detail {

// Advances `state` and returns the next splitmix64 number (Steele, Lea and Flood).
inline uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// xoshiro256** (Blackman and Vigna), seeded through splitmix64.
class Rng {
 public:
  explicit Rng(uint64_t seed) {
    for (uint64_t& word : s_) word = splitmix64(seed);
  }
  uint64_t next() {
    const uint64_t result = rotl(s_[1] * 5, 7) * 9, t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  // Uniform in [0, 1), 53 bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  // Uniform in [lo, hi), rounded to float.
  float uniform(double lo, double hi) { return static_cast<float>(lo + (hi - lo) * uniform()); }
  bool chance(double p) { return uniform() < p; }
  // Uniform integer in [lo, hi] by multiply-shift (bias below 2^-32 * span: immaterial here).
  uint32_t range(uint32_t lo, uint32_t hi) {
    const uint64_t span = uint64_t(hi) - lo + 1;
    return lo + static_cast<uint32_t>(((next() >> 32) * span) >> 32);
  }
  template <class T, size_t N>
  const T& pick(const T (&items)[N]) {
    return items[range(0, N - 1)];
  }

 private:
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t s_[4];
};

}  // namespace farfield::detail
