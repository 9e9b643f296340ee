// The clusters bake's finished work kept in the pack as it goes, so that a bake killed at any
// point and run again redoes only unfinished objects and nodes (the stratified bake does the
// same per viewcell): items (objects' LOD chains, nodes' cluster meshes) are simplified on
// every core and written, from the calling thread, in batches of consecutive items, one
// transaction each, under "clusters/work/TASK/NNNNNN". A plan blob per task (the scene's
// fingerprint and the settings the work depends on) tells a resumable bake from another one,
// whose work is erased. The final blobs replace the work when the bake ends.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/simplify.hpp"
#include "farfield/techniques/technique.hpp"

namespace farfield {

class Store;

using PartList = std::vector<SimplifiedPart>;

// The vertices and indices of every part of `items` (to reserve the arrays they go to).
struct PartSizes {
  uint64_t vertices = 0, indices = 0;
  bool fit_uint32() const { return vertices < UINT32_MAX && indices < UINT32_MAX; }
};
PartSizes sizes_of(const std::vector<PartList>& items);

class BakeWork {
 public:
  // Without a store nothing is kept (a technique loaded without a pack makes its own).
  // `plan` describes the task's work; work of another plan in the store is erased.
  // `shards`: the bake is spread over ranks (technique.hpp): run() does this rank's batches,
  // and on rank 0 takes in the others' from their shards.
  static Result<BakeWork> open(Store* store, const std::string& task, const std::string& plan,
                               const BakeShards* shards = nullptr);

  // work(item) for every item in [0, count), taken in `order` (a permutation: the costliest
  // first keeps the cores busy to the end); items of batches already in the store are read
  // instead, and said ("N of M `noun` already kept"). Shows progress as `label`. Spread over
  // ranks: this rank's batches only; then, once every rank is done (a barrier), rank 0 takes
  // the others' batches in from their shards and returns every item, other ranks their own.
  // The first `rank0_batches` batches are rank 0's whatever the ranks (work that needs what
  // only rank 0 holds).
  Result<std::vector<PartList>> run(const std::string& label, const std::string& noun, size_t count,
                                    const std::vector<uint32_t>& order, size_t batch, int threads,
                                    Progress& progress,
                                    const std::function<PartList(uint32_t)>& work,
                                    size_t rank0_batches = 0);

  // The task's work blobs, once the final ones are written.
  Result<void> erase();

 private:
  BakeWork(Store* store, std::string prefix, const BakeShards* shards)
      : store_(store), prefix_(std::move(prefix)), shards_(shards) {}
  Result<void> take_in_shards(size_t batches, size_t batch, size_t count,
                              const std::vector<uint32_t>& order, std::vector<bool>& saved,
                              std::vector<PartList>& results);
  Store* store_;
  std::string prefix_;  // "clusters/work/TASK/"
  const BakeShards* shards_ = nullptr;
};

// A batch's bytes and back (exposed for the fuzzer); reading refuses anything inconsistent
// with a message naming `what`.
std::vector<std::byte> encode_parts(const std::vector<const PartList*>& items);
Result<std::vector<PartList>> decode_parts(std::span<const std::byte> bytes, size_t items,
                                           const std::string& what);

}  // namespace farfield
