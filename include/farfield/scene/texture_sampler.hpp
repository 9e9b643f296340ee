// A texture sampled on the CPU as the GPU samples a scene texture, for bakes that rasterise
// on the CPU (colour-cube leaves): a box-filtered mip chain, the level whose texels match the
// footprint of the bake's pixel, the nearest texel there, wrap modes as the shader applies
// them (repeat, mirror, clamp).
#pragma once

#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/scene/texture_image.hpp"

namespace farfield {

class TextureSampler {
 public:
  explicit TextureSampler(Texels top);
  // RGBA in [0, 1] at `uv` (glTF's origin: (0, 0) is the top-left texel); `footprint` is the
  // pixel's extent in texels of the top level (<= 1: the top level).
  glm::vec4 sample(glm::vec2 uv, float footprint, TextureWrap wrap_u, TextureWrap wrap_v) const;
  int width() const { return levels_.front().width; }
  int height() const { return levels_.front().height; }

 private:
  std::vector<Texels> levels_;  // top first, each half the one before (at least 1 x 1)
};

// The scene's textures decoded, one sampler each, in order; refused naming the texture that
// does not decode.
Result<std::vector<TextureSampler>> scene_texture_samplers(const Scene& scene);

// A texture coordinate repeated, mirrored or clamped into [0, 1] (the scene shader's rule).
float wrap_texture_coordinate(float t, TextureWrap wrap);

}  // namespace farfield
