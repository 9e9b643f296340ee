// How much a representation's image looks like the full object's, in [0, 1] (1: the same),
// for the clusters technique's accuracy tables (paper 001, Sec. 3.2), two ways:
//  - edge_similarity: the paper's comparator. Both images to grey (the mean of R, G, B: "the
//    achromatic channel ... most important for shape recognition"), convolved with a 5x5
//    Laplacian, its zero crossings marked as edges, the edge maps blurred ("increases the
//    chances of matching"), then compared pixel by pixel: 1 - sum |a - b| / (sum a + sum b).
//    blur_radius 0 is the plain pixel compare of the edge maps the paper avoids.
//  - structural_similarity: the mean SSIM of the grey images (Wang, Bovik, Sheikh and
//    Simoncelli, IEEE TIP 2004) over 8 x 8 windows every 4 pixels, the usual constants
//    (0.01 and 0.03 of 255): tone, contrast and structure together, so that a representation
//    of the right shape in the wrong colour also loses.
// The images must have the same size.
#pragma once

#include <cstdint>
#include <span>

#include "farfield/core/image.hpp"

namespace farfield {

struct EdgeSimilarityOptions {
  int blur_radius = 2;           // pixels of the box blur of the edge maps; 0: none
  float crossing_contrast = 16;  // a sign change of the Laplacian counts where |a - b| > this
};

double edge_similarity(const Image& a, const Image& b, const EdgeSimilarityOptions& options = {});
double structural_similarity(const Image& a, const Image& b);
// The same over the windows that hold a pixel of `mask` (one byte a pixel, non-zero: in),
// so that a background both images share does not count; 1 where no window does.
double structural_similarity(const Image& a, const Image& b, std::span<const uint8_t> mask);

}  // namespace farfield
