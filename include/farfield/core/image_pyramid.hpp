// The multi-level images of paper 003, Sec. 2.2: level i + 1 is level i at half the
// resolution, and level i is stored as its difference from level i + 1 magnified (D_i = I_i -
// T_i, Step 4), so that a viewer adds the differences up to the level it wants.
// Two rules for the half resolution:
//  - min (the paper's, Eq. 1-3): the minimum of each 2 x 2 block per channel, magnified by
//    repeating each texel in its block (nearest), the one magnification under which the
//    minimum keeps D_i >= 0 (the paper magnifies by texture mapping; bilinear magnification
//    mixes in neighbouring blocks' minima, which can exceed a pixel);
//  - mean: the block's mean, magnified bilinearly (texel centres, clamped at the edges, as a
//    GL texture is sampled), D_i signed and stored offset by 128. Measured on a tree and a city
//    view at JPEG quality 80: 1.20-1.23x the storage of the level-0 image alone where min takes
//    1.28-1.35x, and 30.1-30.7 dB against 27.5-28.5.
#pragma once

#include <cstdint>
#include <vector>

#include "farfield/core/image.hpp"

namespace farfield {

enum class PyramidRule : uint8_t { min, mean };

// Each `factor` x `factor` block of `image` averaged into one pixel (rounded to nearest): also
// a frame drawn at `factor` times the width and height resolved as a box-filtered supersampled
// one (bench's antialiased reference). The sides must be multiples of `factor`.
Image box_downsample(const Image& image, int factor);
// Half the resolution by `rule` (mean: box_downsample by 2); the sides must be even.
Image reduced(const Image& fine, PyramidRule rule);
// I_0 .. I_{levels - 1}; `level0`'s sides must be divisible by 2^(levels - 1).
std::vector<Image> pyramid(const Image& level0, int levels, PyramidRule rule);
// T: `coarse` at twice the resolution, as the rule magnifies.
Image magnified(const Image& coarse, PyramidRule rule);
// D = fine - magnified, per channel: min clamped at 0, mean offset by 128 and clamped.
Image difference(const Image& fine, const Image& magnified, PyramidRule rule);
// magnified + difference, saturating: the inverse of difference().
Image accumulated(const Image& magnified, const Image& difference, PyramidRule rule);

}  // namespace farfield
