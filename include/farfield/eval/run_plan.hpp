// Everything a run was asked, checked before its first frame or file (bench, bake, view):
// technique names known, every `--set` for a technique that runs (composite's parts count),
// known and in range, bakes present in the pack, of this farfield's format and for this
// scene, settings that a bake fixes not contradicted, and output folders writable.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/store/bake_record.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield {

class ChunkedScene;

class Store;

struct PlannedTechnique {
  const TechniqueDescriptor* descriptor;
  std::optional<BakeRecord> bake;  // the pack's bake it loads from, if any
};

// `names` are the techniques asked for (`raw` excluded); `store` the --store pack or null.
// The plan has one entry per technique that runs, parts included, in the order met. With
// `others_may_be_set` (view, where every technique can be switched to) a --set of another
// technique is checked against its descriptor rather than refused.
Result<std::vector<PlannedTechnique>> plan_run(const std::vector<std::string>& names,
                                               const TechniqueSettings& settings,
                                               const Store* store, const Scene& scene,
                                               bool others_may_be_set = false,
                                               const ChunkedScene* on_disk = nullptr);

// Creates `folder` (and its parents) and proves it writable with a probe file, removed again.
Result<void> check_writable_folder(const std::string& folder);
// Proves that `file` can be written (its folder exists and takes a new file) without touching
// `file` itself.
Result<void> check_writable_file(const std::string& file);

}  // namespace farfield
