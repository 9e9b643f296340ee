#include "clusters_technique.hpp"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <span>
#include <tuple>

#include "farfield/core/text.hpp"
#include "farfield/store/bake_record.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/clusters/occluder_boxes.hpp"

namespace farfield {

namespace {

// Under a budget with the scene on disk, the share of a frame's time its uploads may take.
constexpr double kUploadShare = 0.25;
// With the scene on disk, the boxes' tiles by default (box_atlas.hpp).
constexpr int kStreamedTilePx = 512;

constexpr SettingSpec kSettings[] = {
    {.key = "error_px",
     .type = SettingType::number,
     .default_value = "1",
     .help = "an object is drawn as the coarsest level whose geometric error projects below "
             "this many pixels (the full object where none does)",
     .unit = "px",
     .min = 0,
     .max = 1e4},
    {.key = "average_px",
     .type = SettingType::number,
     .default_value = "1",
     .help = "a textured box whose object (or cluster) spans fewer pixels than this (its "
             "bounds' diagonal) is drawn as its average-colour box instead: per side the mean "
             "colour of its image over the share of the side it covers (paper 001, Sec. 4.2: "
             "\"less than a few pixels\"); without a budget only within error_px; 0: never",
     .unit = "px",
     .min = 0,
     .max = 1e4},
    {.key = "levels",
     .type = SettingType::integer,
     .default_value = "6",
     .help = "simplified levels an object may have, each about half the triangles of the last",
     .min = 1,
     .max = 16,
     .baked = true},
    {.key = "min_triangles",
     .type = SettingType::integer,
     .default_value = "8",
     .help = "an object with no more triangles gets no further level",
     .min = 1,
     .max = 1e6,
     .baked = true},
    {.key = "leaf_objects",
     .type = SettingType::integer,
     .default_value = "16",
     .help = "a cell of the cluster hierarchy with more objects wholly inside is split in eight",
     .min = 1,
     .max = 1e6,
     .baked = true},
    {.key = "loose",
     .type = SettingType::number,
     .default_value = "0.5",
     .help = "an octant of the hierarchy takes the objects whose centre it holds that fit in it "
             "grown by this share of its size on every side (a loose octree); 0: the paper's "
             "cells, where what crosses a cell's middle stays in the cell",
     .min = 0,
     .max = 4,
     .baked = true},
    {.key = "cluster_triangles",
     .type = SettingType::integer,
     .default_value = "2048",
     .help = "triangles of a cluster's merged mesh (at most half of its objects')",
     .min = 1,
     .max = 1e7,
     .baked = true},
    {.key = "cluster_input_triangles",
     .type = SettingType::integer,
     .default_value = "1048576",
     .help = "a cluster is simplified from at most this many triangles: its objects' full "
             "geometry where that holds no more, else their finest levels of detail that do "
             "(their error added to its own), so that a node's work and memory stay bounded on "
             "any scene; 0: always the full geometry (paper 001, Sec. 4.4: the root takes the "
             "whole scene at once)",
     .min = 0,
     .max = 4e9,
     .baked = true},
    {.key = "boxes",
     .type = SettingType::choice,
     .default_value = "objects",
     .help = "textured boxes baked (paper 001, Sec. 5.1: each rendered onto the sides of its "
             "bounding box, drawn as up to 12 triangles): objects (of 32 triangles or more), "
             "all (clusters too, the paper's; a cluster's box seen obliquely floats lower roofs "
             "at the tallest one's height), or none",
     .choices = "all|objects|none",
     .baked = true},
    {.key = "blend_frames",
     .type = SettingType::integer,
     .default_value = "0",
     .help = "a node switching between its cluster and its children is cross-faded over this "
             "many frames (paper 001, Sec. 5.4: what was drawn there fades out as what is "
             "drawn now fades in, each on its dithered share of the pixels), the scene in "
             "memory; 0: switches at once (the default: fading costs the 10M street at 33 ms "
             "8% of frames over 1.1x the budget against 1.7%); 4 is the paper's smooth switch",
     .min = 0,
     .max = 64},
    {.key = "cost_pixels",
     .type = SettingType::flag,
     .default_value = "0",
     .help = "under a budget, the cost model has a part per pixel covered (the chosen "
             "representations' bounds on screen, estimated before drawing) beside its fixed "
             "part and its parts per triangle and per draw; 0: triangles and draws alone (the "
             "previous release's model)"},
    {.key = "pseudo_px",
     .type = SettingType::integer,
     .default_value = "0",
     .help = "0: the textured boxes' images are textures; N: pseudo-texture maps instead (paper "
             "001, Sec. 5.1: each side's image shrunk by a Gaussian to at most N texels a side, "
             "a quad of its colour per texel covered at least half, for renderers without "
             "texture mapping), with the scene in memory",
     .unit = "px",
     .min = 0,
     .max = 64},
    {.key = "billboards",
     .type = SettingType::choice,
     .default_value = "trees",
     .help = "objects whose textured box is drawn as a billboard instead (paper 001, Sec. "
             "4.1.2: the side image facing the viewer most, on a quad through the centre "
             "turned to face it, for roughly symmetric objects): trees (objects of kind "
             "tree), all, or none",
     .choices = "trees|all|none"},
    {.key = "box_texels",
     .type = SettingType::number,
     .default_value = "64",
     .help = "the boxes' texels together, millions (RGBA8: 4 bytes each and a third more for "
             "mipmaps; paper 001 kept 1)",
     .unit = "Mtexel",
     .min = 0.01,
     .max = 4096,
     .baked = true},
    {.key = "errors",
     .type = SettingType::choice,
     .default_value = "image",
     .help = "image: a representation's error is how far its image, from the direction it is "
             "seen from, is from the full geometry's (the bake's accuracy tables, paper 001, "
             "Sec. 3.2), down to the tables' finest texel, and the geometric error below it; "
             "tables: the tables' errors at every scale (extrapolated below their finest "
             "texel); geometric: the distance between the surfaces (a box: the depth behind its "
             "sides); without tables in the pack, geometric",
     .choices = "image|tables|geometric"},
    {.key = "accuracy_directions",
     .type = SettingType::integer,
     .default_value = "16",
     .help = "directions over the sphere the accuracy tables compare each representation "
             "from (the paper used 5); 0: no tables",
     .min = 0,
     .max = 4096,
     .baked = true},
    {.key = "accuracy_px",
     .type = SettingType::integer,
     .default_value = "64",
     .help = "texels across a representation's bounding sphere in the tables' finest "
             "comparison (three coarser levels follow, each half the last)",
     .unit = "px",
     .min = 16,
     .max = 4096,
     .baked = true},
    {.key = "comparator",
     .type = SettingType::choice,
     .default_value = "ssim",
     .help = "ssim: structural similarity of the grey images over the windows something "
             "covers; edges: the paper's (5x5 Laplacian zero crossings, blurred, compared)",
     .choices = "ssim|edges",
     .baked = true},
    {.key = "accuracy_threshold",
     .type = SettingType::number,
     .default_value = "0.97",
     .help = "the similarity at which a representation's image passes at a level of the tables",
     .min = 0.01,
     .max = 1,
     .baked = true},
    {.key = "benefit_size",
     .type = SettingType::number,
     .default_value = "0",
     .help = "under a budget, the weight of image-space size in the benefit that orders "
             "refinements (paper 001, Sec. 3.1; all four weights 0: the projected error alone)",
     .min = 0,
     .max = 100},
    {.key = "benefit_focus",
     .type = SettingType::number,
     .default_value = "0",
     .help = "the weight of nearness to the line of sight in the benefit",
     .min = 0,
     .max = 100},
    {.key = "benefit_speed",
     .type = SettingType::number,
     .default_value = "0",
     .help = "the weight of slowness across the screen in the benefit",
     .min = 0,
     .max = 100},
    {.key = "benefit_semantics",
     .type = SettingType::number,
     .default_value = "0",
     .help = "the weight of the object's kind in the benefit (buildings 1, trees 0.8, terrain "
             "0.7, streets and ground 0.5)",
     .min = 0,
     .max = 100},
    {.key = "traversal",
     .type = SettingType::choice,
     .default_value = "refined",
     .help = "refined: visit only the nodes refined and their children; paper: first look at "
             "every node and object (paper 001, Sec. 4.5.1, O(n) a frame)",
     .choices = "refined|paper"},
    {.key = "over_share",
     .type = SettingType::number,
     .default_value = "0.03",
     .help = "under a budget, the share of frames the aim lets run over 1.1x the budget: frames "
             "aim at 1.1x the budget over this quantile from the top of the last 128 frames' "
             "measured / predicted times (budget_target.hpp)",
     .min = 0.005,
     .max = 0.5},
    {.key = "hysteresis",
     .type = SettingType::integer,
     .default_value = "12",
     .help = "under a budget, frames a cluster waits before it is refined into its children "
             "(paper 001, Sec. 4.6; which clusters wait: clusters.hysteresis_rule), with the "
             "scene in memory once the cost model tells its parts apart; 0: none",
     .unit = "frames",
     .min = 0,
     .max = 1000},
    {.key = "hysteresis_rule",
     .type = SettingType::choice,
     .default_value = "paper",
     .help = "flips: only a cluster that went back from its children within the last "
             "clusters.hysteresis frames waits; paper: every refinement of a cluster drawn last "
             "frame waits (paper 001, Sec. 4.6)",
     .choices = "flips|paper"},
    {.key = "occlusion",
     .type = SettingType::flag,
     .default_value = "1",
     .help = "skip what the nearest opaque objects hide (spatial/occluders.hpp, checked on "
             "the CPU each frame)"},
    {.key = "occluders",
     .type = SettingType::choice,
     .default_value = "auto",
     .help = "with occlusion: boxes inside the nearest objects (0.3 ms a frame on the 10M "
             "street); meshes, their own triangles sampled at every pixel (8 ms; hides twice as "
             "much; a level of detail drawn instead of an object differs from it by its error); "
             "auto: boxes under a frame budget, whose time they would take, meshes without",
     .choices = "auto|boxes|meshes"},
    {.key = "occluder_count",
     .type = SettingType::integer,
     .default_value = "128",
     .help = "with occlusion: occluders a frame, the nearest objects' first (one that nearer "
             "ones hide is skipped, not counted)",
     .unit = "objects",
     .min = 1,
     .max = 1e5},
    {.key = "wait",
     .type = SettingType::flag,
     .default_value = "0",
     .help = "with the scene left on disk (--cache-mb): wait until every page the frame "
             "chose is loaded, so that nothing is drawn coarser than chosen (for references "
             "and tests); 0: stand in the nearest coarser resident representation, never wait"},
    {.key = "prefetch_frames",
     .type = SettingType::integer,
     .default_value = "15",
     .help = "with the scene left on disk (--cache-mb): every fourth frame, the hierarchy is "
             "also selected for where the viewer will be this many frames ahead at its present "
             "velocity, and what that selection draws is asked for after the frame's own "
             "pages (the nearest first); 0: no prefetch",
     .min = 0,
     .max = 1000},
    {.key = "box_tile_px",
     .type = SettingType::integer,
     .default_value = "0",
     .help = "the boxes' images are drawn from tiles of this many texels a side, the bake's "
             "pages' boxes packed again (larger for a box that does not fit one); 0: 512 with "
             "the scene left on disk (--cache-mb: a tile is read as the walk wants its boxes), "
             "the bake's pages with the scene in memory (fewer textures to draw from); the "
             "pages' size or more: the pages",
     .unit = "texels",
     .min = 0,
     .max = 16384},
    {.key = "threads",
     .type = SettingType::integer,
     .default_value = "0",
     .help = "simplification threads; 0: all cores",
     .min = 0,
     .max = 1024},
};

}  // namespace

const TechniqueDescriptor clusters_descriptor{
    .name = "clusters",
    .summary =
        "a hierarchy of merged cluster meshes and object LODs (meshoptimizer) within a projected "
        "error or a frame budget (paper 001, under way)",
    .paper = "001",
    .settings = kSettings,
    .bake = BakeUse::optional,
    .bake_format = 8,  // 8: an instance's levels are its prototype's ranges
    .plain_scene_format = 7,
    .bake_renders = true,
    .bake_images_small = true,
    .streams = true,
    .distributes = true,
    .make = [](const SettingValues& v,
               const TechniqueSettings&) -> Result<std::unique_ptr<Technique>> {
      ClustersOptions o;
      o.error_px = float(v.number("error_px"));
      o.average_px = float(v.number("average_px"));
      o.lods.max_levels = v.integer("levels");
      o.lods.min_triangles = uint32_t(v.integer("min_triangles"));
      o.lods.threads = v.integer("threads");
      o.tree.leaf_objects = uint32_t(v.integer("leaf_objects"));
      o.tree.cluster_triangles = uint32_t(v.integer("cluster_triangles"));
      o.tree.loose = float(v.number("loose"));
      o.tree.input_triangles = uint64_t(v.integer("cluster_input_triangles"));
      o.tree.threads = o.lods.threads;
      o.boxes = v.text("boxes") != "none";
      o.box.clusters = v.text("boxes") == "all";
      o.box.max_texels = v.number("box_texels") * 1e6;
      o.billboards = v.text("billboards") == "all"    ? ClustersOptions::Billboards::all
                     : v.text("billboards") == "none" ? ClustersOptions::Billboards::none
                                                      : ClustersOptions::Billboards::trees;
      o.accuracy_tables = v.integer("accuracy_directions") > 0;
      o.accuracy.directions = v.integer("accuracy_directions");
      o.accuracy.resolution_px = v.integer("accuracy_px");
      o.accuracy.comparator =
          v.text("comparator") == "edges" ? Comparator::edges : Comparator::ssim;
      o.accuracy.threshold = v.number("accuracy_threshold");
      o.errors = v.text("errors") == "tables"      ? ClustersOptions::Errors::tables
                 : v.text("errors") == "geometric" ? ClustersOptions::Errors::geometric
                                                   : ClustersOptions::Errors::image;
      o.benefit = {float(v.number("benefit_size")), float(v.number("benefit_focus")),
                   float(v.number("benefit_speed")), float(v.number("benefit_semantics"))};
      o.hysteresis = v.integer("hysteresis");
      o.over_share = v.number("over_share");
      o.blend_frames = v.integer("blend_frames");
      o.cost_pixels = v.flag("cost_pixels");
      o.pseudo_px = v.integer("pseudo_px");
      o.wait = v.flag("wait");
      o.prefetch_frames = v.integer("prefetch_frames");
      o.box_tile_px = v.integer("box_tile_px");
      o.occlusion = v.flag("occlusion");
      o.occluders = v.text("occluders") == "boxes"    ? ClustersOptions::Occluders::boxes
                    : v.text("occluders") == "meshes" ? ClustersOptions::Occluders::meshes
                                                      : ClustersOptions::Occluders::automatic;
      o.occluder_count = uint32_t(v.integer("occluder_count"));
      o.hysteresis_rule =
          v.text("hysteresis_rule") == "paper" ? HysteresisRule::paper : HysteresisRule::flips;
      o.traversal =
          v.text("traversal") == "paper" ? ClusterTraversal::paper : ClusterTraversal::refined;
      return std::unique_ptr<Technique>(std::make_unique<ClustersTechnique>(o));
    },
};

namespace {

// Opaque ranges the renderer draws in one instanced command with another (one mesh range
// named for several instances): the frame's predicted draws count each such group once, as
// the renderer's draw calls, which the cost model learns from, do.
size_t instanced_copies(std::span<const DrawRange> ranges) {
  std::vector<DrawRange> drawn;
  for (const DrawRange& r : ranges)
    if (r.instance != kNoInstance) drawn.push_back(r);
  const auto key = [](const DrawRange& r) {
    return std::tuple(r.mesh.id, r.first_index, r.index_count, r.material);
  };
  std::sort(drawn.begin(), drawn.end(),
            [&](const DrawRange& a, const DrawRange& b) { return key(a) < key(b); });
  return drawn.size() -
         size_t(std::unique(drawn.begin(), drawn.end(), same_range_for_instances) - drawn.begin());
}

// A set's meshes, once saved in pages: its tables stay.
template <class PagedSet>
void drop_geometry(PagedSet& set) {
  set.vertices = {};
  set.uvs = {};
  set.indices = {};
}

size_t count_clusters(const ClusterTree& tree) {
  return size_t(std::count_if(tree.nodes.begin(), tree.nodes.end(),
                              [](const ClusterNode& n) { return n.clustered(); }));
}

}  // namespace

// Finished objects and clusters are kept in the pack as the bake goes (bake_work.hpp), so a
// bake killed and run again redoes only the rest; the work goes once the bake is saved. The
// levels' and clusters' meshes are saved as soon as they are made and leave memory once the
// clusters are made (the largest from the levels; the accuracy tables read both back a page
// at a time), so that the bake holds the scene, its renderer, the levels and the clusters'
// meshes at most, and a cluster's work is bounded (ClusterTreeOptions::input_triangles).
Result<void> ClustersTechnique::bake(const BakeContext& context) {
  const bool rank0 = !context.shards || context.shards->rank == 0;
  // Until it is finished, the pack holds no clusters bake.
  if (rank0)
    if (auto ok = erase_bake_record(context.store, "clusters"); !ok) return ok;
  // Levels laid out in pages of the hierarchy's neighbours (its depth-first order).
  const std::vector<uint32_t> order = build_cluster_cells(context.scene, options_.tree).objects;
  auto lods = build_lod_set(context.scene, options_.lods, context.progress, &context.store,
                            context.shards, order);
  if (!lods) return make_error("clusters: ", lods.error().message);
  if (rank0)
    if (auto ok = save_lod_set(*lods, context.store); !ok) return ok;
  // The largest clusters are made from the levels (ClusterTreeOptions::input_triangles).
  auto tree = build_cluster_tree(context.scene, options_.tree, context.progress, &context.store,
                                 context.shards, &*lods);
  if (!tree) return make_error("clusters: ", tree.error().message);
  drop_geometry(*lods);
  // Spread over ranks: the simplification was shared; the rest (boxes and tables, which
  // render, and the final blobs) is rank 0's, from every rank's work.
  if (!rank0) return {};
  if (auto ok = save_cluster_tree(*tree, context.store); !ok) return ok;
  drop_geometry(*tree);
  malloc_trim(0);  // the simplifiers' many small blocks, freed, back to the system
  if (auto ok = save_occluder_boxes(
          find_occluder_boxes(context.scene, options_.lods.threads, context.progress),
          context.store);
      !ok)
    return ok;
  // The renderer from here on only (BakeRenderer). Its images are small (tables of 64 px,
  // box sides of at most 256: bake_images_small): on the default city the tables took 23.5 s
  // instead of 52 on the calling thread, the boxes 3.1 s instead of 6.0, the pack the same.
  gpu::Renderer* renderer = nullptr;
  if ((options_.boxes || options_.accuracy_tables) && context.renderer) {
    auto made = context.renderer();
    if (!made) return made.error();
    renderer = *made;
  }
  BoxSet boxes;
  if (options_.boxes && renderer) {
    auto baked = bake_box_set(context.scene, *tree, *renderer, options_.box, context.progress);
    if (!baked) return make_error("clusters: ", baked.error().message);
    boxes = std::move(*baked);
  }
  AccuracyTable accuracy;
  if (options_.accuracy_tables && renderer) {
    auto baked = bake_accuracy_table(context.scene, *lods, *tree, boxes, *renderer,
                                     options_.accuracy, context.progress, &context.store);
    if (!baked) return make_error("clusters: ", baked.error().message);
    accuracy = std::move(*baked);
  }
  std::vector<AverageBox> averages = average_boxes(boxes);
  if (auto ok = save_box_set(boxes, context.store); !ok) return ok;
  if (auto ok = save_average_boxes(averages, context.store); !ok) return ok;
  if (auto ok = save_accuracy_table(accuracy, context.store); !ok) return ok;
  if (auto erased = context.store.erase("clusters/work/"); !erased) return erased.error();
  lods_ = std::move(*lods);
  tree_ = std::move(*tree);
  clusters_ = count_clusters(tree_);
  boxes_ = std::move(boxes);
  averages_ = std::move(averages);
  accuracy_ = std::move(accuracy);
  accuracy_px_ = float(options_.accuracy.resolution_px);
  return {};
}

Result<void> ClustersTechnique::load(const LoadContext& context) {
  // A pack that holds a clusters bake is read; without one the hierarchy is made now.
  auto record = context.store ? read_bake_record(*context.store, "clusters")
                              : Result<std::optional<BakeRecord>>(std::optional<BakeRecord>{});
  if (!record) return record.error();
  if (*record) {
    if (auto usable = usable_bake(
            *context.store, "clusters", clusters_descriptor.bake_format,
            context.on_disk ? context.on_disk->fingerprint() : scene_fingerprint(context.scene),
            clusters_descriptor.oldest_format(context.scene));
        !usable)
      return usable.error();
    // The scene left on disk: the meshes stay in the pack and stream (cluster_stream.hpp).
    const GeometryLoad geometry = context.on_disk ? GeometryLoad::index_only : GeometryLoad::whole;
    auto lods = load_lod_set(*context.store, context.scene, geometry);
    if (!lods) return lods.error();
    auto tree = load_cluster_tree(*context.store, context.scene, geometry);
    if (!tree) return tree.error();
    // On disk the boxes' images are read as the walk wants them (box_atlas.hpp).
    auto boxes = load_box_set(*context.store, context.scene, *tree, !context.on_disk);
    if (!boxes) return boxes.error();
    auto accuracy = load_accuracy_table(*context.store, *lods, *tree, *boxes);
    if (!accuracy) return accuracy.error();
    auto averages = load_average_boxes(*context.store, *boxes);
    if (!averages) return averages.error();
    auto occluder_boxes = load_occluder_boxes(*context.store, context.scene);
    if (!occluder_boxes) return occluder_boxes.error();
    occluder_boxes_ = std::move(*occluder_boxes);
    accuracy_px_ = 0.0f;  // unknown: the tables' errors at every scale
    if (auto px = (*record)->settings.find("accuracy_px"); px != (*record)->settings.end())
      accuracy_px_ = std::max(0.0f, std::strtof(px->second.c_str(), nullptr));
    return use(std::move(*lods), std::move(*tree), std::move(*boxes), std::move(*averages),
               std::move(*accuracy), context);
  }
  if (context.on_disk)
    return make_error(
        "clusters: a scene left on disk (--cache-mb) is walked from a clusters "
        "bake: bake one first (farfield bake SCENE --technique clusters --store "
        "PACK) and pass --store PACK");
  auto lods = build_lod_set(context.scene, options_.lods, context.progress, nullptr, nullptr,
                            build_cluster_cells(context.scene, options_.tree).objects);
  if (!lods) return make_error("clusters: ", lods.error().message);
  auto tree =
      build_cluster_tree(context.scene, options_.tree, context.progress, nullptr, nullptr, &*lods);
  if (!tree) return make_error("clusters: ", tree.error().message);
  // Boxes are rendered by a bake; without one there are none.
  occluder_boxes_.clear();
  return use(std::move(*lods), std::move(*tree), BoxSet{}, {}, AccuracyTable{}, context);
}

Result<void> ClustersTechnique::use(LodSet lods, ClusterTree tree, BoxSet boxes,
                                    std::vector<AverageBox> averages, AccuracyTable accuracy,
                                    const LoadContext& context) {
  const Scene& scene = context.scene;
  gpu::Device& device = context.device;
  stream_.reset();
  atlas_.reset();  // its loader reads boxes_
  lods_ = std::move(lods);
  tree_ = std::move(tree);
  boxes_ = std::move(boxes);
  // Pseudo-texture maps from the pages, before the atlas takes them (in memory only).
  pseudo_ = options_.pseudo_px > 0 && !boxes_.pages.empty()
                ? pseudo_maps(boxes_, options_.pseudo_px)
                : PseudoMaps{};
  // A pack baked before them: made from the pages where they are in memory (the atlas takes
  // them next), else none.
  averages_ =
      averages.empty() && !boxes_.pages.empty() ? average_boxes(boxes_) : std::move(averages);
  accuracy_ = std::move(accuracy);
  // Object boxes drawn as billboards (the nodes' never: a cluster is no symmetric object).
  billboard_.assign(boxes_.boxes.size(), 0);
  if (options_.billboards != ClustersOptions::Billboards::none)
    for (uint32_t o = 0; o < boxes_.object_box.size(); ++o)
      if (boxes_.object_box[o] != BoxSet::kNone &&
          (options_.billboards == ClustersOptions::Billboards::all ||
           scene.objects[o].kind == ObjectKind::tree))
        billboard_[boxes_.object_box[o]] = 1;
  scene_ = &scene;
  clusters_ = count_clusters(tree_);
  resources_.bind(device);
  lod_mesh_ = cluster_mesh_ = average_mesh_ = {};
  white_ = {};
  upload_frame_ = false;
  auto atlas = context.on_disk
                   ? BoxAtlas::create_streamed(
                         boxes_, resources_, context.store->path(),
                         gpu::MeshPoolOptions{}.upload_bytes_per_frame,
                         options_.box_tile_px > 0 ? options_.box_tile_px : kStreamedTilePx)
                   : BoxAtlas::create(boxes_, resources_, options_.box_tile_px);
  if (!atlas) return make_error("clusters: ", atlas.error().message);
  atlas_ = std::move(*atlas);
  if (context.on_disk) {
    auto stream = ClusterStream::create(*context.on_disk, *context.store, lods_, tree_, boxes_,
                                        *atlas_, device, context.cache_bytes, has_averages());
    if (!stream) return make_error("clusters: ", stream.error().message);
    stream_ = std::move(*stream);
  }
  if (has_averages() || !pseudo_.first.empty()) {  // made anew each frame from those chosen
    auto mesh = resources_.textured_mesh({}, {});
    if (!mesh) return make_error("clusters: ", mesh.error().message);
    average_mesh_ = *mesh;
    white_ = resources_.texture();
  }
  if (!lods_.indices.empty()) {
    auto mesh = resources_.scene_mesh(lods_.vertices, lods_.uvs, lods_.indices);
    if (!mesh) return make_error("clusters: ", mesh.error().message);
    lod_mesh_ = *mesh;
  }
  if (!tree_.indices.empty()) {
    auto mesh = resources_.scene_mesh(tree_.vertices, tree_.uvs, tree_.indices);
    if (!mesh) return make_error("clusters: ", mesh.error().message);
    cluster_mesh_ = *mesh;
  }
  selection_ = std::make_unique<ClusterSelection>(scene, tree_, lods_, &boxes_, has_averages());
  fades_.reset();
  if (options_.blend_frames > 0 && !stream_)
    fades_ = std::make_unique<SwitchFades>(tree_, lods_, boxes_, scene.objects.size(),
                                           options_.blend_frames);
  ahead_selection_.reset();
  ahead_choices_.clear();
  if (stream_ && options_.prefetch_frames > 0)
    ahead_selection_ =
        std::make_unique<ClusterSelection>(scene, tree_, lods_, &boxes_, has_averages());
  full_ = std::make_unique<ObjectSet>(scene);
  occluders_.reset();
  mesh_occluders_.reset();
  // With the scene on disk its triangles are not at hand: the bake's boxes are the occluders
  // (none in a pack made without them).
  if (options_.occlusion && (!stream_ || !occluder_boxes_.empty())) {
    if (stream_ || options_.occluders != ClustersOptions::Occluders::meshes)
      occluders_ = std::make_unique<Occluders>(
          scene, OccluderOptions{.per_frame = options_.occluder_count}, occluder_boxes_);
    if (!stream_ && options_.occluders != ClustersOptions::Occluders::boxes)
      mesh_occluders_ = std::make_unique<Occluders>(
          scene, OccluderOptions{.per_frame = options_.occluder_count, .meshes = true},
          occluder_boxes_);
  }
  frames_ = clusters_drawn_ = lods_drawn_ = full_drawn_ = visited_ = switches_ = boxes_drawn_ = 0;
  averages_drawn_ = billboards_drawn_ = 0;
  selection_ms_.clear();
  coarser_frames_ = stood_in_ = 0;
  cost_ = FrameCostModel(options_.cost_pixels);
  budget_target_ = BudgetTarget(options_.over_share);
  last_pixels_ = 0.0;
  last_needed_ = INFINITY;
  probe_triangles_ = 0.0;
  upload_cost_ = {};
  last_upload_bytes_ = {};
  return {};
}

void ClustersTechnique::select(const FrameInput& input, DrawList& out) {
  if (!selection_ || tree_.nodes.empty() || input.region.kind == Region::Kind::far_field) return;
  const View& view = input.view;
  ++frames_;
  frame_start_ = std::chrono::steady_clock::now();
  budget_ms_ = input.budget.target_ms;
  const Frustum frustum(view);
  SelectionView sv;
  sv.frustum = &frustum;
  sv.eye = view.pose.position;
  // A length e at distance d covers e / (d * pixel) pixels at the centre of the view.
  sv.pixel = 2.0f * std::tan(glm::radians(view.hfov_deg) * 0.5f) / float(view.width);
  if (input.region.kind == Region::Kind::near) sv.near_box = input.region.box;
  sv.error_px = options_.error_px;
  sv.average_px = options_.average_px;
  // Refinements wait (paper 001, Sec. 4.6) once the cost model tells its parts apart: before,
  // the tight first frames' clusters would wait level by level (the 10M street drew 13,000
  // triangles for its first 8 frames at 5 to 10 ms of 33). With the scene on disk the start-up
  // frames wait for their pages instead (starting()); after them, refinements wait from the
  // start, which paces the refinement to what the loaders bring.
  sv.hysteresis = cost_.separated() || (stream_ && !starting()) ? options_.hysteresis : 0;
  sv.hysteresis_rule = options_.hysteresis_rule;
  if (options_.errors != ClustersOptions::Errors::geometric && !accuracy_.empty()) {
    sv.accuracy = &accuracy_;
    if (options_.errors == ClustersOptions::Errors::image) sv.accuracy_finest_px = accuracy_px_;
  }
  sv.benefit = options_.benefit;
  sv.forward = view.pose.forward();
  sv.width_px = float(view.width);
  sv.half_fov_rad = std::atan(std::tan(glm::radians(view.hfov_deg) * 0.5f) *
                              std::sqrt(1.0f + 1.0f / (view.aspect() * view.aspect())));
  sv.velocity = frames_ > 1 ? view.pose.position - last_eye_ : glm::vec3(0.0f);
  last_eye_ = view.pose.position;
  // auto: boxes under a budget (mesh occluders' 8 ms on the 10M street would come out of
  // what the frame can draw: 26.31 dB against 31.56 at 33 ms), meshes without (the same image
  // at error_px=1 in 0.193x brute's time against 0.294x).
  Occluders* occluders = budgeted() && occluders_ ? occluders_.get()
                         : mesh_occluders_       ? mesh_occluders_.get()
                                                 : occluders_.get();
  if (occluders) {
    out.occlusion_ms = occluders->fill(occlusion_, view, frustum);
    sv.occlusion = &occlusion_;
  }
  // Paper 001, Sec. 4.5.2 under the budget: the triangles that the cost model fitted to the
  // frames measured so far predicts will fit, under the budget by the model's recent error
  // (budget_target.hpp); before any
  // frame was measured, the coarsest complete representation (a budget of no triangles), so
  // that the model starts from below: starting from the error rule's millions of small
  // triangles, the line through them and the next frame put the fixed part over the budget
  // and held the 10M fly over 20 ms for its first 13 frames. The model learns from
  // every frame, so that it predicts each frame's time (bench's predicted_ms) in both modes.
  // The frame that took the boxes' pages to the renderer timed their upload and mipmaps
  // (a second and more), not its drawing: it is not learnt from. Streamed data taken in is
  // priced apart (upload_cost.hpp): the model of triangles and draws learns the frame less
  // its uploads, and a frame's budget is what its foreseen uploads leave.
  if (!upload_frame_) {
    upload_cost_.observe(last_upload_bytes_, input.budget.last_upload_ms);
    cost_.observe(
        {double(input.budget.last_triangles), double(input.budget.last_draw_calls), last_pixels_},
        input.budget.last_frame_ms - input.budget.last_upload_ms);
    budget_target_.observe(last_predicted_ms_, input.budget.last_frame_ms, input.budget.target_ms);
  }
  upload_frame_ = false;
  last_predicted_ms_ = -1.0;
  if (input.budget.target_ms > 0.0) {
    if (stream_ && upload_cost_.ms_per_mesh_byte() > 0.0) {
      // What the scene on disk takes in a frame: at most a quarter of the budget by the
      // uploads' measured cost (half of it the pages' and chunks', half the boxes' tiles, each
      // at its own cost a byte), at least a tile's worth (a 4 MB cap cost this VM's frames up
      // to 15 ms of page faults).
      const double ms = kUploadShare * input.budget.target_ms / 2.0;
      auto cap = [&](double ms_per_byte) {
        return uint64_t(std::clamp(ms / ms_per_byte, double(1 << 20), 1e15));
      };
      stream_->set_upload_bytes_per_frame(cap(upload_cost_.ms_per_mesh_byte()));
      atlas_->set_upload_bytes_per_frame(cap(upload_cost_.ms_per_texture_byte()));
    }
    // The tiles' bytes are mostly pixels: counted as textures.
    const UploadBytes foreseen =
        stream_ ? UploadBytes{stream_->ready_bytes(), atlas_->ready_bytes()} : UploadBytes{};
    const double target_ms = std::max(
        0.0, budget_target_.target_ms(input.budget.target_ms) - upload_cost_.predict_ms(foreseen));
    sv.max_triangles = 0.0;
    if (cost_.ready()) {
      // The pixels this frame will cover are known only once it is chosen: the last frame's
      // (a refinement draws over about the pixels of what it refines).
      sv.max_triangles = cost_.triangles_within(target_ms, last_pixels_);
      // Frames of one count cannot tell the fixed part from the triangles' (the model then
      // charges all to the triangles, and the 892 triangles of the 10M city's root cluster at
      // 5 us each never afford a refinement): while the last frame was under the budget, ask
      // for twice its triangles, so that the counts vary; and where the last frame skipped a
      // refinement for want of budget, for what that needed, doubled every such frame (a
      // field of trees drawn as 456 triangles of boxes, whose first level of detail costs
      // thousands, stayed at its boxes for the whole walk at 33 ms asking for 4,000 to 9,000).
      // The doubling is held to what the last frame's time a triangle leaves of the target:
      // a model that does not separate at a held budget (a field's copies, a draw each,
      // move draws and triangles together) doubled frames at 30 of 31 ms into 60 ms ones.
      if (!cost_.separated() && input.budget.last_frame_ms < target_ms) {
        probe_triangles_ =
            std::isfinite(last_needed_) ? std::max(2.0 * probe_triangles_, last_needed_) : 0.0;
        const double growth = std::min(2.0, target_ms / std::max(input.budget.last_frame_ms, 1e-3));
        sv.max_triangles = std::max(
            {sv.max_triangles, growth * double(input.budget.last_triangles), probe_triangles_});
      } else {
        probe_triangles_ = 0.0;
      }
    }
    sv.triangles_per_draw = cost_.triangles_per_draw();
  }
  const auto selection_start = std::chrono::steady_clock::now();
  const SelectionStats stats = selection_->select(sv, options_.traversal, choices_);
  last_needed_ = stats.needed;
  selection_ms_.push_back(
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - selection_start)
          .count());
  visited_ += stats.nodes_visited;
  switches_ += stats.switches;
  if (ahead_selection_ && glm::length(sv.velocity) == 0.0f) ahead_choices_.clear();
  if (ahead_selection_ && frames_ % 4 == 1 && glm::length(sv.velocity) > 0.0f) {
    // Issue 16: prefetched from the predicted motion, the view held as it is.
    View ahead = view;
    ahead.pose.position += sv.velocity * float(options_.prefetch_frames);
    const Frustum ahead_frustum(ahead);
    SelectionView ahead_sv = sv;
    ahead_sv.frustum = &ahead_frustum;
    ahead_sv.eye = ahead.pose.position;
    ahead_sv.occlusion = nullptr;  // the map is this frame's
    ahead_selection_->select(ahead_sv, options_.traversal, ahead_choices_);
    ahead_eye_ = ahead.pose.position;
  }

  // What this frame appends, counted as the renderer counts it (what is drawn, stand-ins
  // included, not what was chosen): the cost model learns from the renderer's counts.
  const DrawList::Ends before = out.ends();
  place(out);
  if (fades_) fades_->update(selection_->switched(), choices_);
  full_->clear();
  // Ranges that follow each other in one mesh with one material are one draw; opaque ones
  // fading in or out (switch_fades.hpp) are drawn on their share of the pixels.
  float coverage = 1.0f;
  bool complement = false;
  // An instance's levels are its prototype's, placed (lod_set.hpp): a range of their own,
  // which the renderer gathers with the other copies of that level into one command.
  auto push = [&](uint32_t first, uint32_t count, uint32_t material, MeshHandle mesh,
                  uint32_t instance = kNoInstance) {
    const bool transparent = scene_->materials[material].transparent();
    if (coverage < 1.0f && !transparent) {
      out.faded.push_back({{first, count, material, mesh, instance}, coverage, complement});
      return;
    }
    auto& ranges = transparent ? out.transparent : out.opaque;
    if (!ranges.empty() && ranges.back().mesh == mesh && ranges.back().material == material &&
        ranges.back().instance == instance &&
        ranges.back().first_index + ranges.back().index_count == first)
      ranges.back().index_count += count;
    else
      ranges.push_back({first, count, material, mesh, instance});
  };
  for (const ClusterStream::Placed& p : placed_) {
    const Choice& c = p.choice;
    coverage = fades_ ? fades_->coverage(c) : 1.0f;
    switch (c.kind) {
      case Choice::Kind::cluster: {
        ++clusters_drawn_;
        const ClusterNode& node = tree_.nodes[c.index];
        for (uint32_t k = node.parts_begin; k < node.parts_end; ++k) {
          const ClusterPart& part = tree_.parts[k];
          push(part.first_index - p.index_base, part.index_count, part.material, p.mesh);
        }
        break;
      }
      case Choice::Kind::lod: {
        ++lods_drawn_;
        const Lod& lod = lods_.lods[c.index];
        push(lod.first_index - p.index_base, lod.index_count, scene_->objects[lod.object].material,
             p.mesh, lods_.instance_of(lod.object));
        break;
      }
      case Choice::Kind::whole:
        ++full_drawn_;
        if (p.mesh) {
          streamed_whole_.push_back(p);  // from its chunk, after the rest as full_'s
        } else if (coverage < 1.0f) {
          const Object& object = scene_->objects[c.index];
          push(object.first_index, object.index_count, object.material, {});
        } else {
          full_->insert(c.index);
        }
        break;
      case Choice::Kind::box:
        if (!pseudo_.first.empty()) {
          ++boxes_drawn_;
          pseudo_chosen_.push_back(c.index);
        } else if (billboard_[c.index]) {
          ++billboards_drawn_;
          billboards_chosen_.push_back(c.index);
        } else {
          ++boxes_drawn_;
          boxes_chosen_.push_back(c.index);
        }
        break;
      case Choice::Kind::average:
        ++averages_drawn_;
        averages_chosen_.push_back(c.index);
        break;
    }
  }
  coverage = 1.0f;
  full_->emit(out);  // the whole objects, in scene order
  // What the last frames drew where a node switched, fading out (in memory only: its meshes
  // are all resident).
  if (fades_) {
    complement = true;
    for (const SwitchFades::Out& o : fades_->fading_out()) {
      coverage = o.coverage;
      const Choice& c = o.choice;
      if (c.kind == Choice::Kind::cluster) {
        const ClusterNode& node = tree_.nodes[c.index];
        for (uint32_t k = node.parts_begin; k < node.parts_end; ++k)
          push(tree_.parts[k].first_index, tree_.parts[k].index_count, tree_.parts[k].material,
               cluster_mesh_);
      } else if (c.kind == Choice::Kind::lod) {
        const Lod& lod = lods_.lods[c.index];
        push(lod.first_index, lod.index_count, scene_->objects[lod.object].material, lod_mesh_,
             lods_.instance_of(lod.object));
      } else if (c.kind == Choice::Kind::whole) {
        const Object& object = scene_->objects[c.index];
        push(object.first_index, object.index_count, object.material, {});
      }
    }
    complement = false;
    coverage = 1.0f;
  }
  std::sort(streamed_whole_.begin(), streamed_whole_.end(),
            [](const ClusterStream::Placed& a, const ClusterStream::Placed& b) {
              return a.choice.index < b.choice.index;
            });
  for (const ClusterStream::Placed& p : streamed_whole_) {
    const Object& object = scene_->objects[p.choice.index];
    push(object.first_index - p.index_base, object.index_count, object.material, p.mesh);
  }
  streamed_whole_.clear();
  const size_t box_draws = atlas_->add(boxes_chosen_, out) +
                           atlas_->add_billboards(billboards_chosen_, last_eye_, out) +
                           add_averages(out);
  last_upload_bytes_ = out.upload_bytes();
  last_pixels_ = covered_pixels(view);
  if (cost_.ready()) {
    out.predicted_ms =
        cost_.predict_ms(
            {double(out.triangle_count_since(before)),
             double(out.opaque.size() + out.transparent.size() + out.faded.size() + box_draws -
                    instanced_copies(std::span(out.opaque).subspan(before.opaque))),
             last_pixels_}) +
        upload_cost_.predict_ms(last_upload_bytes_);
    last_predicted_ms_ = out.predicted_ms;
  }
}

Bounds3 ClustersTechnique::bounds_of(const Choice& c) const {
  switch (c.kind) {
    case Choice::Kind::cluster:
      return tree_.nodes[c.index].bounds;
    case Choice::Kind::lod:
      return scene_->objects[lods_.lods[c.index].object].bounds;
    case Choice::Kind::whole:
      return scene_->objects[c.index].bounds;
    case Choice::Kind::box:
    case Choice::Kind::average:
      return boxes_.boxes[c.index].bounds;
  }
  return {};
}

double ClustersTechnique::covered_pixels(const View& view) const {
  if (!options_.cost_pixels) return 0.0;
  const glm::mat4 view_projection = view.projection_matrix() * view.view_matrix();
  double pixels = 0.0;
  for (const ClusterStream::Placed& p : placed_)
    pixels += projected_pixels(bounds_of(p.choice), view_projection, view.width, view.height);
  if (fades_)
    for (const SwitchFades::Out& o : fades_->fading_out())
      pixels += projected_pixels(bounds_of(o.choice), view_projection, view.width, view.height);
  return pixels;
}

// The chosen average-colour boxes' and pseudo-texture boxes' front sides as one mesh of this
// frame, drawn with a white texture (uploaded with every such list: 4 bytes); returns the
// draws (0 or 1).
size_t ClustersTechnique::add_averages(DrawList& out) {
  if (averages_chosen_.empty() && pseudo_chosen_.empty()) return 0;
  auto mesh = std::make_shared<TexturedMesh>();
  for (uint32_t b : averages_chosen_)
    append_average_box(boxes_.boxes[b], averages_[b], last_eye_, *mesh);
  for (uint32_t b : pseudo_chosen_) append_pseudo_box(boxes_, pseudo_, b, last_eye_, *mesh);
  averages_chosen_.clear();
  pseudo_chosen_.clear();
  if (mesh->indices.empty()) return 0;
  static constexpr uint8_t kWhite[4] = {255, 255, 255, 255};
  out.uploads.push_back({white_, 1, 1, 4, kWhite, nullptr});
  out.meshes.push_back({average_mesh_, 0, uint32_t(mesh->indices.size()), white_});
  out.textured_mesh_uploads.push_back({average_mesh_, std::move(mesh)});
  return 1;
}

// The first frames of a walk from disk under a budget, until the cost model tells its parts
// apart (at most kStartFrames): refinements do not wait a level at a time (hysteresis), and
// each frame waits for the pages it chose until half its budget has gone, their uploads paced
// as in any frame. The 100M street's frame 10: 30.0 dB against 14.5 (the refinement held
// level by level, coarse clusters round the eye). Waiting without the bound brought frame 0
// to 24.6 dB against 15.2 but frames of 50 to 110 ms (p99 1.62x in a walk without brute).
bool ClustersTechnique::starting() const {
  constexpr uint64_t kStartFrames = 16;
  return stream_ && budgeted() && !cost_.separated() && frames_ <= kStartFrames;
}

// Where each choice is drawn from: the technique's meshes, or with the scene on disk what of
// the pack and the scene is resident (cluster_stream.hpp), waiting for the rest with
// clusters.wait.
void ClustersTechnique::place(DrawList& out) {
  placed_.clear();
  if (!stream_) {
    for (const Choice& c : choices_)
      placed_.push_back({c,
                         c.kind == Choice::Kind::cluster ? cluster_mesh_
                         : c.kind == Choice::Kind::lod   ? lod_mesh_
                                                         : MeshHandle{},
                         0});
    upload_frame_ = atlas_->end_frame(out);
    return;
  }
  // Start-up frames wait only until half their budget has gone (starting()).
  using Clock = std::chrono::steady_clock;
  const bool start_up = !options_.wait && starting();
  const Clock::time_point until =
      start_up ? frame_start_ + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double, std::milli>(0.5 * budget_ms_))
               : Clock::time_point::max();
  uint64_t fewest = UINT64_MAX;
  for (int stalled = 0;;) {
    const uint64_t stood_in = stream_->place(choices_, last_eye_, placed_);
    stream_->prefetch(ahead_choices_, ahead_eye_);
    stream_->end_frame(out);
    upload_frame_ = atlas_->end_frame(out) || upload_frame_;
    if (stood_in == 0) return;
    // As brute.wait: given up when three rounds in a row load nothing more, or a page cannot
    // be read.
    stalled = stood_in < fewest ? 0 : stalled + 1;
    fewest = std::min(fewest, stood_in);
    if ((!options_.wait && !start_up) || stalled >= 3 || !failure().empty() ||
        Clock::now() >= until) {
      ++coarser_frames_;
      stood_in_ += stood_in;
      return;
    }
    stream_->wait_for_loads(until);
    atlas_->wait_for_loads(until);
  }
}

void ClustersTechnique::tint(DrawList& list) const {
  list.tints.push_back({0, {0.75f, 0.75f, 0.75f, 0.85f}});
  if (lod_mesh_) list.tints.push_back({lod_mesh_.id, {0.15f, 0.75f, 0.2f, 0.85f}});
  if (cluster_mesh_) list.tints.push_back({cluster_mesh_.id, {0.95f, 0.45f, 0.1f, 0.85f}});
}

std::string ClustersTechnique::describe() const {
  // Levels of instances: their prototypes' drawn placed, no triangles of their own.
  size_t placed = 0;
  for (const Lod& lod : lods_.lods) placed += lods_.instance_of(lod.object) != kNoInstance;
  return formatted(
      "%zu levels of detail for %zu objects (%llu triangles%s), %zu nodes of which %zu clusters "
      "(%llu triangles), %zu textured boxes (%.1f Mtexel, %.3f m a texel on average; %s), "
      "accuracy tables from %zu directions",
      lods_.lods.size(), lods_.first_lod.empty() ? size_t(0) : lods_.first_lod.size() - 1,
      (unsigned long long)lods_.triangle_count(),
      placed ? formatted("; %zu levels of instances, drawn from their prototypes'", placed).c_str()
             : "",
      tree_.nodes.size(), clusters_, (unsigned long long)tree_.triangle_count(),
      boxes_.boxes.size(), double(boxes_.texels()) / 1e6, boxes_.mean_texel_m(),
      averages_.empty() ? "no average-colour boxes" : "with average-colour boxes",
      accuracy_.directions.size());
}

std::vector<std::pair<std::string, double>> ClustersTechnique::figures() const {
  auto mean = [&](uint64_t sum) { return frames_ ? double(sum) / double(frames_) : 0.0; };
  auto median = [](std::vector<double> values) {
    if (values.empty()) return 0.0;
    const auto middle = values.begin() + std::ptrdiff_t(values.size() / 2);
    std::nth_element(values.begin(), middle, values.end());
    return *middle;
  };
  std::vector<std::pair<std::string, double>> figures = {
      {"lods", double(lods_.lods.size())},
      {"lod_triangles", double(lods_.triangle_count())},
      {"nodes", double(tree_.nodes.size())},
      {"clusters", double(clusters_)},
      {"cluster_triangles", double(tree_.triangle_count())},
      {"mean_clusters_drawn", mean(clusters_drawn_)},
      {"mean_objects_as_lods", mean(lods_drawn_)},
      {"mean_objects_full", mean(full_drawn_)},
      {"boxes", double(boxes_.boxes.size())},
      {"box_texels", double(boxes_.texels())},
      {"mean_boxes_drawn", mean(boxes_drawn_)},
      {"mean_average_boxes_drawn", mean(averages_drawn_)},
      {"mean_billboards_drawn", mean(billboards_drawn_)},
      {"mean_visited", mean(visited_)},
      {"median_selection_ms", median(selection_ms_)},
      {"switches", double(switches_)},
      {"cost_fixed_ms", cost_.fixed_ms()},
      {"cost_ms_per_triangle", cost_.ms_per_triangle()},
      {"cost_ms_per_draw", cost_.ms_per_draw()},
      {"cost_ms_per_megapixel", cost_.ms_per_pixel() * 1e6}};
  if (stream_) {
    const gpu::MeshPoolCounters& c = stream_->counters();
    figures.insert(figures.end(), {{"cache_hits", double(c.hits)},
                                   {"cache_misses", double(c.misses)},
                                   {"cache_prefetches", double(c.prefetches)},
                                   {"bytes_read", double(c.bytes_read)},
                                   {"cache_evictions", double(c.evictions)},
                                   {"cache_peak_mb", double(c.peak_resident_bytes) / 1e6},
                                   {"pinned_mb", double(stream_->pinned_bytes()) / 1e6},
                                   {"box_tiles", double(atlas_->tiles())},
                                   {"box_tiles_in", double(atlas_->tiles_in())},
                                   {"box_bytes_read", double(atlas_->bytes_read())},
                                   {"coarser_frames", double(coarser_frames_)},
                                   {"stood_in", double(stood_in_)}});
  }
  return figures;
}

std::string ClustersTechnique::failure() const {
  if (stream_ && !stream_->failure().empty()) return stream_->failure();
  return atlas_ ? atlas_->failure() : std::string();
}

}  // namespace farfield
