// farfield info FILE
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>

#include "commands.hpp"
#include "farfield/core/file_reading.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/scene/scene_summary.hpp"
#include "farfield/store/store.hpp"
#include "farfield/store/bake_record.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield::cli {

namespace {

bool is_sqlite_file(const std::string& path) {
  auto file = ReadableFile::open(path);
  char magic[16] = {};
  return file && file->size() >= sizeof(magic) && file->read_at(magic, sizeof(magic), 0) &&
         std::memcmp(magic, "SQLite format 3", sizeof(magic)) == 0;
}

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
  for (const auto& [key, value] : *meta)
    if (!key.ends_with("/bake")) std::printf("%-24s %s\n", (key + ":").c_str(), value.c_str());
  for (const TechniqueDescriptor* d : technique_descriptors()) {
    auto record = read_bake_record(*store, d->name);
    if (!record) return fail(record.error().message);
    if (!*record) continue;
    const BakeRecord& r = **record;
    std::printf("%s bake:%*s format %d%s, %.2f s, scene %016llx\n", r.technique.c_str(),
                int(std::max<size_t>(1, 17 - r.technique.size())), "", r.format,
                r.format == d->bake_format ? "" : " (this farfield reads another: re-bake)",
                r.bake_s, (unsigned long long)r.scene);
    for (const auto& [key, value] : r.settings)
      std::printf("  %s.%s = %s\n", r.technique.c_str(), key.c_str(), value.c_str());
    if (d->describe_bake) {
      auto text = d->describe_bake(*store);
      if (!text) return fail(text.error().message);
      std::printf("%s", text->c_str());
    }
  }
  return 0;
}

}  // namespace

void add_info_command(CLI::App& root, std::vector<Command>& commands) {
  auto path = std::make_shared<std::string>();
  CLI::App* cmd = root.add_subcommand(
      "info",
      "Describe a .ffscene file (counts, bounds, bytes, objects by kind, file version, "
      "load time) or a .ffpack store (techniques baked, blobs, bytes, their figures)");
  cmd->add_option("file", *path, "A .ffscene or .ffpack file")->required();
  commands.push_back(
      {cmd, [path] {
         if (!is_scene_file(*path) && (path->ends_with(".ffpack") || is_sqlite_file(*path)))
           return describe_pack(*path);
         const auto start = std::chrono::steady_clock::now();
         // A file with chunks is described without reading its geometry (a few chunks are read
         // for its detail); older ones are read whole.
         if (auto chunked = ChunkedScene::open(*path); chunked) {
           const double seconds =
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
           auto detail = sampled_triangle_edge(*chunked);
           if (!detail) return fail(detail.error().message);
           std::fputs(summarize_scene({chunked->index(), *path, chunked->file(), seconds,
                                       &*chunked, *detail})
                          .c_str(),
                      stdout);
           return 0;
         }
         SceneFileInfo file;
         auto scene = read_scene(*path, &file);
         if (!scene) return fail(scene.error().message);
         const double seconds =
             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
         std::fputs(summarize_scene({*scene, *path, file, seconds}).c_str(), stdout);
         return 0;
       }});
}

}  // namespace farfield::cli
