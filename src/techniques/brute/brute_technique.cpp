#include "brute_technique.hpp"

#include "farfield/techniques/object_set.hpp"

namespace farfield {

Result<void> BruteTechnique::load(const Scene& scene) {
  ObjectSet all(scene);
  all.insert_all();
  everything_.clear();
  all.emit(everything_);
  return {};
}

void BruteTechnique::select(const View&, const FrameBudget&, DrawList& out) {
  out.clear();  // everything, bird's-eye lines of a previous frame included
  out.opaque.assign(everything_.opaque.begin(), everything_.opaque.end());
  out.transparent.assign(everything_.transparent.begin(), everything_.transparent.end());
}

}  // namespace farfield
