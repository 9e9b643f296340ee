// farfield export SCENE --format glb --out F.glb: the scene in a standard format, for other
// viewers and tools.
#include <chrono>
#include <cstdio>

#include "commands.hpp"
#include "farfield/eval/run_plan.hpp"
#include "farfield/scene/glb_export.hpp"
#include "farfield/scene/scene_file.hpp"

namespace farfield::cli {

void add_export_command(CLI::App& root, std::vector<Command>& commands) {
  struct Settings {
    std::string scene, format = "glb", out;
    GlbOptions glb;
  };
  auto s = std::make_shared<Settings>();
  CLI::App* cmd = root.add_subcommand(
      "export",
      "Write a scene as glTF 2.0 binary (.glb): one node a object, named as it, with its "
      "material (base colour, texture, alpha mode) and its vertex colours, +Y up in metres");
  cmd->add_option("scene", s->scene, "A .ffscene file")->required();
  cmd->add_option("--format", s->format, "glb (glTF 2.0 binary)")
      ->check(CLI::IsMember({"glb"}))
      ->capture_default_str();
  cmd->add_option("--out,-o", s->out, "Output file (.glb)")->required();
  cmd->add_option("--objects", s->glb.objects,
                  "Only the objects whose names match this shell pattern (e.g. 'block 3*'); a "
                  "scene past the GLB container's 4 GiB is exported in parts this way");
  commands.push_back({cmd, [s] {
                        if (!s->out.ends_with(".glb"))
                          return usage_error("--out " + s->out +
                                             ": a .glb file for --format glb");
                        if (auto ok = check_writable_file(s->out); !ok)
                          return fail(ok.error().message);
                        const auto start = std::chrono::steady_clock::now();
                        auto scene = read_scene(s->scene);
                        if (!scene) return fail(scene.error().message);
                        auto written = write_glb(*scene, s->out, s->glb);
                        if (!written) return fail(written.error().message);
                        std::printf(
                            "wrote %s: %s, %s, %s, %s, %.2f MB in %.2f s\n", s->out.c_str(),
                            counted(written->objects, "object").c_str(),
                            counted(written->triangles, "triangle").c_str(),
                            counted(written->materials, "material").c_str(),
                            counted(written->textures, "texture").c_str(),
                            double(written->bytes) / 1e6,
                            std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                                .count());
                        return 0;
                      }});
}

}  // namespace farfield::cli
