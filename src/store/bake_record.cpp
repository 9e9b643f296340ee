// Records as text: one KEY=VALUE a line, the baked settings as "setting.KEY=VALUE".
#include "farfield/store/bake_record.hpp"

#include <cstdlib>
#include <sstream>

namespace farfield {

namespace {

std::string record_key(std::string_view technique) {
  return std::string(technique) + "/bake";
}

constexpr std::string_view kSettingPrefix = "setting.";

}  // namespace

Result<void> write_bake_record(Store& store, const BakeRecord& r) {
  std::string text = "format=" + std::to_string(r.format) + "\nscene=" + std::to_string(r.scene) +
                     "\nbake_s=" + std::to_string(r.bake_s) + "\n";
  for (const auto& [key, value] : r.settings) {
    if (key.find_first_of("=\n") != std::string::npos || value.find('\n') != std::string::npos)
      return make_error("bake record of ", r.technique, ": setting '", key,
                        "' cannot be written on one line");
    text += std::string(kSettingPrefix) + key + "=" + value + "\n";
  }
  return store.set_meta(record_key(r.technique), text);
}

Result<void> erase_bake_record(Store& store, std::string_view technique) {
  return store.erase_meta(record_key(technique));
}

Result<std::optional<BakeRecord>> read_bake_record(const Store& store, std::string_view technique) {
  auto text = store.get_meta(record_key(technique));
  if (!text) return text.error();
  if (!*text) return std::optional<BakeRecord>{};
  BakeRecord r;
  r.technique = std::string(technique);
  bool has_format = false, has_scene = false;
  std::istringstream in(**text);
  std::string line;
  auto bad = [&](const std::string& why) {
    return make_error(store.path(), ": the ", std::string(technique), " bake record is damaged (",
                      why, "); re-bake it");
  };
  while (std::getline(in, line)) {
    const size_t eq = line.find('=');
    if (eq == std::string::npos || eq == 0) return bad("line '" + line + "'");
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    char* end = nullptr;
    if (key == "format") {
      r.format = int(std::strtol(value.c_str(), &end, 10));
      has_format = !value.empty() && *end == '\0';
    } else if (key == "scene") {
      r.scene = std::strtoull(value.c_str(), &end, 10);
      has_scene = !value.empty() && *end == '\0';
    } else if (key == "bake_s") {
      r.bake_s = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0') return bad("bake_s '" + value + "'");
    } else if (key.compare(0, kSettingPrefix.size(), kSettingPrefix) == 0) {
      r.settings[key.substr(kSettingPrefix.size())] = value;
    } else {
      return bad("unknown key '" + key + "'");
    }
  }
  if (!has_format || !has_scene) return bad("no format or scene");
  return std::optional<BakeRecord>(std::move(r));
}

Result<BakeRecord> usable_bake(const Store& store, std::string_view technique, int format,
                               uint64_t scene, int oldest) {
  const std::string name(technique);
  auto record = read_bake_record(store, technique);
  if (!record) return record.error();
  if (!*record) {
    auto blobs = store.total_bytes(name + "/");
    if (blobs && *blobs > 0)
      return make_error(store.path(), ": its ", name,
                        " bake is unfinished or was made by an "
                        "older farfield (no bake record): run the bake again (farfield bake "
                        "SCENE --technique ",
                        name, " --out ", store.path(),
                        "), or re-bake it "
                        "into a new pack");
    return make_error(store.path(), ": holds no ", name,
                      " bake (run: farfield bake SCENE "
                      "--technique ",
                      name, " --out ", store.path(), ")");
  }
  if ((*record)->format != format &&
      !(oldest > 0 && (*record)->format >= oldest && (*record)->format < format))
    return make_error(store.path(), ": its ", name, " bake has format ",
                      std::to_string((*record)->format), " and this farfield reads format ",
                      std::to_string(format), "; re-bake it: farfield bake SCENE --technique ",
                      name, " --out NEW.ffpack");
  if ((*record)->scene != scene)
    return make_error(store.path(), ": its ", name, " bake was made for another scene");
  return std::move(**record);
}

}  // namespace farfield
