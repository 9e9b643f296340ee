// farfield info FILE
#include <chrono>
#include <cstdio>
#include <map>

#include "commands.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/scene/scene_summary.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/stratified/stratified_pack.hpp"

namespace farfield::cli {

namespace {

// A pack: its blobs grouped by technique (the name before the first '/') and its metadata,
// which holds each bake's figures (e.g. colorcube/table1: paper 002's Table 1).
int describe_pack(const std::string& path) {
  auto store = Store::open(path, Store::Mode::kRead);
  if (!store) return fail(store.error().message);
  auto blobs = store->list();
  if (!blobs) return fail(blobs.error().message);
  auto meta = store->list_meta();
  if (!meta) return fail(meta.error().message);
  std::printf("file:        %s (.ffpack store)\n", path.c_str());
  std::map<std::string, std::pair<uint64_t, uint64_t>> techniques;  // blobs, stored bytes
  for (const BlobInfo& b : *blobs) {
    auto& t = techniques[b.name.substr(0, b.name.find('/'))];
    t.first++;
    t.second += b.stored_size;
  }
  for (const auto& [name, t] : techniques)
    std::printf("baked:       %-12s %8llu blobs %14llu bytes\n", name.c_str(),
                (unsigned long long)t.first, (unsigned long long)t.second);
  for (const auto& [key, value] : *meta) std::printf("%-24s %s\n", (key + ":").c_str(), value.c_str());
  if (techniques.count("stratified")) {
    auto text = store->get_meta(stratified::kParamsKey);
    if (!text) return fail(text.error().message);
    if (*text) {
      auto params = stratified::parse_params(**text);
      if (!params) return fail(path + ": " + params.error().message);
      for (size_t s = 0; s < params->shells.size(); ++s) {
        auto cells = stratified::baked_cells(*store, int(s));
        if (!cells) return fail(cells.error().message);
        std::printf("stratified shell %zu:      %zu viewcells baked, v %.2f m, box %.1f m\n", s,
                    cells->size(), params->shells[s].viewcell, params->shells[s].box);
      }
    }
  }
  return 0;
}

}  // namespace

void add_info_command(CLI::App& root, std::vector<Command>& commands) {
  auto path = std::make_shared<std::string>();
  CLI::App* cmd = root.add_subcommand(
      "info", "Describe a .ffscene file (counts, bounds, bytes, objects by kind, file version, "
              "load time) or a .ffpack store (techniques baked, blobs, bytes, their figures)");
  cmd->add_option("file", *path, "A .ffscene or .ffpack file")->required();
  commands.push_back({cmd, [path] {
                        if (!is_scene_file(*path) && path->ends_with(".ffpack")) return describe_pack(*path);
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
