// farfield bake SCENE --technique NAME --out PACK
#include <cstdio>

#include "commands.hpp"
#include "farfield/core/mpi_world.hpp"
#include "farfield/eval/bake_run.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield::cli {

void add_bake_command(CLI::App& root, std::vector<Command>& commands) {
  struct Settings {
    std::string scene, technique, out;
    std::vector<std::string> settings;
    bool quiet = false;
  };
  auto s = std::make_shared<Settings>();
  CLI::App* cmd = root.add_subcommand(
      "bake",
      "Preprocess a scene for a technique into a .ffpack store (SQLite, checksummed); "
      "bench and view load it with --store. A colorcube bake replaces the pack's "
      "colorcube bake; a stratified bake commits each viewcell as it goes: run it again "
      "with the same settings after an interruption and it continues (other settings "
      "need a new pack). Settings: --set TECHNIQUE.KEY=VALUE, listed by 'farfield techniques' "
      "(docs/techniques/).");
  cmd->add_option("scene", s->scene, "A .ffscene file")->required();
  cmd->add_option("--technique,-t", s->technique, "The technique to bake: colorcube or stratified")
      ->required();
  cmd->add_option("--set", s->settings, "Technique setting TECHNIQUE.KEY=VALUE, repeatable");
  cmd->add_option("--out,-o", s->out, "The .ffpack to write (created if missing)")->required();
  cmd->add_flag("--quiet,-q", s->quiet, "Do not show progress");
  commands.push_back({cmd, [s] {
                        TechniqueSettings settings;
                        for (const std::string& setting : s->settings)
                          if (auto ok = settings.add(setting); !ok)
                            return usage_error(ok.error().message);
                        if (auto d = find_technique(s->technique); !d)
                          return usage_error(d.error().message);
                        auto scene = read_scene(s->scene);
                        if (!scene) return fail(scene.error().message);
                        // One rank shows progress.
                        Progress progress(s->quiet || MpiWorld::get().rank() != 0);
                        auto baked = run_bake(*scene, s->technique, settings, s->out, progress);
                        progress.finish();
                        if (!baked) return fail(baked.error().message);
                        std::printf("baked %s into %s: %s; %llu bytes, %.2f s\n",
                                    s->technique.c_str(), s->out.c_str(),
                                    baked->description.c_str(),
                                    (unsigned long long)baked->store_bytes, baked->seconds);
                        if (baked->compacted_bytes > 0)
                          std::printf("compacted the pack: %.1f MB of erased work given back\n",
                                      double(baked->compacted_bytes) / 1e6);
                        if (!baked->compact_failure.empty())
                          std::fprintf(stderr,
                                       "farfield: warning: the pack is complete but was not "
                                       "compacted: %s\n",
                                       baked->compact_failure.c_str());
                        return 0;
                      }});
}

}  // namespace farfield::cli
