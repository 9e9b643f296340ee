#include "farfield/eval/bake_run.hpp"

#include <chrono>
#include <filesystem>
#include <optional>

#include "farfield/eval/run_plan.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/store/bake_record.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

namespace {

Result<BakeOutcome> bake_into(const Scene& scene, const TechniqueDescriptor& d,
                              const SettingValues& values, const TechniqueSettings& settings,
                              const std::string& pack, Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  auto technique = d.make(values, settings);
  if (!technique) return technique.error();
  auto store = Store::open(pack, Store::Mode::kReadWrite);
  if (!store) return store.error();
  std::unique_ptr<gpu::Context> context;
  std::unique_ptr<gpu::Renderer> renderer;
  if (d.bake_renders) {
    auto made_context = gpu::create_headless_context();
    if (!made_context) return made_context.error();
    context = std::move(*made_context);
    auto made = gpu::Renderer::create(scene);
    if (!made) return made.error();
    renderer = std::move(*made);
  }
  if (auto ok = (*technique)->bake({scene, *store, renderer.get(), progress}); !ok)
    return ok.error();
  BakeOutcome outcome;
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  BakeRecord record{
      std::string(d.name), d.bake_format, scene_fingerprint(scene), outcome.seconds, {}};
  for (const SettingSpec& s : d.settings)
    if (s.baked) record.settings[std::string(s.key)] = values.text(s.key);
  if (auto ok = write_bake_record(*store, record); !ok) return ok.error();
  auto bytes = store->total_bytes(std::string(d.name) + "/");
  if (!bytes) return bytes.error();
  outcome.store_bytes = *bytes;
  outcome.description = (*technique)->describe();
  return outcome;
}

}  // namespace

Result<BakeOutcome> run_bake(const Scene& scene, const std::string& technique,
                             const TechniqueSettings& settings, const std::string& pack,
                             Progress& progress) {
  auto d = find_technique(technique);
  if (!d) return d.error();
  if ((*d)->bake == BakeUse::none)
    return make_error("technique '", technique,
                      "' has nothing to bake; it loads in moments "
                      "from the scene (techniques that bake: colorcube, stratified)");
  for (const auto& [assignment, value] : settings.values)
    if (assignment.compare(0, technique.size() + 1, technique + ".") != 0)
      return make_error("--set ", assignment, "=", value, ": bake runs only ", technique);
  auto values = parse_settings(**d, settings);
  if (!values) return values.error();
  if (auto ok = check_writable_file(pack); !ok) return ok.error();
  const bool existed = std::filesystem::exists(pack);
  auto outcome = bake_into(scene, **d, *values, settings, pack, progress);
  if (!outcome && !existed) {
    std::error_code ec;
    std::filesystem::remove(pack, ec);
  }
  return outcome;
}

}  // namespace farfield
