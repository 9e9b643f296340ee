// Google Benchmark: .ffscene write and read throughput, and city generation, on a generated
// city (not part of the correctness run; `make bench`).
#include <benchmark/benchmark.h>

#include <filesystem>

#include "farfield/scene/city_generator.hpp"
#include "farfield/scene/scene_file.hpp"

namespace {

const farfield::Scene& city() {
  static const farfield::Scene scene = [] {
    farfield::CityOptions options;
    options.blocks_x = options.blocks_z = 4;
    farfield::Progress quiet(true);
    return std::move(farfield::generate_city(options, quiet).value());
  }();
  return scene;
}

std::string temp_path() {
  return (std::filesystem::temp_directory_path() / "farfield-bench.ffscene").string();
}

void BM_GenerateCity(benchmark::State& state) {
  farfield::CityOptions options;
  options.blocks_x = options.blocks_z = static_cast<uint32_t>(state.range(0));
  farfield::Progress quiet(true);
  uint64_t triangles = 0;
  for (auto _ : state) triangles = farfield::generate_city(options, quiet)->triangle_count();
  state.counters["triangles/s"] =
      benchmark::Counter(double(triangles), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_GenerateCity)->Arg(2)->Arg(4)->Unit(benchmark::kMillisecond);

void BM_WriteScene(benchmark::State& state) {
  const auto& scene = city();
  for (auto _ : state) benchmark::DoNotOptimize(farfield::write_scene(scene, temp_path()).ok());
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(scene.byte_size()));
}
BENCHMARK(BM_WriteScene)->Unit(benchmark::kMillisecond);

void BM_ReadScene(benchmark::State& state) {
  (void)farfield::write_scene(city(), temp_path());
  for (auto _ : state) benchmark::DoNotOptimize(farfield::read_scene(temp_path()).ok());
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(city().byte_size()));
  std::filesystem::remove(temp_path());
}
BENCHMARK(BM_ReadScene)->Unit(benchmark::kMillisecond);

}  // namespace
