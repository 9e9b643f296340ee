#include "farfield/scene/texture_sampler.hpp"

#include <algorithm>
#include <cmath>

namespace farfield {

namespace {

// The next level: each texel the mean of the (up to) 2 x 2 texels it covers.
Texels halve(const Texels& in) {
  Texels out(std::max(1, in.width / 2), std::max(1, in.height / 2));
  const int fx = in.width > 1 ? 2 : 1, fy = in.height > 1 ? 2 : 1;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 4; ++c) {
        int sum = 0;
        for (int dy = 0; dy < fy; ++dy)
          for (int dx = 0; dx < fx; ++dx) sum += in.texel(x * fx + dx, y * fy + dy)[c];
        out.texel(x, y)[c] = uint8_t((sum + fx * fy / 2) / (fx * fy));
      }
  return out;
}

}  // namespace

float wrap_texture_coordinate(float t, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::repeat:
      return t - std::floor(t);
    case TextureWrap::mirror:
      return 1.0f - std::abs(std::fmod(std::abs(t), 2.0f) - 1.0f);
    default:
      return std::clamp(t, 0.0f, 1.0f);
  }
}

TextureSampler::TextureSampler(Texels top) {
  levels_.push_back(std::move(top));
  while (levels_.back().width > 1 || levels_.back().height > 1)
    levels_.push_back(halve(levels_.back()));
}

glm::vec4 TextureSampler::sample(glm::vec2 uv, float footprint, TextureWrap wrap_u,
                                 TextureWrap wrap_v) const {
  const int level = footprint > 1.0f && std::isfinite(footprint)
                        ? std::min(int(levels_.size()) - 1, int(std::lround(std::log2(footprint))))
                        : 0;
  const Texels& t = levels_[size_t(level)];
  const float u = wrap_texture_coordinate(uv.x, wrap_u), v = wrap_texture_coordinate(uv.y, wrap_v);
  const int x = std::clamp(int(u * float(t.width)), 0, t.width - 1);
  const int y = std::clamp(int(v * float(t.height)), 0, t.height - 1);
  const uint8_t* texel = t.texel(x, y);
  return glm::vec4(texel[0], texel[1], texel[2], texel[3]) / 255.0f;
}

Result<std::vector<TextureSampler>> scene_texture_samplers(const Scene& scene) {
  std::vector<TextureSampler> samplers;
  samplers.reserve(scene.textures.size());
  for (const Texture& texture : scene.textures) {
    auto texels = decode_texture(texture);
    if (!texels) return texels.error();
    samplers.emplace_back(std::move(*texels));
  }
  return samplers;
}

}  // namespace farfield
