#include "farfield/eval/bake_run.hpp"

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "farfield/core/mpi_world.hpp"
#include "farfield/core/text.hpp"
#include "farfield/eval/run_plan.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/store/bake_record.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

namespace {

Result<BakeOutcome> bake_into(const Scene& scene, const TechniqueDescriptor& d,
                              const SettingValues& values, const TechniqueSettings& settings,
                              const std::string& pack, Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  auto technique = d.make(values, settings);
  if (!technique) return technique.error();
  // Spread over the ranks of an MPI job: rank 0 bakes into the pack, the others their share
  // into shards beside it (BakeShards).
  const MpiWorld& world = MpiWorld::get();
  const BakeShards shards{world.rank(), world.size(), pack};
  const bool rank0 = world.rank() == 0;
  auto opened = Store::open(rank0 ? pack : shards.shard(world.rank()), Store::Mode::kReadWrite);
  if (!opened) return opened.error();
  std::optional<Store> store;
  store.emplace(std::move(*opened));
  std::unique_ptr<gpu::Context> context;
  std::unique_ptr<gpu::Renderer> renderer;
  BakeRenderer make_renderer;
  if (d.bake_renders && rank0)
    make_renderer = [&]() -> Result<gpu::Renderer*> {
      if (renderer) return renderer.get();
      // llvmpipe draws many small images faster on the calling thread alone than on every
      // core, which it wakes and waits for at each image (read when the context is made; a
      // user's value stays).
      if (d.bake_images_small) setenv("LP_NUM_THREADS", "0", 0);
      auto made_context = gpu::create_headless_context();
      if (!made_context) return made_context.error();
      context = std::move(*made_context);
      auto made = gpu::Renderer::create(scene);
      if (!made) return made.error();
      renderer = std::move(*made);
      return renderer.get();
    };
  if (auto ok = (*technique)->bake(
          {scene, *store, make_renderer, progress, world.distributed() ? &shards : nullptr});
      !ok)
    return ok.error();
  BakeOutcome outcome;
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!rank0) {
    // Shards go once the pack holds everything; this rank waits for that, its shard closed.
    auto bytes = store->total_bytes(std::string(d.name) + "/");
    if (!bytes) return bytes.error();
    outcome.store_bytes = *bytes;
    outcome.description = formatted("rank %d of %d: its share kept in %s", world.rank(),
                                    world.size(), shards.shard(world.rank()).c_str());
    store.reset();
    world.barrier();
    return outcome;
  }
  BakeRecord record{
      std::string(d.name), d.bake_format, scene_fingerprint(scene), outcome.seconds, {}};
  for (const SettingSpec& s : d.settings)
    if (s.baked) record.settings[std::string(s.key)] = values.text(s.key);
  if (auto ok = write_bake_record(*store, record); !ok) return ok.error();
  auto bytes = store->total_bytes(std::string(d.name) + "/");
  if (!bytes) return bytes.error();
  outcome.store_bytes = *bytes;
  outcome.description = (*technique)->describe();
  // A bake drops its resumable work when it ends, leaving its room free in the file.
  progress.start("compact the pack", 1);
  if (auto compacted = store->compact(); compacted)
    outcome.compacted_bytes = *compacted;
  else
    outcome.compact_failure = compacted.error().message;
  progress.finish();
  if (world.distributed()) {
    world.barrier();
    for (int r = 1; r < world.size(); ++r) {
      std::error_code ec;
      std::filesystem::remove(shards.shard(r), ec);
      for (const char* side : {"-wal", "-shm", "-journal"})
        std::filesystem::remove(shards.shard(r) + side, ec);
    }
  }
  return outcome;
}

}  // namespace

Result<BakeOutcome> run_bake(const Scene& scene, const std::string& technique,
                             const TechniqueSettings& settings, const std::string& pack,
                             Progress& progress) {
  auto d = find_technique(technique);
  if (!d) return d.error();
  if ((*d)->bake == BakeUse::none)
    return make_error("technique '", technique,
                      "' has nothing to bake; it loads in moments "
                      "from the scene (techniques that bake: colorcube, stratified)");
  for (const auto& [assignment, value] : settings.values)
    if (assignment.compare(0, technique.size() + 1, technique + ".") != 0)
      return make_error("--set ", assignment, "=", value, ": bake runs only ", technique);
  auto values = parse_settings(**d, settings);
  if (!values) return values.error();
  if (MpiWorld::get().distributed() && !(*d)->distributes)
    return make_error(technique, "'s bake does not spread over the ranks of an MPI job: run it "
                      "without mpirun (techniques that do: clusters)");
  if (auto ok = check_writable_file(pack); !ok) return ok.error();
  const bool existed = std::filesystem::exists(pack);
  auto outcome = bake_into(scene, **d, *values, settings, pack, progress);
  if (!outcome && !existed && MpiWorld::get().rank() == 0) {
    std::error_code ec;
    std::filesystem::remove(pack, ec);
  }
  return outcome;
}

}  // namespace farfield
