// GLSL of the Renderer and the program object built from it.
#pragma once

#include <epoxy/gl.h>

namespace farfield::gpu {

// Attribute locations of the scene VAO.
enum : GLuint {
  kPositionAttrib = 0,
  kNormalAttrib = 1,
  kColorAttrib = 2,
  kMaterialAttrib = 3,
  kTexcoordAttrib = 4,
  kTexturingAttrib = 5,  // ivec3: a material's texture array, layer, modes (scene_textures.hpp)
  kCutoffAttrib = 6,     // float: its alpha cutoff
  kFirstTriangleAttrib = 8,  // uint per draw command: the visibility pass's first triangle
  kPlacementAttrib = 9,      // vec4 x 3 per draw command (PLACED): rows of its 3 x 4 placement
  kNormalPlacementAttrib = 12,  // vec3 x 3: rows of its normals' matrix
};
// Uniform locations.
enum : GLint {
  kViewProjectionUniform = 0,  // mat4
  kLightDirUniform = 1,        // vec3[2], unit, towards the lights
  kLightWeightUniform = 3,     // float, diffuse weight of each light
  kAmbientUniform = 4,         // float
  kOpacityUniform = 5,         // float, of a textured quad
  kPartUniform = 6,            // vec2 (offset, sign) of a textured quad: a signed difference's part
  kTintUniform = 7,            // vec4 of the scene programs: DrawList::tints
  kFadeUniform = 8,            // vec2 (coverage, complement) of the faded scene programs
};

// Compiles and links the scene shading program. A compile or link error is a programming
// error: it asserts with the GL info log.
// `faded`: the variant of DrawList::faded, kFadeUniform choosing the pixels drawn.
// `placed`: the variant of a scene drawn instanced, reading each command's placement
// (kPlacementAttrib, kNormalPlacementAttrib); every scene program of such a scene is placed.
GLuint build_scene_program(bool faded = false, bool placed = false, bool one_sided = false);
// The same for the textured materials of a scene with textures: texture coordinate (location
// 4), the material's texturing (5, 6), the batch's texture array on unit 0.
GLuint build_textured_scene_program(bool faded = false, bool placed = false);
// The unlit program of proxy geometry: position (location 0), colour (location 2), the
// view-projection matrix at kViewProjectionUniform.
GLuint build_proxy_program();
// Textured quads: position (location 0), texture coordinate (location 4), the texture on unit
// 0, kOpacityUniform multiplying its alpha, kPartUniform choosing the part of a signed image.
GLuint build_quad_program();
// The visibility pass: positions (location 0), each command's first triangle (location 8);
// the depth program writes depth only, the mark program sets each visible fragment's
// triangle bit in the shader storage buffer at binding 0.
// `placed` as for the scene programs.
GLuint build_visibility_depth_program(bool placed = false);
GLuint build_visibility_mark_program(bool placed = false);
// Textured meshes: position (0), colour (2), texture coordinate (4), the texture on unit 0.
GLuint build_textured_program();

}  // namespace farfield::gpu
