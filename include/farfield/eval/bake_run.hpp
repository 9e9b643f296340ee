// `farfield bake`: one technique's bake into a .ffpack, with everything asked checked first
// (the technique bakes, its settings, the pack writable), a headless renderer for bakes that
// render, and the bake record (store/bake_record.hpp) written when it finishes. A pack this
// run created and could not fill is removed; an existing one keeps its last committed state.
#pragma once

#include <cstdint>
#include <string>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

struct BakeOutcome {
  std::string description;   // Technique::describe() after the bake
  uint64_t store_bytes = 0;  // the technique's blobs in the pack
  double seconds = 0.0;
  // The pack compacted after the bake (Store::compact): bytes given back, or why it was not
  // (the bake is complete either way).
  uint64_t compacted_bytes = 0;
  std::string compact_failure;
};

Result<BakeOutcome> run_bake(const Scene& scene, const std::string& technique,
                             const TechniqueSettings& settings, const std::string& pack,
                             Progress& progress);

}  // namespace farfield
