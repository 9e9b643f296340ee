// A camera path: one pose per frame, played back by `bench` and `view` (paper 000, Sec. 5.2.1:
// recording a path writes viewpoints and viewing directions; playing renders them in order).
// Stored as JSON (docs/path.md).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/core/view.hpp"

namespace farfield {

struct CameraPath {
  std::string kind;   // street, fly, orbit, recorded, ...
  std::string scene;  // the scene file it was made for (informative)
  std::vector<CameraPose> frames;
};

// Written atomically. Reading refuses malformed JSON, missing fields, non-finite numbers and
// empty paths with a message naming the file and the problem.
Result<void> write_camera_path(const CameraPath& path, const std::string& file);
Result<CameraPath> read_camera_path(const std::string& file);
// The same from the file's text; messages name `file`.
Result<CameraPath> parse_camera_path(std::string_view text, const std::string& file);

}  // namespace farfield
