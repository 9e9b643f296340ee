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

Image difference_image(const Image& a, const Image& b) {
  FF_ASSERT(a.width == b.width && a.height == b.height, "sizes %dx%d and %dx%d", a.width, a.height,
            b.width, b.height);
  Image d(a.width, a.height);
  for (size_t i = 0; i < d.rgb.size(); ++i)
    d.rgb[i] = static_cast<uint8_t>(std::clamp(128 + int(b.rgb[i]) - int(a.rgb[i]), 0, 255));
  return d;
}

}  // namespace farfield
