// A field of copies of one model on a square grid in the XZ plane (paper 002, Sec. 6.3: the
// scaling experiment lays out 1, 4, 16, ... trees). Each copy is one object; the model's
// material colours are folded into the vertex colours so a copy needs a single material. The
// first copy holds the model and the others are its instances (Scene::instances), which a
// scene file stores once.
#pragma once

#include <cstdint>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

struct FieldOptions {
  uint64_t count = 16;    // copies; laid out ceil(sqrt(count)) to a row along X, rows along Z
  double spacing = 10.0;  // metres between neighbouring copies' centres
};

Result<void> validate_field_options(const FieldOptions& options);

// `model` must be a valid scene with at least one triangle. Copies stand on y = 0, the grid
// centred on the origin.
Result<Scene> generate_field(const Scene& model, const FieldOptions& options, Progress& progress);

}  // namespace farfield
