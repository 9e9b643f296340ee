// Google Benchmark: the CPU side of stratified rendering (paper 000) on a generated city:
// locating a viewpoint's viewcell in the k-d tree, and finding near objects through object
// boundaries for a batch of viewcells (not part of the correctness run; `make bench`).
#include <benchmark/benchmark.h>

#include <random>

#include "farfield/scene/city_generator.hpp"
#include "farfield/techniques/stratified/stratified_options.hpp"
#include "farfield/spatial/viewcell_tree.hpp"

namespace {

using farfield::CellKey;
using farfield::ViewcellTree;

const farfield::Scene& city() {
  static const farfield::Scene scene = [] {
    farfield::CityOptions options;  // the default city: 8 x 8 blocks, 1.16M triangles
    farfield::Progress quiet(true);
    return std::move(farfield::generate_city(options, quiet).value());
  }();
  return scene;
}

ViewcellTree street_tree(double viewcell) {
  const auto region = farfield::stratified::navigable_region("street", city().bounds).value();
  return std::move(ViewcellTree::create(region, viewcell, 240.0).value());
}

void BM_LocateViewcell(benchmark::State& state) {
  const ViewcellTree tree = street_tree(double(state.range(0)) / 100.0);
  std::mt19937 rng(1);
  const auto& r = tree.region();
  std::uniform_real_distribution<float> x(r.min.x, r.max.x), z(r.min.z, r.max.z);
  std::vector<glm::vec3> points(4096);
  for (auto& p : points) p = {x(rng), r.min.y + 1.0f, z(rng)};
  size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(tree.locate(points[i++ & 4095]));
  state.counters["viewcells"] = double(tree.cell_count());
}
BENCHMARK(BM_LocateViewcell)->Arg(553)->Arg(100);

void BM_NearObjectsOfViewcells(benchmark::State& state) {
  const ViewcellTree tree = street_tree(5.53);
  std::vector<farfield::Bounds3> bounds;
  for (const auto& o : city().objects) bounds.push_back(o.bounds);
  // A row of viewcells along X through the middle, like a street path.
  std::vector<CellKey> wanted;
  for (uint32_t x = 0; x < uint32_t(state.range(0)) && x < tree.cells()[0]; ++x)
    wanted.push_back({{x, 0, tree.cells()[2] / 2}});
  uint64_t near = 0;
  for (auto _ : state)
    tree.visit(bounds, &wanted, [&](const CellKey&, std::span<const uint32_t> list) {
      near += list.size();
      return true;
    });
  state.counters["viewcells/s"] =
      benchmark::Counter(double(wanted.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_NearObjectsOfViewcells)->Arg(100)->Unit(benchmark::kMillisecond);

}  // namespace
