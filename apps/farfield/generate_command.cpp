// farfield generate city | building | field | tree | landscape
#include <chrono>
#include <cstdio>

#include "commands.hpp"
#include "farfield/scene/building_generator.hpp"
#include "farfield/scene/chunked_scene.hpp"
#include "farfield/scene/city_generator.hpp"
#include "farfield/scene/field_generator.hpp"
#include "farfield/scene/import.hpp"
#include "farfield/scene/landscape_generator.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/scene/tree_generator.hpp"

namespace farfield::cli {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int write_and_report(const Scene& scene, const std::string& out,
                     std::chrono::steady_clock::time_point start) {
  if (auto ok = write_scene(scene, out); !ok) return fail(ok.error().message);
  std::printf("wrote %s: %s, %s, %.1f x %.1f m, in %.2f s\n", out.c_str(),
              counted(scene.triangle_count(), "triangle").c_str(),
              counted(scene.objects.size(), "object").c_str(), scene.bounds.size().x,
              scene.bounds.size().z, seconds_since(start));
  return 0;
}

void add_city(CLI::App& generate, std::vector<Command>& commands) {
  struct Settings {
    CityOptions city;
    uint32_t blocks = 0;
    CLI::Option* blocks_option = nullptr;
    std::string out;
    bool quiet = false;
  };
  auto s = std::make_shared<Settings>();
  CityOptions& c = s->city;
  CLI::App* cmd = generate.add_subcommand(
      "city",
      "The random city of paper 000, App. A: blocks of buildings, parks, fountains, trees, "
      "streets and curbs. The default is about 1 km x 1 km with over 1M triangles.");
  cmd->add_option("--out,-o", s->out, "Output .ffscene file")->required();
  cmd->add_option("--seed", c.seed, "Random seed; the same seed and options give the same file")
      ->capture_default_str();
  cmd->add_option("--target-triangles", c.target_triangles,
                  "Grow the (square) grid of blocks until the city has at least this many "
                  "triangles; overrides --blocks")
      ->capture_default_str();
  cmd->add_flag("--textures", c.textures,
                "Procedural textures (brick facades, paving, asphalt) on buildings, sidewalks and "
                "streets; the same geometry as without");
  cmd->add_option("--max-height", c.max_height, "Maximum height of the city, m")
      ->capture_default_str();
  cmd->add_option("--block-length", c.block_length, "Length of a block along X, m")
      ->capture_default_str();
  cmd->add_option("--block-width", c.block_width, "Width of a block along Z, m")
      ->capture_default_str();
  cmd->add_option("--rows", c.rows, "Maximum rows of buildings per block")->capture_default_str();
  cmd->add_option("--columns", c.columns, "Maximum columns of buildings per block")
      ->capture_default_str();
  s->blocks_option = cmd->add_option("--blocks", s->blocks,
                                     "Blocks in each dimension (sets --blocks-x and --blocks-z)")
                         ->check(CLI::Range(1u, 100000u));
  cmd->add_option("--blocks-x", c.blocks_x, "Blocks along X")->capture_default_str();
  cmd->add_option("--blocks-z", c.blocks_z, "Blocks along Z")->capture_default_str();
  cmd->add_option("--street-width", c.street_width, "Street width, m")->capture_default_str();
  cmd->add_option("--street-height", c.street_height, "Street slab height, m")
      ->capture_default_str();
  cmd->add_option("--curb-width", c.curb_width, "Curb width, m")->capture_default_str();
  cmd->add_option("--curb-height", c.curb_height, "Curb height above the street, m")
      ->capture_default_str();
  cmd->add_option("--tree-distance", c.tree_distance, "Distance between trees, m")
      ->capture_default_str();
  cmd->add_option("--park-blocks", c.park_block_fraction, "Fraction of blocks that are parks")
      ->capture_default_str();
  cmd->add_option("--tree-blocks", c.tree_block_fraction, "Fraction of blocks lined with trees")
      ->capture_default_str();
  cmd->add_flag("--quiet,-q", s->quiet, "Do not show progress");
  commands.push_back({cmd, [s] {
                        const auto start = std::chrono::steady_clock::now();
                        if (s->blocks_option->count())
                          s->city.blocks_x = s->city.blocks_z = s->blocks;
                        Progress progress(s->quiet);
                        // Written a block at a time: a city larger than memory is written too.
                        auto written = write_city(s->city, s->out, progress);
                        progress.finish();
                        if (!written) return fail(written.error().message);
                        auto scene = ChunkedScene::open(s->out);
                        if (!scene) return fail(scene.error().message);
                        const Scene& index = scene->index();
                        std::printf("wrote %s: %s, %s, %.1f x %.1f m, in %.2f s\n",
                                    s->out.c_str(),
                                    counted(scene->triangle_count(), "triangle").c_str(),
                                    counted(index.objects.size(), "object").c_str(),
                                    index.bounds.size().x, index.bounds.size().z,
                                    seconds_since(start));
                        return 0;
                      }});
}

void add_building(CLI::App& generate, std::vector<Command>& commands) {
  struct Settings {
    BuildingOptions building;
    std::string out;
    bool quiet = false;
  };
  auto s = std::make_shared<Settings>();
  BuildingOptions& o = s->building;
  CLI::App* cmd = generate.add_subcommand(
      "building",
      "A large office building of furnished rooms, corridors and a stairwell, with its rooms as "
      "cells and its doors and windows as portals (portal rendering, paper 004). The default "
      "has 12 floors, 1,128 rooms and about 5.2M triangles.");
  cmd->add_option("--out,-o", s->out, "Output .ffscene file")->required();
  cmd->add_option("--seed", o.seed, "Random seed; the same seed and options give the same file")
      ->capture_default_str();
  cmd->add_option("--floors", o.floors, "Storeys")->capture_default_str();
  cmd->add_option("--rooms", o.rooms_per_side,
                  "Room slots on each side of the corridor, per floor (two hold the stairwell)")
      ->capture_default_str();
  cmd->add_option("--segment-rooms", o.segment_rooms,
                  "Room slots per corridor segment (each segment is a cell)")
      ->capture_default_str();
  cmd->add_option("--room-width", o.room_width, "Room width along the corridor, m")
      ->capture_default_str();
  cmd->add_option("--room-depth", o.room_depth, "Room depth, m")->capture_default_str();
  cmd->add_option("--corridor-width", o.corridor_width, "Corridor width, m")->capture_default_str();
  cmd->add_option("--storey", o.storey, "Floor-to-floor height, m")->capture_default_str();
  cmd->add_option("--books", o.books, "Books per bookshelf (two a room): the rooms' detail")
      ->capture_default_str();
  cmd->add_flag("--quiet,-q", s->quiet, "Do not show progress");
  commands.push_back({cmd, [s] {
                        const auto start = std::chrono::steady_clock::now();
                        Progress progress(s->quiet);
                        auto scene = generate_building(s->building, progress);
                        progress.finish();
                        if (!scene) return fail(scene.error().message);
                        return write_and_report(*scene, s->out, start);
                      }});
}

void add_field(CLI::App& generate, std::vector<Command>& commands) {
  struct Settings {
    FieldOptions field;
    std::string mesh, out;
    bool quiet = false;
  };
  auto s = std::make_shared<Settings>();
  CLI::App* cmd = generate.add_subcommand(
      "field",
      "Copies of one model on a square grid, each copy its own object (the scaling "
      "experiments of paper 002, Sec. 6.3)");
  cmd->add_option("--mesh", s->mesh, "The model: a .ffscene or any format 'import' reads")
      ->required();
  cmd->add_option("--count", s->field.count, "Number of copies")->capture_default_str();
  cmd->add_option("--spacing", s->field.spacing, "Distance between copies, m")
      ->capture_default_str();
  cmd->add_option("--out,-o", s->out, "Output .ffscene file")->required();
  cmd->add_flag("--quiet,-q", s->quiet, "Do not show progress");
  commands.push_back({cmd, [s] {
                        const auto start = std::chrono::steady_clock::now();
                        if (auto ok = validate_field_options(s->field); !ok)
                          return fail(ok.error().message);
                        Scene model;
                        if (is_scene_file(s->mesh)) {
                          auto read = read_scene(s->mesh);
                          if (!read) return fail(read.error().message);
                          model = std::move(*read);
                        } else if (auto ok = import_model(s->mesh, model); !ok) {
                          return fail(ok.error().message);
                        }
                        Progress progress(s->quiet);
                        auto field = generate_field(model, s->field, progress);
                        progress.finish();
                        if (!field) return fail(field.error().message);
                        return write_and_report(*field, s->out, start);
                      }});
}

void add_tree(CLI::App& generate, std::vector<Command>& commands) {
  struct Settings {
    TreeOptions tree;
    std::string out;
    bool quiet = false;
  };
  auto s = std::make_shared<Settings>();
  TreeOptions& t = s->tree;
  CLI::App* cmd = generate.add_subcommand(
      "tree",
      "An L-system tree of branch cylinders and double-sided leaves (paper 002, Sec. 5). "
      "The default is 10 m tall with about 52K triangles in 28 objects.");
  cmd->add_option("--out,-o", s->out, "Output .ffscene file")->required();
  cmd->add_option("--seed", t.seed, "Random seed; the same seed and options give the same file")
      ->capture_default_str();
  cmd->add_option("--iterations", t.iterations,
                  "Rewriting steps of the L-system; each one triples the default tree")
      ->capture_default_str();
  cmd->add_option("--height", t.height, "Height of the branches' top, m")->capture_default_str();
  cmd->add_option("--branch-angle", t.branch_angle_deg, "Turn of + - & ^, degrees")
      ->capture_default_str();
  cmd->add_option("--divergence", t.divergence_deg, "Roll of / \\, degrees")->capture_default_str();
  cmd->add_option("--length-ratio", t.length_ratio, "Branch length / parent's length")
      ->capture_default_str();
  cmd->add_option("--radius-ratio", t.radius_ratio, "Branch radius / parent's radius")
      ->capture_default_str();
  cmd->add_option("--taper", t.segment_taper, "Radius at the end of a segment / at its start")
      ->capture_default_str();
  cmd->add_option("--jitter", t.jitter, "Random variation of angles and lengths, fraction")
      ->capture_default_str();
  cmd->add_option("--leaf-size", t.leaf_size, "Length of a leaf, m")->capture_default_str();
  cmd->add_option("--leaves", t.leaves, "Leaves per L symbol (per twig); 0 for a bare tree")
      ->capture_default_str();
  cmd->add_option("--sides", t.sides, "Sides of a branch cylinder")->capture_default_str();
  cmd->add_option("--objects", t.objects,
                  "About this many objects: the trunk and subtrees; 1 for one object")
      ->capture_default_str();
  cmd->add_option("--axiom", t.axiom, "The L-system's start string")->capture_default_str();
  cmd->add_option("--rule", t.rules,
                  "A rewriting rule LETTER=SUCCESSOR, repeatable; replaces the default rules")
      ->capture_default_str();
  cmd->add_flag("--quiet,-q", s->quiet, "Do not show progress");
  commands.push_back({cmd, [s] {
                        const auto start = std::chrono::steady_clock::now();
                        Progress progress(s->quiet);
                        auto scene = generate_tree(s->tree, progress);
                        progress.finish();
                        if (!scene) return fail(scene.error().message);
                        return write_and_report(*scene, s->out, start);
                      }});
}

void add_landscape(CLI::App& generate, std::vector<Command>& commands) {
  struct Settings {
    LandscapeOptions landscape;
    std::string out;
    bool quiet = false;
  };
  auto s = std::make_shared<Settings>();
  LandscapeOptions& l = s->landscape;
  CLI::App* cmd = generate.add_subcommand(
      "landscape",
      "Hills of fractal noise in square tiles, with groves of L-system trees (paper "
      "002, Sec. 5). The default is 1 km x 1 km with about 2M triangles.");
  cmd->add_option("--out,-o", s->out, "Output .ffscene file")->required();
  cmd->add_option("--seed", l.seed, "Random seed; the same seed and options give the same file")
      ->capture_default_str();
  cmd->add_option("--size", l.size, "Side of the square terrain, m")->capture_default_str();
  cmd->add_option("--resolution", l.resolution, "Grid cells per side of the terrain")
      ->capture_default_str();
  cmd->add_option("--tile", l.tile_cells, "Grid cells per side of a terrain tile (object)")
      ->capture_default_str();
  cmd->add_option("--relief", l.relief, "Height between the lowest and highest ground, m")
      ->capture_default_str();
  cmd->add_option("--trees", l.trees, "Number of trees")->capture_default_str();
  cmd->add_flag("--quiet,-q", s->quiet, "Do not show progress");
  commands.push_back({cmd, [s] {
                        const auto start = std::chrono::steady_clock::now();
                        Progress progress(s->quiet);
                        auto scene = generate_landscape(s->landscape, progress);
                        progress.finish();
                        if (!scene) return fail(scene.error().message);
                        return write_and_report(*scene, s->out, start);
                      }});
}

}  // namespace

void add_generate_commands(CLI::App& root, std::vector<Command>& commands) {
  CLI::App* generate =
      root.add_subcommand("generate", "Generate a scene: city, building, field, tree or landscape");
  generate->require_subcommand(1);
  add_city(*generate, commands);
  add_building(*generate, commands);
  add_field(*generate, commands);
  add_tree(*generate, commands);
  add_landscape(*generate, commands);
}

}  // namespace farfield::cli
