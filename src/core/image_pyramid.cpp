#include "farfield/core/image_pyramid.hpp"

#include <algorithm>
#include <cmath>

#include "farfield/core/assert.hpp"

namespace farfield {

namespace {

constexpr int kOffset = 128;  // of a signed difference

void check_same(const Image& a, const Image& b) {
  FF_ASSERT(a.width == b.width && a.height == b.height, "images of %d x %d and %d x %d", a.width,
            a.height, b.width, b.height);
}

}  // namespace

Image box_downsample(const Image& image, int factor) {
  FF_ASSERT(factor >= 1 && image.width % factor == 0 && image.height % factor == 0,
            "box_downsample: %dx%d by %d", image.width, image.height, factor);
  Image out(image.width / factor, image.height / factor);
  const uint32_t area = uint32_t(factor * factor);
  std::vector<uint32_t> sums(size_t(out.width) * 3);
  for (int y = 0; y < out.height; ++y) {
    std::fill(sums.begin(), sums.end(), 0u);
    for (int dy = 0; dy < factor; ++dy) {
      const uint8_t* row = image.pixel(0, y * factor + dy);
      for (int x = 0; x < image.width; ++x)
        for (int c = 0; c < 3; ++c) sums[size_t(x / factor) * 3 + c] += row[size_t(x) * 3 + c];
    }
    uint8_t* to = out.pixel(0, y);
    for (size_t i = 0; i < sums.size(); ++i) to[i] = uint8_t((sums[i] + area / 2) / area);
  }
  return out;
}

Image reduced(const Image& fine, PyramidRule rule) {
  FF_ASSERT(fine.width % 2 == 0 && fine.height % 2 == 0, "halving an image of %d x %d", fine.width,
            fine.height);
  if (rule == PyramidRule::mean) return box_downsample(fine, 2);
  Image coarse(fine.width / 2, fine.height / 2);
  for (int y = 0; y < coarse.height; ++y)
    for (int x = 0; x < coarse.width; ++x)
      for (int c = 0; c < 3; ++c)  // paper 003, Eq. 1-3
        coarse.pixel(x, y)[c] =
            std::min({fine.pixel(2 * x, 2 * y)[c], fine.pixel(2 * x + 1, 2 * y)[c],
                      fine.pixel(2 * x, 2 * y + 1)[c], fine.pixel(2 * x + 1, 2 * y + 1)[c]});
  return coarse;
}

std::vector<Image> pyramid(const Image& level0, int levels, PyramidRule rule) {
  FF_ASSERT(levels >= 1 && level0.width % (1 << (levels - 1)) == 0 &&
                level0.height % (1 << (levels - 1)) == 0,
            "an image of %d x %d has no %d levels", level0.width, level0.height, levels);
  std::vector<Image> out{level0};
  for (int i = 1; i < levels; ++i) out.push_back(reduced(out.back(), rule));
  return out;
}

Image magnified(const Image& coarse, PyramidRule rule) {
  Image fine(2 * coarse.width, 2 * coarse.height);
  if (rule == PyramidRule::min) {
    for (int y = 0; y < fine.height; ++y)
      for (int x = 0; x < fine.width; ++x)
        std::copy_n(coarse.pixel(x / 2, y / 2), 3, fine.pixel(x, y));
    return fine;
  }
  // Fine pixel x samples the coarse image at (x + 0.5) / 2 - 0.5: a quarter and three
  // quarters of the two nearest texels, clamped at the edges.
  auto taps = [](int x, int size, int& a, int& b, float& wb) {
    const float at = (float(x) + 0.5f) * 0.5f - 0.5f;
    a = int(std::floor(at));
    wb = at - float(a);
    b = std::min(a + 1, size - 1);
    a = std::max(a, 0);
  };
  for (int y = 0; y < fine.height; ++y) {
    int y0, y1;
    float wy;
    taps(y, coarse.height, y0, y1, wy);
    for (int x = 0; x < fine.width; ++x) {
      int x0, x1;
      float wx;
      taps(x, coarse.width, x0, x1, wx);
      for (int c = 0; c < 3; ++c) {
        const float top = (1 - wx) * coarse.pixel(x0, y0)[c] + wx * coarse.pixel(x1, y0)[c];
        const float bottom = (1 - wx) * coarse.pixel(x0, y1)[c] + wx * coarse.pixel(x1, y1)[c];
        fine.pixel(x, y)[c] = uint8_t(std::lround((1 - wy) * top + wy * bottom));
      }
    }
  }
  return fine;
}

Image difference(const Image& fine, const Image& magnified, PyramidRule rule) {
  check_same(fine, magnified);
  const int offset = rule == PyramidRule::mean ? kOffset : 0;
  Image d(fine.width, fine.height);
  for (size_t i = 0; i < d.rgb.size(); ++i)
    d.rgb[i] = uint8_t(std::clamp(int(fine.rgb[i]) - int(magnified.rgb[i]) + offset, 0, 255));
  return d;
}

Image accumulated(const Image& magnified, const Image& difference, PyramidRule rule) {
  check_same(magnified, difference);
  const int offset = rule == PyramidRule::mean ? kOffset : 0;
  Image fine(magnified.width, magnified.height);
  for (size_t i = 0; i < fine.rgb.size(); ++i)
    fine.rgb[i] =
        uint8_t(std::clamp(int(magnified.rgb[i]) + int(difference.rgb[i]) - offset, 0, 255));
  return fine;
}

}  // namespace farfield
