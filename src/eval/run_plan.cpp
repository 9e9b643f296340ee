#include "farfield/eval/run_plan.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "farfield/scene/chunked_scene.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ",") + n;
  return out;
}

// Whether a baked setting asked for now differs from what the bake was made with.
bool differs(const SettingSpec& spec, const std::string& asked, const std::string& baked) {
  if (spec.type == SettingType::number || spec.type == SettingType::integer)
    return std::strtod(asked.c_str(), nullptr) != std::strtod(baked.c_str(), nullptr);
  return asked != baked;
}

}  // namespace

Result<std::vector<PlannedTechnique>> plan_run(const std::vector<std::string>& names,
                                               const TechniqueSettings& settings,
                                               const Store* store, const Scene& scene,
                                               bool others_may_be_set,
                                               const ChunkedScene* on_disk) {
  // The techniques that run, parts after the technique that holds them.
  std::vector<const TechniqueDescriptor*> running;
  std::vector<std::string> pending = names;
  for (size_t i = 0; i < pending.size(); ++i) {
    auto found = find_technique(pending[i]);
    if (!found) return found.error();
    if (std::find(running.begin(), running.end(), *found) != running.end()) continue;
    running.push_back(*found);
    if ((*found)->parts) {
      auto values = parse_settings(**found, settings);
      if (!values) return values.error();
      for (std::string& part : (*found)->parts(*values)) pending.push_back(std::move(part));
    }
  }
  for (const auto& [assignment, value] : settings.values) {
    const std::string technique = assignment.substr(0, assignment.find('.'));
    const bool runs =
        std::any_of(running.begin(), running.end(),
                    [&](const TechniqueDescriptor* d) { return d->name == technique; });
    if (!runs && others_may_be_set) {
      auto d = find_technique(technique);
      if (!d) return d.error();
      if (auto values = parse_settings(**d, settings); !values) return values.error();
    } else if (!runs) {
      return make_error("--set ", assignment, "=", value, ": ", technique,
                        " is not among the techniques run (", joined(names), ")");
    }
  }

  // A scene left on disk has no geometry in memory: its file holds its fingerprint.
  const uint64_t fingerprint = on_disk ? on_disk->fingerprint() : scene_fingerprint(scene);
  std::vector<PlannedTechnique> plan;
  for (const TechniqueDescriptor* d : running) {
    auto values = parse_settings(*d, settings);
    if (!values) return values.error();
    if (auto made = d->make(*values, settings); !made) return made.error();  // cross-checks
    PlannedTechnique p{d, std::nullopt};
    const std::string name(d->name);
    if (on_disk && !d->streams)
      return make_error(name, " cannot walk a scene left on disk (--cache-mb): it needs the "
                        "scene in memory (drop --cache-mb)");
    if (d->bake == BakeUse::required && store == nullptr)
      return make_error(name, " draws from a bake: bake it first (farfield bake SCENE --technique ",
                        name, " --out PACK.ffpack), then pass --store PACK.ffpack");
    if (d->bake != BakeUse::none && store != nullptr) {
      auto record = read_bake_record(*store, name);
      if (!record) return record.error();
      if (*record || d->bake == BakeUse::required) {
        auto usable =
            usable_bake(*store, name, d->bake_format, fingerprint, d->oldest_format(scene));
        if (!usable) return usable.error();
        p.bake = std::move(*usable);
      }
    }
    if (p.bake) {
      for (const SettingSpec& spec : d->settings) {
        if (!spec.baked || !values->given(spec.key)) continue;
        const auto at = p.bake->settings.find(std::string(spec.key));
        const std::string& asked = values->text(spec.key);
        if (at == p.bake->settings.end() || differs(spec, asked, at->second))
          return make_error("--set ", name, ".", std::string(spec.key), "=", asked, ": ",
                            store->path(), " holds a ", name, " bake made with ",
                            std::string(spec.key), "=",
                            at == p.bake->settings.end() ? "(not recorded)" : at->second,
                            ", which a run cannot change; re-bake to change it");
      }
    }
    plan.push_back(std::move(p));
  }
  return plan;
}

Result<void> check_writable_folder(const std::string& folder) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) return make_error(folder, ": cannot create the output folder: ", ec.message());
  const std::filesystem::path probe =
      std::filesystem::path(folder) / (".farfield-probe-" + std::to_string(::getpid()));
  {
    std::ofstream out(probe);
    if (!out) return make_error(folder, ": the output folder is not writable");
  }
  std::filesystem::remove(probe, ec);
  return {};
}

Result<void> check_writable_file(const std::string& file) {
  std::filesystem::path path(file);
  if (std::filesystem::is_directory(path)) return make_error(file, ": is a folder, not a file");
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : ".";
  if (!std::filesystem::is_directory(folder))
    return make_error(file, ": its folder ", folder.string(), " does not exist");
  const std::filesystem::path probe = folder / (".farfield-probe-" + std::to_string(::getpid()));
  {
    std::ofstream out(probe);
    if (!out) return make_error(file, ": its folder ", folder.string(), " is not writable");
  }
  std::error_code ec;
  std::filesystem::remove(probe, ec);
  if (std::filesystem::exists(path) && ::access(file.c_str(), W_OK) != 0)
    return make_error(file, ": exists and is not writable");
  return {};
}

}  // namespace farfield
