// The scene's textures on the GPU, for the scene shader: each texture decoded, resampled to a
// square power-of-two side (16 to the renderer's limit, 2048 by default) and stored as a layer
// of the array texture of that side, mipmapped, so that every textured material is drawn by
// the same multi-draw as the rest (no draw per texture): a material names its array and
// layer. Texture coordinates outside [0, 1] are wrapped by the shader (repeat, mirror, clamp),
// the arrays sample with clamping, trilinear.
#pragma once

#include <epoxy/gl.h>

#include <array>
#include <cstdint>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield::gpu {

// Array sides 16 .. 2048: eight arrays at most, bound to texture units 0..7.
inline constexpr int kMinArraySide = 16;
inline constexpr int kTextureArrays = 8;

// A material as the scene shader reads it per instance (location kTexturingAttrib, integers,
// and kCutoffAttrib).
struct MaterialTexturing {
  int32_t array = -1;  // -1: untextured
  int32_t layer = 0;
  int32_t modes = 0;  // wrap_u | wrap_v << 2 | alpha_mode << 4
  float cutoff = 0.5f;
};
static_assert(sizeof(MaterialTexturing) == 16);

class SceneTextures {
 public:
  // Textures larger than `max_side` a side are scaled down to it (a power of two).
  static Result<SceneTextures> create(const Scene& scene, int max_side = 2048);
  SceneTextures() = default;
  SceneTextures(SceneTextures&& other) noexcept;
  SceneTextures& operator=(SceneTextures&& other) noexcept;
  ~SceneTextures();

  // One per scene material, in order.
  const std::vector<MaterialTexturing>& materials() const { return materials_; }
  void bind(int array) const;  // that array on unit 0
  // Trilinear (the default) or nearest texel of the top level (tests compare with ray casts).
  void set_nearest(bool nearest);
  uint64_t bytes() const { return bytes_; }  // GPU memory, mipmaps included

 private:
  std::array<GLuint, kTextureArrays> arrays_{};
  std::vector<MaterialTexturing> materials_;
  uint64_t bytes_ = 0;
};

}  // namespace farfield::gpu
