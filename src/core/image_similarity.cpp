#include "farfield/core/image_similarity.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "farfield/core/assert.hpp"

namespace farfield {

namespace {

std::vector<float> grey(const Image& image) {
  std::vector<float> out(size_t(image.width) * size_t(image.height));
  for (size_t p = 0; p < out.size(); ++p) {
    const uint8_t* c = image.rgb.data() + 3 * p;
    out[p] = (float(c[0]) + float(c[1]) + float(c[2])) / 3.0f;
  }
  return out;
}

// Paper 001, Sec. 3.2: the 5x5 Laplacian (of a Gaussian), edges clamped.
std::vector<float> laplacian(const std::vector<float>& g, int w, int h) {
  static constexpr float kKernel[5][5] = {{0, 0, -1, 0, 0},
                                          {0, -1, -2, -1, 0},
                                          {-1, -2, 16, -2, -1},
                                          {0, -1, -2, -1, 0},
                                          {0, 0, -1, 0, 0}};
  std::vector<float> out(g.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float sum = 0.0f;
      for (int j = -2; j <= 2; ++j)
        for (int i = -2; i <= 2; ++i) {
          const int sx = std::clamp(x + i, 0, w - 1), sy = std::clamp(y + j, 0, h - 1);
          sum += kKernel[j + 2][i + 2] * g[size_t(sy) * w + sx];
        }
      out[size_t(y) * w + x] = sum;
    }
  return out;
}

// 1 where the Laplacian changes sign towards the right or lower neighbour by more than
// `contrast`, else 0.
std::vector<float> zero_crossings(const std::vector<float>& l, int w, int h, float contrast) {
  std::vector<float> out(l.size(), 0.0f);
  auto crosses = [&](float a, float b) { return a * b < 0.0f && std::abs(a - b) > contrast; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v = l[size_t(y) * w + x];
      if ((x + 1 < w && crosses(v, l[size_t(y) * w + x + 1])) ||
          (y + 1 < h && crosses(v, l[size_t(y + 1) * w + x])))
        out[size_t(y) * w + x] = 1.0f;
    }
  return out;
}

// A box blur of radius r, separable (rows then columns), edges clamped.
std::vector<float> box_blur(const std::vector<float>& in, int w, int h, int r) {
  if (r <= 0) return in;
  std::vector<float> rows(in.size()), out(in.size());
  const float scale = 1.0f / float(2 * r + 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float sum = 0.0f;
      for (int i = -r; i <= r; ++i) sum += in[size_t(y) * w + std::clamp(x + i, 0, w - 1)];
      rows[size_t(y) * w + x] = sum * scale;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float sum = 0.0f;
      for (int j = -r; j <= r; ++j) sum += rows[size_t(std::clamp(y + j, 0, h - 1)) * w + x];
      out[size_t(y) * w + x] = sum * scale;
    }
  return out;
}

}  // namespace

double edge_similarity(const Image& a, const Image& b, const EdgeSimilarityOptions& o) {
  FF_ASSERT(a.width == b.width && a.height == b.height, "sizes %dx%d and %dx%d", a.width, a.height,
            b.width, b.height);
  const int w = a.width, h = a.height;
  if (w == 0 || h == 0) return 1.0;
  auto edges = [&](const Image& image) {
    return box_blur(zero_crossings(laplacian(grey(image), w, h), w, h, o.crossing_contrast), w, h,
                    o.blur_radius);
  };
  const std::vector<float> ea = edges(a), eb = edges(b);
  double difference = 0.0, total = 0.0;
  for (size_t p = 0; p < ea.size(); ++p) {
    difference += std::abs(double(ea[p]) - double(eb[p]));
    total += double(ea[p]) + double(eb[p]);
  }
  return total > 0.0 ? 1.0 - difference / total : 1.0;  // no edges in either: alike
}

double structural_similarity(const Image& a, const Image& b) {
  return structural_similarity(a, b, {});
}

double structural_similarity(const Image& a, const Image& b, std::span<const uint8_t> mask) {
  FF_ASSERT(a.width == b.width && a.height == b.height, "sizes %dx%d and %dx%d", a.width, a.height,
            b.width, b.height);
  FF_ASSERT(mask.empty() || mask.size() == size_t(a.width) * size_t(a.height),
            "a mask of %zu pixels for %dx%d", mask.size(), a.width, a.height);
  const int w = a.width, h = a.height;
  constexpr int kWindow = 8, kStep = 4;
  constexpr double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
  const std::vector<float> ga = grey(a), gb = grey(b);
  double sum = 0.0;
  int windows = 0;
  const int wx = std::max(1, std::min(kWindow, w)), wy = std::max(1, std::min(kWindow, h));
  for (int y0 = 0; y0 + wy <= h; y0 += kStep)
    for (int x0 = 0; x0 + wx <= w; x0 += kStep) {
      if (!mask.empty()) {
        bool any = false;
        for (int y = y0; y < y0 + wy && !any; ++y)
          for (int x = x0; x < x0 + wx && !any; ++x) any = mask[size_t(y) * w + x] != 0;
        if (!any) continue;
      }
      double ma = 0, mb = 0, vaa = 0, vbb = 0, vab = 0;
      const double n = double(wx) * double(wy);
      for (int y = y0; y < y0 + wy; ++y)
        for (int x = x0; x < x0 + wx; ++x) {
          ma += ga[size_t(y) * w + x];
          mb += gb[size_t(y) * w + x];
        }
      ma /= n;
      mb /= n;
      for (int y = y0; y < y0 + wy; ++y)
        for (int x = x0; x < x0 + wx; ++x) {
          const double da = ga[size_t(y) * w + x] - ma, db = gb[size_t(y) * w + x] - mb;
          vaa += da * da;
          vbb += db * db;
          vab += da * db;
        }
      vaa /= n;
      vbb /= n;
      vab /= n;
      sum += ((2 * ma * mb + c1) * (2 * vab + c2)) / ((ma * ma + mb * mb + c1) * (vaa + vbb + c2));
      ++windows;
    }
  return windows ? sum / windows : 1.0;
}

}  // namespace farfield
