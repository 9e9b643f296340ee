// What a bake leaves in a .ffpack beside its blobs (docs/ffpack.md): the technique's bake
// format, the fingerprint of the scene it was made for, the settings it was made with, and its
// figures (bake_s). One metadata entry per technique, `NAME/bake`, written when a bake
// finishes; readers check it before they read a blob, so a pack made for another scene, or
// by a farfield whose bake format differs, is refused with a message that says to re-bake.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "farfield/core/result.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

struct BakeRecord {
  std::string technique;
  int format = 0;       // the technique's bake format (TechniqueDescriptor::bake_format)
  uint64_t scene = 0;   // scene_fingerprint of the scene baked
  double bake_s = 0.0;  // wall time of the bake that finished it
  std::map<std::string, std::string> settings;  // the baked settings, KEY -> VALUE as typed
};

// Replaces the technique's record (its own metadata write).
Result<void> write_bake_record(Store& store, const BakeRecord& record);
// Removes the technique's record: a bake about to replace its blobs first says the pack holds
// no finished bake of it, so that one killed half-way is never read as finished.
Result<void> erase_bake_record(Store& store, std::string_view technique);
// The technique's record; none when the pack holds no finished bake of it. A malformed record
// is an error naming the pack.
Result<std::optional<BakeRecord>> read_bake_record(const Store& store, std::string_view technique);

// The record of a bake that a run can use: present, of `format` (or one from `oldest` on, where
// given) and made for `scene`; errors name the pack and the technique and say how to re-bake.
Result<BakeRecord> usable_bake(const Store& store, std::string_view technique, int format,
                               uint64_t scene, int oldest = 0);

}  // namespace farfield
