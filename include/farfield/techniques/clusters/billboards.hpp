// Billboards (paper 001, Sec. 4.1.2): one of a textured box's side images (box_set.hpp) on a
// quad through the box's centre, turned to face the viewer: "one billboard is computed for
// each face of the object's bounding box; as the observer moves around the object a
// different billboard is selected". For roughly rotationally symmetric objects such as trees,
// where a box seen obliquely shows two narrowed images side by side, wider than the object.
#pragma once

#include <glm/vec3.hpp>

#include "farfield/gpu/draw_list.hpp"
#include "farfield/techniques/clusters/box_set.hpp"

namespace farfield {

// The side shown from `eye`: the top or the bottom where the eye is more above or below the
// box's centre than beside it, else the upright side facing the eye most; a side whose image
// is empty gives way to the next best. -1: every side is empty.
int billboard_side(const TexturedBox& box, const glm::vec3& eye);

// The billboard of `box` (its sides placed in a texture `texture_px` square) seen from `eye`:
// an upright side's image stands through the centre turned about the vertical to face the
// eye; the top's or bottom's lies flat through the centre. Nothing where billboard_side is -1.
void append_billboard(const TexturedBox& box, int texture_px, const glm::vec3& eye,
                      TexturedMesh& out);

}  // namespace farfield
