// farfield path SCENE --kind street|fly|orbit|interior --frames N --out path.json
#include <cstdio>
#include <optional>
#include <glm/geometric.hpp>

#include "commands.hpp"
#include "farfield/scene/chunked_scene.hpp"
#include "farfield/core/camera_path.hpp"
#include "farfield/scene/path_generator.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/spatial/interior_path.hpp"

namespace farfield::cli {

void add_path_command(CLI::App& root, std::vector<Command>& commands) {
  struct Settings {
    std::string scene, out;
    PathOptions path;
  };
  auto s = std::make_shared<Settings>();
  PathOptions& p = s->path;
  CLI::App* cmd = root.add_subcommand(
      "path",
      "Make a camera path through a scene for 'bench' and 'view': street (at eye height "
      "along the streets of a generated city), fly (a loop above the roofs), orbit "
      "(a circle around the scene, looking at its centre) or interior (room to room through "
      "doors and up stairs, in a scene with cells and portals such as a generated building)");
  cmd->add_option("scene", s->scene, "A .ffscene file")->required();
  cmd->add_option("--kind", p.kind, "street, fly, orbit or interior")
      ->check(CLI::IsMember({"street", "fly", "orbit", "interior"}))
      ->capture_default_str();
  cmd->add_option("--frames", p.frames, "Number of frames")->capture_default_str();
  cmd->add_option("--speed", p.speed,
                  "Metres per frame; 0: 1.5 for street, 0.15 for interior, one loop over all "
                  "frames for fly and orbit")
      ->capture_default_str();
  cmd->add_option("--seed", p.seed, "Random seed of the turns of a street path")
      ->capture_default_str();
  cmd->add_option("--eye-height", p.eye_height, "Eye height above the ground, m (street, interior)")
      ->capture_default_str();
  cmd->add_option("--out,-o", s->out, "Output path .json file")->required();
  commands.push_back(
      {cmd, [s] {
         // Street, fly and orbit paths need the objects, not their triangles: a chunked file
         // is read without its geometry (the 100M city's path in a second, not 36 s and
         // 4.7 GB); interior paths walk on the triangles.
         std::optional<ChunkedScene> on_disk;
         std::optional<Scene> in_memory;
         if (s->path.kind != "interior")
           if (auto opened = ChunkedScene::open(s->scene); opened)
             on_disk.emplace(std::move(*opened));
         if (!on_disk) {
           auto read = read_scene(s->scene);
           if (!read) return fail(read.error().message);
           in_memory.emplace(std::move(*read));
         }
         const Scene& scene = on_disk ? on_disk->index() : *in_memory;
         auto path = s->path.kind == "interior" ? interior_path(scene, s->path)
                                                : generate_path(scene, s->path);
         if (!path) {  // name the scene, unless it is an option that is wrong
           const std::string& message = path.error().message;
           return fail(message.starts_with("--") ? message : s->scene + ": " + message);
         }
         path->scene = s->scene;
         if (auto ok = write_camera_path(*path, s->out); !ok) return fail(ok.error().message);
         double length = 0.0;
         for (size_t i = 1; i < path->frames.size(); ++i)
           length += glm::distance(path->frames[i - 1].position, path->frames[i].position);
         std::printf("wrote %s: %s path, %s, %.1f m\n", s->out.c_str(), path->kind.c_str(),
                     counted(path->frames.size(), "frame").c_str(), length);
         return 0;
       }});
}

}  // namespace farfield::cli
