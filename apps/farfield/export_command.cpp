// farfield export SCENE --format glb --out F.glb: the scene in a standard format, for other
// viewers and tools; --format 3dtiles --store PACK: its cluster hierarchy as a 3D Tiles tileset.
#include <chrono>
#include <cstdio>

#include "commands.hpp"
#include "farfield/eval/run_plan.hpp"
#include "farfield/scene/glb_export.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/store/bake_record.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/clusters/tileset_export.hpp"

namespace farfield::cli {

namespace {

struct ExportSettings {
  std::string scene, format = "glb", out, store;
  GlbOptions glb;
  bool quiet = false;
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int export_glb(const ExportSettings& s) {
  if (!s.out.ends_with(".glb"))
    return usage_error("--out " + s.out + ": a .glb file for --format glb");
  if (!s.store.empty()) return usage_error("--store is for --format 3dtiles");
  if (auto ok = check_writable_file(s.out); !ok) return fail(ok.error().message);
  const auto start = std::chrono::steady_clock::now();
  auto scene = read_scene(s.scene);
  if (!scene) return fail(scene.error().message);
  auto written = write_glb(*scene, s.out, s.glb);
  if (!written) return fail(written.error().message);
  std::printf("wrote %s: %s, %s, %s, %s, %.2f MB in %.2f s\n", s.out.c_str(),
              counted(written->objects, "object").c_str(),
              counted(written->triangles, "triangle").c_str(),
              counted(written->materials, "material").c_str(),
              counted(written->textures, "texture").c_str(), double(written->bytes) / 1e6,
              seconds_since(start));
  return 0;
}

int export_tiles(const ExportSettings& s) {
  if (s.store.empty())
    return usage_error("--format 3dtiles needs --store PACK, a pack with a clusters bake "
                       "('farfield bake SCENE --technique clusters --out PACK')");
  if (!s.glb.objects.empty()) return usage_error("--objects is for --format glb");
  const auto start = std::chrono::steady_clock::now();
  auto scene = read_scene(s.scene);
  if (!scene) return fail(scene.error().message);
  auto store = Store::open(s.store, Store::Mode::kRead);
  if (!store) return fail(store.error().message);
  auto record = read_bake_record(*store, "clusters");
  if (!record) return fail(record.error().message);
  if (!*record)
    return fail(s.store + ": no clusters bake; run 'farfield bake " + s.scene +
                " --technique clusters --out " + s.store + "' first");
  auto tree = load_cluster_tree(*store, *scene);
  if (!tree) return fail(tree.error().message);
  auto boxes = load_box_set(*store, *scene, *tree);
  if (!boxes) return fail(boxes.error().message);
  Progress progress(s.quiet);
  auto written = write_tileset(*scene, *tree, *boxes, s.out, progress);
  if (!written) return fail(written.error().message);
  std::printf("wrote %s: %s (%llu with content, %llu textured boxes), %d levels, root error "
              "%.3g m, %.2f MB in %.2f s\n",
              s.out.c_str(), counted(written->tiles, "tile").c_str(),
              (unsigned long long)written->contents, (unsigned long long)written->boxes,
              written->depth + 1, written->root_error_m,
              double(written->bytes) / 1e6, seconds_since(start));
  return 0;
}

}  // namespace

void add_export_command(CLI::App& root, std::vector<Command>& commands) {
  auto s = std::make_shared<ExportSettings>();
  CLI::App* cmd = root.add_subcommand(
      "export",
      "Write a scene as glTF 2.0 binary (--format glb: one node a object, named as it, with "
      "its material, texture and vertex colours, +Y up in metres), or the cluster hierarchy "
      "of a clusters bake as a 3D Tiles 1.1 tileset (--format 3dtiles --store PACK: one tile a "
      "node, its merged mesh as content, its error in metres as geometricError; a folder, or "
      "one .3dtiles package)");
  cmd->add_option("scene", s->scene, "A .ffscene file")->required();
  cmd->add_option("--format", s->format, "glb (glTF 2.0 binary) or 3dtiles (a tileset)")
      ->check(CLI::IsMember({"glb", "3dtiles"}))
      ->capture_default_str();
  cmd->add_option("--out,-o", s->out,
                  "Output: a .glb file; for 3dtiles a new folder (tileset.json, tiles/) or a "
                  ".3dtiles package")
      ->required();
  cmd->add_option("--store", s->store,
                  "For 3dtiles: the .ffpack of 'farfield bake SCENE --technique clusters'");
  cmd->add_option("--objects", s->glb.objects,
                  "For glb: only the objects whose names match this shell pattern (e.g. "
                  "'block 3*'); a scene past the GLB container's 4 GiB is exported in parts "
                  "this way");
  cmd->add_flag("--quiet,-q", s->quiet, "Do not show progress");
  commands.push_back({cmd, [s] { return s->format == "glb" ? export_glb(*s) : export_tiles(*s); }});
}

}  // namespace farfield::cli
