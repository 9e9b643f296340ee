// Google Benchmark: the clusters technique's selection (paper 001, Sec. 4.5) on a synthetic
// hierarchy the size of the 10M city's (25,600 objects on a 1.6 km grid, their levels and
// clusters with errors proportional to their size), from street level, by error and under a
// budget, with the default traversal and the paper's O(n) one (not part of the correctness
// run; `make bench`). With FARFIELD_BENCH_SCENE, FARFIELD_BENCH_PACK (a clusters bake of it)
// and FARFIELD_BENCH_PATH set, also on that bake along that path, as the technique selects:
// accuracy tables, textured boxes, the occluder boxes' map, hysteresis of 8 frames, a budget
// of FARFIELD_BENCH_TRIANGLES (150,000 by default); `/cold` runs with the caches flushed
// between frames, as drawing a frame flushes them in a walk.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/core/camera_path.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/spatial/occluders.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/clusters/cluster_selection.hpp"
#include "farfield/techniques/clusters/occluder_boxes.hpp"

namespace {

using namespace farfield;

struct Synthetic {
  Scene scene;
  LodSet lods;
  ClusterTree tree;
};

const Synthetic& synthetic() {
  static const Synthetic s = [] {
    Synthetic out;
    out.scene.materials.push_back(Material{});
    constexpr int kSide = 160;
    for (int z = 0; z < kSide; ++z)
      for (int x = 0; x < kSide; ++x) {
        Object o;
        o.material = 0;
        o.index_count = 3 * 400;
        const float height = 10.0f + float((x * 7 + z * 13) % 40);
        o.bounds = {{x * 10.0f + 1.0f, 0.0f, z * 10.0f + 1.0f},
                    {x * 10.0f + 9.0f, height, z * 10.0f + 9.0f}};
        out.scene.objects.push_back(o);
      }
    out.lods.first_lod.push_back(0);
    for (uint32_t i = 0; i < out.scene.objects.size(); ++i) {
      const float size = glm::length(out.scene.objects[i].bounds.size());
      for (int level = 0; level < 3; ++level)
        out.lods.lods.push_back(
            {i, 0, uint32_t(3 * (200 >> (2 * level))), size * 0.005f * float(1 << (2 * level))});
      out.lods.first_lod.push_back(uint32_t(out.lods.lods.size()));
    }
    out.tree = build_cluster_cells(out.scene, {});
    out.tree.parts.push_back({0, 3, 0, 0});
    for (ClusterNode& node : out.tree.nodes) {
      if (node.objects_end - node.objects_begin < 2) continue;
      node.parts_begin = 0;
      node.parts_end = 1;
      node.triangles = 2048;
      node.error_m = 0.01f * glm::length(node.bounds.size());
    }
    return out;
  }();
  return s;
}

// Along a street of the grid at eye height, looking down it.
void BM_ClustersSelect(benchmark::State& state) {
  const Synthetic& s = synthetic();
  ClusterSelection selection(s.scene, s.tree, s.lods);
  View view;
  view.pose.position = {800.0f, 1.7f, 5.0f};
  view.pose.yaw_deg = 90.0f;
  const Frustum frustum(view);
  SelectionView sv;
  sv.frustum = &frustum;
  sv.eye = view.pose.position;
  sv.pixel = 2.0f * std::tan(glm::radians(view.hfov_deg) * 0.5f) / float(view.width);
  sv.max_triangles = state.range(1) ? 500000.0 : -1.0;
  const ClusterTraversal traversal =
      state.range(0) ? ClusterTraversal::paper : ClusterTraversal::refined;
  std::vector<Choice> choices;
  SelectionStats stats;
  for (auto _ : state) {
    stats = selection.select(sv, traversal, choices);
    benchmark::DoNotOptimize(choices.data());
  }
  state.counters["visited"] = double(stats.nodes_visited);
  state.counters["choices"] = double(choices.size());
  state.counters["triangles"] = double(stats.triangles);
}
// Args: traversal (0 refined, 1 paper), mode (0 by error, 1 under a budget of 500k triangles).
BENCHMARK(BM_ClustersSelect)
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({0, 1})
    ->Args({1, 1})
    ->Unit(benchmark::kMicrosecond);

// A clusters bake read as the technique reads it, without its meshes and images.
struct Baked {
  Scene scene;
  LodSet lods;
  ClusterTree tree;
  BoxSet boxes;
  AccuracyTable accuracy;
  std::vector<Bounds3> occluder_boxes;
  CameraPath path;
};

template <typename T>
T checked(Result<T> r) {
  if (!r) {
    std::fprintf(stderr, "bench_clusters: %s\n", r.error().message.c_str());
    std::exit(1);
  }
  return std::move(*r);
}

const Baked& baked() {
  static const std::unique_ptr<Baked> b = [] {
    auto out = std::make_unique<Baked>();
    out->scene = checked(read_scene(std::getenv("FARFIELD_BENCH_SCENE")));
    const Store store = checked(Store::open(std::getenv("FARFIELD_BENCH_PACK"), Store::Mode::kRead));
    out->lods = checked(load_lod_set(store, out->scene, GeometryLoad::index_only));
    out->tree = checked(load_cluster_tree(store, out->scene, GeometryLoad::index_only));
    out->boxes = checked(load_box_set(store, out->scene, out->tree, false));
    out->accuracy = checked(load_accuracy_table(store, out->lods, out->tree, out->boxes));
    out->occluder_boxes = checked(load_occluder_boxes(store, out->scene));
    out->path = checked(read_camera_path(std::getenv("FARFIELD_BENCH_PATH")));
    return out;
  }();
  return *b;
}

// Each iteration one frame of the path, in order (the selection's hysteresis sees a walk); the
// occlusion map filled outside the timing.
void select_baked(benchmark::State& state, ClusterTraversal traversal, bool cold) {
  std::vector<uint8_t> flush(cold ? 64u << 20 : 0);
  const Baked& b = baked();
  ClusterSelection selection(b.scene, b.tree, b.lods, &b.boxes);
  Occluders occluders(b.scene, OccluderOptions{}, b.occluder_boxes);
  OcclusionMap occlusion;
  const char* budget = std::getenv("FARFIELD_BENCH_TRIANGLES");
  std::vector<Choice> choices;
  SelectionStats stats;
  uint64_t visited = 0;
  size_t frame = 0;
  for (auto _ : state) {
    state.PauseTiming();
    View view;
    view.pose = b.path.frames[frame++ % b.path.frames.size()];
    const Frustum frustum(view);
    // Cold: the caches emptied as a frame's drawing empties them, before the occlusion map is
    // filled (a frame fills it just before it selects).
    for (size_t i = 0; i < flush.size(); i += 64) flush[i] += uint8_t(frame);
    benchmark::DoNotOptimize(flush.data());
    occluders.fill(occlusion, view, frustum);
    SelectionView sv;
    sv.frustum = &frustum;
    sv.eye = view.pose.position;
    sv.pixel = 2.0f * std::tan(glm::radians(view.hfov_deg) * 0.5f) / float(view.width);
    sv.max_triangles = budget ? std::atof(budget) : 150000.0;
    sv.hysteresis = 12;  // the default (clusters.hysteresis)
    sv.occlusion = &occlusion;
    sv.accuracy = b.accuracy.empty() ? nullptr : &b.accuracy;
    state.ResumeTiming();
    stats = selection.select(sv, traversal, choices);
    benchmark::DoNotOptimize(choices.data());
    visited += stats.nodes_visited;
  }
  state.counters["visited"] = double(visited) / double(std::max<size_t>(frame, 1));

}

}  // namespace

// The baked benchmark only where its data is named.
int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (std::getenv("FARFIELD_BENCH_SCENE") && std::getenv("FARFIELD_BENCH_PACK") &&
      std::getenv("FARFIELD_BENCH_PATH"))
    for (const bool cold : {false, true})
      for (const ClusterTraversal traversal : {ClusterTraversal::refined, ClusterTraversal::paper}) {
        const std::string name = std::string("BM_ClustersSelectBaked/") +
                                 (traversal == ClusterTraversal::paper ? "paper" : "refined") +
                                 (cold ? "/cold" : "/warm");
        auto* b = benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
          select_baked(state, traversal, cold);
        });
        b->Unit(benchmark::kMicrosecond);
        if (cold) b->Iterations(600);  // two walks of a 300-frame path
      }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
}
