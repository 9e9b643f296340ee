// Bird's-eye pictures (paper 000, Fig. 5-2): the scene seen from above and behind the eye,
// with the eye's view frustum drawn in red, and whatever the technique adds (its viewcell,
// its far-field box placed where it is: Technique::annotate).
#pragma once

#include "farfield/core/view.hpp"
#include "farfield/gpu/draw_list.hpp"

namespace farfield {

// Looks down at 55 degrees on the eye from `height` metres above it, along its heading.
View birdseye_view(const View& eye, float height);

// The eye's frustum as lines `length` metres long from the eye, and its far rectangle.
void add_frustum_lines(const View& eye, float length, DrawList& list);

}  // namespace farfield
