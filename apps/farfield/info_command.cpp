// farfield info FILE
#include <chrono>
#include <cstdio>

#include "commands.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/scene/scene_summary.hpp"

namespace farfield::cli {

void add_info_command(CLI::App& root, std::vector<Command>& commands) {
  auto path = std::make_shared<std::string>();
  CLI::App* cmd = root.add_subcommand(
      "info", "Describe a .ffscene file: counts, bounds, bytes, objects by kind, file version, "
              "load time");
  cmd->add_option("file", *path, "A .ffscene file")->required();
  commands.push_back({cmd, [path] {
                        const auto start = std::chrono::steady_clock::now();
                        SceneFileInfo file;
                        auto scene = read_scene(*path, &file);
                        if (!scene) return fail(scene.error().message);
                        const double seconds = std::chrono::duration<double>(
                                                   std::chrono::steady_clock::now() - start)
                                                   .count();
                        std::fputs(summarize_scene({*scene, *path, file, seconds}).c_str(), stdout);
                        return 0;
                      }});
}

}  // namespace farfield::cli
