// Google Benchmark: occlusion culling on the CPU (docs/occlusion.md) for `octree` on a
// generated city (4 x 4 blocks) from a street crossing, looking along the street: the frame's
// occluders rasterised and the octree's nodes and objects tested, with the objects' own
// triangles (meshes) and with boxes inside them (not part of the correctness run; `make bench`).
#include <benchmark/benchmark.h>

#include "farfield/scene/city_generator.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace {

const farfield::Scene& city() {
  static const farfield::Scene scene = [] {
    farfield::Progress quiet(true);
    farfield::CityOptions options;
    options.blocks_x = options.blocks_z = 4;
    return std::move(farfield::generate_city(options, quiet).value());
  }();
  return scene;
}

void BM_OctreeOcclusionSelect(benchmark::State& state) {
  farfield::TechniqueSettings settings;
  settings.values["octree.occlusion"] = state.range(0) ? "1" : "0";
  settings.values["octree.occluders"] = state.range(0) == 2 ? "boxes" : "meshes";
  auto technique = std::move(farfield::make_technique("octree", settings).value());
  farfield::gpu::MemoryDevice device;
  farfield::Progress quiet(true);
  if (!technique->load({city(), nullptr, device, quiet}).ok())
    state.SkipWithError("octree failed to load");
  // At eye height at the first crossing, looking along the street (+X).
  farfield::View view;
  view.pose.position = {8.0f, 1.9f, 8.0f};
  farfield::DrawList list;
  for (auto _ : state) {
    list.clear();
    technique->select({view, 0, farfield::Region::everything(), {}}, list);
    benchmark::DoNotOptimize(list.opaque.data());
  }
  state.counters["triangles"] = double(list.triangle_count());
  state.counters["occlusion_ms"] = list.occlusion_ms;
}
// 0: frustum culling alone; 1: occluder meshes (the default); 2: occluder boxes.
BENCHMARK(BM_OctreeOcclusionSelect)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace
