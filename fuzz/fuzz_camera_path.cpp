// libFuzzer target for the camera-path reader (docs/path.md): any bytes as the file's text.
// An accepted path must hold only finite poses with a pitch inside (-90, 90).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "farfield/core/camera_path.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto path = farfield::parse_camera_path(text, "fuzz.json");
  if (!path) return 0;
  if (path->frames.empty()) std::abort();
  for (const farfield::CameraPose& p : path->frames)
    if (!std::isfinite(p.position.x + p.position.y + p.position.z + p.yaw_deg) ||
        !(p.pitch_deg > -90.0f && p.pitch_deg < 90.0f))
      std::abort();
  return 0;
}
