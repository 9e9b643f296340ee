#include "farfield/core/camera_path.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "farfield/core/atomic_file.hpp"
#include "farfield/core/file_reading.hpp"

namespace farfield {

namespace {

using nlohmann::json;

constexpr const char* kFormat = "farfield-path";
constexpr int kVersion = 1;

// The shortest decimal that reads back as the same float, as a double, so that the JSON says
// 12.3 rather than 12.300000190734863 and reading it back gives the float that was written.
double shortest(float v) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, v).ptr;
  double d = 0.0;
  std::from_chars(text, end, d);
  return d;
}

// Empty when the pose can be written and read back; else what is wrong with it.
std::string pose_problem(const CameraPose& p) {
  if (!std::isfinite(p.position.x) || !std::isfinite(p.position.y) || !std::isfinite(p.position.z))
    return "position must be 3 finite numbers";
  if (!std::isfinite(p.yaw_deg)) return "yaw_deg must be a finite number";
  if (!(p.pitch_deg > -90.0f && p.pitch_deg < 90.0f))  // also refuses NaN
    return "pitch_deg must be a number in (-90, 90)";
  return {};
}

// A finite number that fits a float, or nothing.
bool read_number(const json& j, float& out) {
  if (!j.is_number()) return false;
  out = static_cast<float>(j.get<double>());
  return std::isfinite(out);
}

// Parses one frame; the message says what is wrong, without the file and frame number.
std::string parse_frame(const json& j, CameraPose& pose) {
  if (!j.is_object()) return "must be an object";
  const auto position = j.find("position");
  if (position == j.end()) return "missing \"position\"";
  if (!position->is_array() || position->size() != 3) return "position must be 3 numbers";
  for (int a = 0; a < 3; ++a) {
    if (!(*position)[a].is_number()) return "position must be 3 numbers";
    if (!read_number((*position)[a], pose.position[a])) return "position must be finite";
  }
  for (auto [key, value] : {std::pair{"yaw_deg", &pose.yaw_deg}, {"pitch_deg", &pose.pitch_deg}}) {
    const auto it = j.find(key);
    if (it == j.end()) return std::string("missing \"") + key + "\"";
    if (!read_number(*it, *value)) return std::string(key) + " must be a finite number";
  }
  return pose_problem(pose);
}

}  // namespace

Result<void> write_camera_path(const CameraPath& path, const std::string& file) {
  if (path.frames.empty()) return make_error(file, ": refusing to write a path without frames");
  // One frame per line: readable, and diffs of two paths line up.
  std::string text = "{\"format\": ";
  text += json(kFormat).dump();
  text += ", \"version\": " + std::to_string(kVersion);
  text += ", \"kind\": " + json(path.kind).dump();
  text += ", \"scene\": " + json(path.scene).dump();
  text += ",\n \"frames\": [\n";
  for (size_t i = 0; i < path.frames.size(); ++i) {
    const CameraPose& p = path.frames[i];
    if (std::string problem = pose_problem(p); !problem.empty())
      return make_error(file, ": refusing to write frame ", std::to_string(i), ": ", problem);
    // ordered_json: the keys in the order a reader expects rather than sorted.
    const nlohmann::ordered_json frame = {
        {"position", {shortest(p.position.x), shortest(p.position.y), shortest(p.position.z)}},
        {"yaw_deg", shortest(p.yaw_deg)},
        {"pitch_deg", shortest(p.pitch_deg)}};
    text += "  ";
    text += frame.dump();
    text += i + 1 < path.frames.size() ? ",\n" : "\n";
  }
  text += "]}\n";
  return write_file_atomically(file, text);
}

Result<CameraPath> read_camera_path(const std::string& file) {
  auto opened = ReadableFile::open(file);
  if (!opened) return opened.error();
  auto text = opened->read_all();
  if (!text) return text.error();
  return parse_camera_path(*text, file);
}

Result<CameraPath> parse_camera_path(std::string_view text, const std::string& file) {
  if (text.empty()) return make_error(file, ": file is empty");

  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    return make_error(file, ": not valid JSON: ", e.what());
  }
  if (!root.is_object()) return make_error(file, ": not a farfield path (not a JSON object)");
  const auto format = root.find("format");
  if (format == root.end() || !format->is_string() || *format != kFormat)
    return make_error(file, ": not a farfield path (\"format\" is not \"", kFormat, "\")");
  const auto version = root.find("version");
  if (version == root.end() || !version->is_number_integer())
    return make_error(file, ": missing or non-integer \"version\"");
  if (*version != kVersion)
    return make_error(file, ": unsupported path version ", version->dump(),
                      " (this build reads version ", std::to_string(kVersion), ")");

  CameraPath path;
  const auto kind = root.find("kind");
  if (kind == root.end() || !kind->is_string())
    return make_error(file, ": missing or non-string \"kind\"");
  path.kind = kind->get<std::string>();
  if (const auto scene = root.find("scene"); scene != root.end()) {  // informative, optional
    if (!scene->is_string()) return make_error(file, ": \"scene\" must be a string");
    path.scene = scene->get<std::string>();
  }
  const auto frames = root.find("frames");
  if (frames == root.end() || !frames->is_array())
    return make_error(file, ": missing or non-array \"frames\"");
  if (frames->empty()) return make_error(file, ": the path has no frames");
  path.frames.resize(frames->size());
  for (size_t i = 0; i < frames->size(); ++i) {
    if (std::string problem = parse_frame((*frames)[i], path.frames[i]); !problem.empty())
      return make_error(file, ": frame ", std::to_string(i), ": ", problem);
  }
  return path;
}

}  // namespace farfield
