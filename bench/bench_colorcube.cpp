// Google Benchmark: the CPU side of the colour-cube walk (paper 002) over a field of 16 trees
// seen across the field as in the sub-linear experiment, with and without the occlusion
// buffer (not part of the correctness run; `make bench`).
#include <benchmark/benchmark.h>

#include <cmath>

#include <glm/trigonometric.hpp>

#include "farfield/scene/field_generator.hpp"
#include "farfield/scene/tree_generator.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace {

const farfield::Scene& field() {
  static const farfield::Scene scene = [] {
    farfield::Progress quiet(true);
    const farfield::Scene tree = std::move(farfield::generate_tree({}, quiet).value());
    return std::move(
        farfield::generate_field(tree, {.count = 16, .spacing = 37.35}, quiet).value());
  }();
  return scene;
}

void BM_ColorcubeSelect(benchmark::State& state) {
  farfield::TechniqueSettings settings;
  settings.values["colorcube.depth"] = "8";
  settings.values["colorcube.occlusion"] = std::to_string(state.range(0));
  auto technique = std::move(farfield::make_technique("colorcube", settings).value());
  farfield::gpu::MemoryDevice device;
  farfield::Progress quiet(true);
  if (!technique->load({field(), nullptr, device, quiet}).ok())
    state.SkipWithError("colorcube failed to load");
  // From the field's corner, looking across it at 25 degrees, like the experiment's viewer.
  farfield::View view;
  const float corner = -1.5f * 37.35f, back = 112.0f, yaw = glm::radians(25.0f);
  view.pose.position = {corner - back * std::cos(yaw), 6.1f, corner - back * std::sin(yaw)};
  view.pose.yaw_deg = 25.0f;
  view.pose.pitch_deg = -2.0f;
  farfield::DrawList list;
  for (auto _ : state) {
    list.clear();
    technique->select({view, 0, farfield::Region::everything(), {}}, list);
    benchmark::DoNotOptimize(list.meshes.data());
  }
  state.counters["mesh_triangles"] = double(list.mesh_triangle_count());
}
BENCHMARK(BM_ColorcubeSelect)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
