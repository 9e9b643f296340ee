// Google Benchmark: the clusters technique's selection (paper 001, Sec. 4.5) on a synthetic
// hierarchy the size of the 10M city's (25,600 objects on a 1.6 km grid, their levels and
// clusters with errors proportional to their size), from street level, by error and under a
// budget, with the default traversal and the paper's O(n) one (not part of the correctness
// run; `make bench`).
#include <benchmark/benchmark.h>

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/techniques/clusters/cluster_selection.hpp"

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

}  // namespace
