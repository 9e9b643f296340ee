// A texture's texels, and textures made from image files: PNG and JPEG are kept as they came
// (libpng, libturbojpeg decode them); other formats assimp's models use (TGA, BMP, GIF, PSD,
// PNM) are decoded with stb_image and stored as PNG. Decoding checks the size before
// allocating, and every message names the texture.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "farfield/core/image.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

// RGBA8, rows from the top: texture coordinate (0, 0) is the top-left texel (glTF's rule).
using Texels = RgbaImage;

// Textures of at most this many texels a side (GL_MAX_TEXTURE_SIZE is at least 16384).
inline constexpr uint32_t kMaxTextureSide = 16384;

// An image file's bytes as a texture named `name`; refused, naming it, when the bytes are not
// an image this build reads, or are corrupt.
Result<Texture> texture_from_image_bytes(std::string name, std::span<const std::byte> bytes);

// The texels of a stored texture; refused when its image does not decode to its stated size.
Result<Texels> decode_texture(const Texture& texture);

// Texels as a PNG texture (what generators make).
Result<Texture> texture_from_texels(std::string name, const Texels& texels);

}  // namespace farfield
