// Procedural textures of `generate city --textures` (private to src/scene): facades, paving
// and asphalt made of deterministic noise (the same bytes every run, whatever the city's
// seed), and texture coordinates projected from each vertex's position along its face.
#pragma once

#include "farfield/scene/scene.hpp"
#include "farfield/scene/texture_image.hpp"

namespace farfield::city {

// 256 x 256, tiling: brick courses with mortar (light, so that the building's colours show
// through), paving slabs, and asphalt grain.
Texels facade_texels();
Texels paving_texels();
Texels asphalt_texels();

// Texture coordinates of `object`'s vertices (in Scene::uvs) projected from their positions:
// walls (normal within 45 degrees of horizontal) along the wall and down from the top, floors
// and roofs over X and Z; one texture repeat every `tile` metres.
void project_texture_coordinates(Scene& scene, const Object& object, float tile);

}  // namespace farfield::city
