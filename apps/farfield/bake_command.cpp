// farfield bake SCENE --technique NAME --out PACK
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "commands.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/technique.hpp"

namespace farfield::cli {

void add_bake_command(CLI::App& root, std::vector<Command>& commands) {
  struct Settings {
    std::string scene, technique, out;
    std::vector<std::string> settings;
    bool quiet = false;
  };
  auto s = std::make_shared<Settings>();
  CLI::App* cmd = root.add_subcommand(
      "bake", "Preprocess a scene for a technique into a .ffpack store (SQLite, checksummed); "
              "bench and view load it with --store. A stratified bake commits each viewcell as it "
              "goes: run it again after an interruption and it continues. Settings: --set "
              "stratified.path=PATH.json (only the viewcells a path needs), stratified.alpha, "
              "box, resolution, codec, ... (docs/techniques/stratified.md)");
  cmd->add_option("scene", s->scene, "A .ffscene file")->required();
  cmd->add_option("--technique,-t", s->technique, "The technique to bake: colorcube or stratified")
      ->required();
  cmd->add_option("--set", s->settings, "Technique setting NAME.KEY=VALUE, repeatable");
  cmd->add_option("--out,-o", s->out, "The .ffpack to write (created, or its bake replaced)")
      ->required();
  cmd->add_flag("--quiet,-q", s->quiet, "Do not show progress");
  commands.push_back({cmd, [s] {
                        const auto start = std::chrono::steady_clock::now();
                        TechniqueSettings settings;
                        for (const std::string& setting : s->settings)
                          if (auto ok = settings.add(setting); !ok) return fail(ok.error().message);
                        auto technique = make_technique(s->technique, settings);
                        if (!technique) return fail(technique.error().message);
                        auto scene = read_scene(s->scene);
                        if (!scene) return fail(scene.error().message);
                        const bool existed = std::filesystem::exists(s->out);
                        std::string bake_error;
                        uint64_t bytes = 0;
                        {
                          auto store = Store::open(s->out, Store::Mode::kReadWrite);
                          if (!store) return fail(store.error().message);
                          Progress progress(s->quiet);
                          auto ok = (*technique)->bake(*scene, *store, progress);
                          progress.finish();
                          const double seconds = std::chrono::duration<double>(
                                                     std::chrono::steady_clock::now() - start)
                                                     .count();
                          if (!ok) {
                            bake_error = ok.error().message;
                          } else if (auto total = store->total_bytes(s->technique + "/"); !total) {
                            bake_error = total.error().message;
                          } else {
                            bytes = *total;
                            // bench reports it beside the technique's frames
                            if (auto m = store->set_meta(s->technique + "/bake_s",
                                                         std::to_string(seconds));
                                !m)
                              bake_error = m.error().message;
                          }
                        }  // the pack is closed here
                        if (!bake_error.empty()) {
                          // A pack this command created and could not fill is not left behind;
                          // an existing one keeps its last committed state.
                          if (!existed) std::filesystem::remove(s->out);
                          return fail(bake_error);
                        }
                        std::printf("baked %s into %s: %s; %llu bytes, %.2f s\n",
                                    s->technique.c_str(), s->out.c_str(),
                                    (*technique)->describe().c_str(),
                                    (unsigned long long)bytes,
                                    std::chrono::duration<double>(
                                        std::chrono::steady_clock::now() - start)
                                        .count());
                        return 0;
                      }});
}

}  // namespace farfield::cli
