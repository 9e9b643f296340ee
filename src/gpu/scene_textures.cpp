#include "scene_textures.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>

#include "farfield/scene/texture_image.hpp"

namespace farfield::gpu {

namespace {

// Texels resampled to side x side: the mean of the source texels each target texel covers
// (box filter) along an axis that shrinks, the source texel under the target's centre along
// one that grows (so a small power-of-two texture keeps its texels exactly; the GPU's
// magnification filter smooths them when drawn).
RgbaImage resample(const RgbaImage& in, int side) {
  if (in.width == side && in.height == side) return in;
  RgbaImage out(side, side);
  const double sx = double(in.width) / side, sy = double(in.height) / side;
  for (int y = 0; y < side; ++y) {
    for (int x = 0; x < side; ++x) {
      double sum[4] = {0, 0, 0, 0};
      // Source ranges [x0, x1) and [y0, y1): a footprint, or the one texel under the centre.
      const int x0 = sx > 1.0 ? int(x * sx) : std::min(int((x + 0.5) * sx), in.width - 1);
      const int x1 = sx > 1.0 ? std::max(x0 + 1, int(std::ceil((x + 1) * sx))) : x0 + 1;
      const int y0 = sy > 1.0 ? int(y * sy) : std::min(int((y + 0.5) * sy), in.height - 1);
      const int y1 = sy > 1.0 ? std::max(y0 + 1, int(std::ceil((y + 1) * sy))) : y0 + 1;
      int n = 0;
      for (int v = y0; v < std::min(y1, in.height); ++v)
        for (int u = x0; u < std::min(x1, in.width); ++u, ++n)
          for (int c = 0; c < 4; ++c) sum[c] += in.texel(u, v)[c];
      for (double& s : sum) s /= std::max(n, 1);
      for (int c = 0; c < 4; ++c) out.texel(x, y)[c] = uint8_t(std::lround(sum[c]));
    }
  }
  return out;
}

int array_of_side(int side) {
  return std::countr_zero(unsigned(side / kMinArraySide));
}

}  // namespace

Result<SceneTextures> SceneTextures::create(const Scene& scene, int max_side) {
  SceneTextures out;
  const int limit = std::clamp(int(std::bit_floor(unsigned(std::max(max_side, kMinArraySide)))),
                               kMinArraySide, kMinArraySide << (kTextureArrays - 1));
  // Each texture's side and layer.
  std::vector<int> side(scene.textures.size()), layer(scene.textures.size());
  std::array<int, kTextureArrays> layers{};
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const Texture& t = scene.textures[i];
    const int larger = int(std::max(t.width, t.height));
    side[i] = std::clamp(int(std::bit_ceil(unsigned(larger))), kMinArraySide, limit);
    layer[i] = layers[array_of_side(side[i])]++;
  }
  GLint max_layers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
  for (int a = 0; a < kTextureArrays; ++a) {
    if (layers[a] == 0) continue;
    if (layers[a] > max_layers)
      return make_error("the scene has ", std::to_string(layers[a]), " textures of ",
                        std::to_string(kMinArraySide << a), " texels a side; the GL holds ",
                        std::to_string(max_layers), " in one array");
    const int s = kMinArraySide << a, levels = std::countr_zero(unsigned(s)) + 1;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &out.arrays_[a]);
    glTextureStorage3D(out.arrays_[a], levels, GL_RGBA8, s, s, layers[a]);
    if (glGetError() != GL_NO_ERROR)
      return make_error("the GPU cannot hold ", std::to_string(layers[a]), " textures of ",
                        std::to_string(s), " texels a side");
    glTextureParameteri(out.arrays_[a], GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(out.arrays_[a], GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(out.arrays_[a], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(out.arrays_[a], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    out.bytes_ += uint64_t(s) * s * 4 * layers[a] * 4 / 3;
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    auto texels = decode_texture(scene.textures[i]);
    if (!texels) return texels.error();
    const RgbaImage square = resample(*texels, side[i]);
    glTextureSubImage3D(out.arrays_[array_of_side(side[i])], 0, 0, 0, layer[i], side[i], side[i], 1,
                        GL_RGBA, GL_UNSIGNED_BYTE, square.rgba.data());
  }
  for (GLuint a : out.arrays_)
    if (a) glGenerateTextureMipmap(a);

  for (const Material& m : scene.materials) {
    MaterialTexturing t;
    t.modes = int(m.wrap_u) | int(m.wrap_v) << 2 | int(m.alpha_mode) << 4;
    t.cutoff = m.alpha_cutoff;
    if (m.textured()) {
      t.array = array_of_side(side[m.texture]);
      t.layer = layer[m.texture];
    }
    out.materials_.push_back(t);
  }
  return out;
}

SceneTextures::SceneTextures(SceneTextures&& other) noexcept {
  *this = std::move(other);
}

SceneTextures& SceneTextures::operator=(SceneTextures&& other) noexcept {
  std::swap(arrays_, other.arrays_);
  std::swap(materials_, other.materials_);
  std::swap(bytes_, other.bytes_);
  return *this;
}

SceneTextures::~SceneTextures() {
  for (GLuint a : arrays_)
    if (a) glDeleteTextures(1, &a);
}

void SceneTextures::set_nearest(bool nearest) {
  for (GLuint a : arrays_) {
    if (!a) continue;
    glTextureParameteri(a, GL_TEXTURE_MIN_FILTER, nearest ? GL_NEAREST : GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(a, GL_TEXTURE_MAG_FILTER, nearest ? GL_NEAREST : GL_LINEAR);
  }
}

void SceneTextures::bind(int array) const {
  glBindTextureUnit(0, arrays_[size_t(array)]);
}

}  // namespace farfield::gpu
