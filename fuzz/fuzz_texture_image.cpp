// libFuzzer target for texture images (scene/texture_image.hpp): any bytes as an image file
// that import reads (PNG and JPEG through libpng and libturbojpeg, the rest through
// stb_image). An accepted texture must decode again to the size it records.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "farfield/scene/texture_image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto bytes = std::as_bytes(std::span(data, size));
  auto texture = farfield::texture_from_image_bytes("fuzz", bytes);
  if (!texture) return 0;
  auto texels = farfield::decode_texture(*texture);
  if (!texels || texels->rgba.size() != size_t(texture->width) * texture->height * 4) std::abort();
  return 0;
}
