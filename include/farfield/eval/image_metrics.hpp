// Image error against a reference frame (DESIGN.md, benchmark protocol).
#pragma once

#include <cstdint>

#include "farfield/core/image.hpp"

namespace farfield {

struct ImageComparison {
  uint64_t differing_pixels = 0;  // pixels where any channel differs
  double mse = 0.0;               // mean squared error over RGB, in 8-bit units squared
  double psnr_db = 0.0;           // 10 log10(255^2 / mse); infinite when identical
  bool identical() const { return differing_pixels == 0; }
};

// The images must have the same size (an assertion: the caller renders both).
ImageComparison compare_images(const Image& reference, const Image& test);

// Paper 000, Fig. 6-5: per channel, test - reference added to 128 (neutral grey), clamped.
Image difference_image(const Image& reference, const Image& test);

}  // namespace farfield
