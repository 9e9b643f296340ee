// The check every baked mesh of the clusters pack gets when read back (levels of detail and
// cluster meshes alike): texture coordinates one per vertex or none, indices within the
// vertices.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace farfield {

// What is wrong with the arrays, or null where nothing is.
inline const char* mesh_arrays_problem(size_t vertices, size_t uvs,
                                       std::span<const uint32_t> indices) {
  if (uvs != 0 && uvs != vertices) return "texture coordinates are not one per vertex";
  for (uint32_t i : indices)
    if (i >= vertices) return "an index past the vertices";
  return nullptr;
}

}  // namespace farfield
