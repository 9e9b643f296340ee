#include "farfield/eval/image_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "farfield/core/assert.hpp"

namespace farfield {

ImageComparison compare_images(const Image& a, const Image& b) {
  FF_ASSERT(a.width == b.width && a.height == b.height, "sizes %dx%d and %dx%d", a.width, a.height,
            b.width, b.height);
  ImageComparison c;
  uint64_t squared = 0;
  const size_t pixels = size_t(a.width) * size_t(a.height);
  for (size_t p = 0; p < pixels; ++p) {
    const uint8_t* x = a.rgb.data() + 3 * p;
    const uint8_t* y = b.rgb.data() + 3 * p;
    bool differs = false;
    for (int ch = 0; ch < 3; ++ch) {
      const int d = int(x[ch]) - int(y[ch]);
      squared += uint64_t(d * d);
      differs |= d != 0;
    }
    c.differing_pixels += differs;
  }
  c.mse = pixels ? double(squared) / double(3 * pixels) : 0.0;
  c.psnr_db = c.mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / c.mse)
                          : std::numeric_limits<double>::infinity();
  return c;
}

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

Image difference_image(const Image& a, const Image& b) {
  FF_ASSERT(a.width == b.width && a.height == b.height, "sizes %dx%d and %dx%d", a.width, a.height,
            b.width, b.height);
  Image d(a.width, a.height);
  for (size_t i = 0; i < d.rgb.size(); ++i)
    d.rgb[i] = static_cast<uint8_t>(std::clamp(128 + int(b.rgb[i]) - int(a.rgb[i]), 0, 255));
  return d;
}

}  // namespace farfield
