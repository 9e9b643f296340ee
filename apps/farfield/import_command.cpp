// farfield import FILE... --out S.ffscene
#include <chrono>
#include <cstdio>

#include "commands.hpp"
#include "farfield/scene/import.hpp"
#include "farfield/scene/scene_file.hpp"

namespace farfield::cli {

void add_import_command(CLI::App& root, std::vector<Command>& commands) {
  struct Settings {
    std::vector<std::string> files;
    std::string out;
    std::string up = "y";
    ImportOptions options;
    bool no_instances = false;
    bool quiet = false;
  };
  auto s = std::make_shared<Settings>();
  CLI::App* cmd = root.add_subcommand(
      "import",
      "Import model files (OBJ, PLY, OFF, glTF/GLB, STL, DAE, 3DS, IFC, ... through "
      "assimp) into one .ffscene; node transforms applied, names, colours and base-colour "
      "textures kept. A .ffscene given alone is rewritten in this build's format (with chunks, "
      "so that it can be read in parts)");
  cmd->add_option("files", s->files, "Model files, or one .ffscene to rewrite")->required();
  cmd->add_option("--out,-o", s->out, "Output .ffscene file")->required();
  cmd->add_option("--up", s->up,
                  "The axis that points up in the files: y (glTF, OBJ, most) or z "
                  "(many CAD, IFC and scan exports); farfield scenes are +Y up")
      ->check(CLI::IsMember({"y", "z"}))
      ->capture_default_str();
  cmd->add_option(
         "--scale", s->options.scale,
         "Metres per file unit, e.g. 0.001 for a model in millimetres, 0.0254 for inches; on "
         "top of a unit the file states (FBX)")
      ->check(number_range(1e-9, 1e6))
      ->capture_default_str();
  cmd->add_flag("--drop-bad-textures", s->options.drop_bad_textures,
                "Import a material whose texture is missing or cannot be decoded with its base "
                "colour (and say which) instead of refusing the import");
  cmd->add_flag("--no-instances", s->no_instances,
                "Store every placement of a mesh that several nodes place as geometry of its "
                "own; by default the later ones are instances of the first, stored once "
                "(docs/scene.md, \"Instances\")");
  cmd->add_flag("--quiet,-q", s->quiet, "Do not show progress");
  commands.push_back(
      {cmd, [s] {
         const auto start = std::chrono::steady_clock::now();
         for (const std::string& file : s->files)
           if (is_scene_file(file) && s->files.size() > 1)
             return usage_error(file + ": a .ffscene is rewritten alone, not merged with others");
         if (s->files.size() == 1 && is_scene_file(s->files[0])) {
           if (s->options.scale != 1.0 || s->up != "y")
             return usage_error(s->files[0] +
                                ": a .ffscene is rewritten as it is (--scale and --up are "
                                "for model files)");
           auto scene = read_scene(s->files[0]);
           if (!scene) return fail(scene.error().message);
           if (auto ok = write_scene(*scene, s->out); !ok) return fail(ok.error().message);
           std::printf("rewrote %s as %s: %s, %s in %.2f s\n", s->files[0].c_str(),
                       s->out.c_str(), counted(scene->triangle_count(), "triangle").c_str(),
                       counted(scene->objects.size(), "object").c_str(),
                       std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                           .count());
           return 0;
         }
         Progress progress(s->quiet);
         s->options.up = s->up[0];
         s->options.instances = !s->no_instances;
         ImportReport report;
         auto scene = import_models(s->files, progress, s->options, &report);
         progress.finish();
         if (!scene) return fail(scene.error().message);
         for (const std::string& dropped : report.dropped_textures)
           std::fprintf(stderr, "farfield: dropped a texture, kept the colour: %s\n",
                        dropped.c_str());
         if (auto ok = write_scene(*scene, s->out); !ok) return fail(ok.error().message);
         std::printf(
             "wrote %s: %s, %s, %s from %s in %.2f s\n", s->out.c_str(),
             counted(scene->triangle_count(), "triangle").c_str(),
             counted(scene->objects.size(), "object").c_str(),
             counted(scene->textures.size(), "texture").c_str(),
             counted(s->files.size(), "file").c_str(),
             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
         return 0;
       }});
}

}  // namespace farfield::cli
