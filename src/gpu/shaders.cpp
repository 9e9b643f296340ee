#include "shaders.hpp"

#include <string>

#include "farfield/core/assert.hpp"

namespace farfield::gpu {

namespace {

constexpr const char* kFadeFunctions =
    R"(// DrawList::faded: (coverage, complement); drawn wholly at (1, 0). A pixel is kept where the
// 4 x 4 ordered-dither threshold is below the coverage (complement: at or above it).
// Only the faded programs (FADED defined) discard: a discard anywhere in a shader costs
// llvmpipe its early depth test for every draw.
#ifdef FADED
layout(location = 8) uniform vec2 fade = vec2(1.0, 0.0);
bool faded_out() {
  const float bayer[16] = float[16](0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5);
  ivec2 p = ivec2(gl_FragCoord.xy) & 3;
  bool below = (bayer[p.y * 4 + p.x] + 0.5) / 16.0 < fade.x;
  return below == (fade.y != 0.0);
}
#else
bool faded_out() { return false; }
#endif
)";

// Drawn instanced (Scene::instances): where PLACED is defined, every draw command also reads
// (instanced attributes at its baseInstance, as the material) an affine placement of its
// vertices, three rows of a 3 x 4 matrix, and the rows of its normals' matrix (the inverse
// transpose of its linear part); objects drawn as they are read the identity, which changes
// no bit of a position. Without PLACED (a scene without instances) the shaders are as before.
constexpr const char* kPlacementFunctions = R"(#ifdef PLACED
layout(location = 9) in vec4 placement_x;
layout(location = 10) in vec4 placement_y;
layout(location = 11) in vec4 placement_z;
layout(location = 12) in vec3 normal_x;
layout(location = 13) in vec3 normal_y;
layout(location = 14) in vec3 normal_z;
vec3 placed(vec3 p) {
  vec4 q = vec4(p, 1.0);
  return vec3(dot(placement_x, q), dot(placement_y, q), dot(placement_z, q));
}
vec3 placed_normal(vec3 n) { return vec3(dot(normal_x, n), dot(normal_y, n), dot(normal_z, n)); }
#else
vec3 placed(vec3 p) { return p; }
vec3 placed_normal(vec3 n) { return n; }
#endif
)";

// Lambert from two directional lights plus ambient (paper 000, Sec. 5.3; gpu/lighting.hpp),
// at the vertices (Gouraud): the light on a face's front and on its back, for the fragment
// shader to pick by the side it sees (back faces are seen only through transparent surfaces,
// and shaded as seen from the eye's side). A flat face's light is the same at its corners,
// so only curved surfaces change against lighting every pixel, which cost llvmpipe a tenth
// of a frame (docs/architecture.md).
constexpr const char* kLightFunctions = R"(layout(location = 1) uniform vec3 light_dir[2];
layout(location = 3) uniform float light_weight;
layout(location = 4) uniform float ambient;
vec2 lights(vec3 n) {
  vec2 d = vec2(dot(n, light_dir[0]), dot(n, light_dir[1]));
  return ambient + light_weight * vec2(max(d.x, 0.0) + max(d.y, 0.0),
                                       max(-d.x, 0.0) + max(-d.y, 0.0));
}
)";

// The material colour is an instanced attribute (divisor 1) read at the draw's baseInstance,
// so every command of a multi-draw picks its material without gl_DrawID.
constexpr const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 color;
layout(location = 3) in vec4 material_color;
layout(location = 0) uniform mat4 view_projection;
#ifdef ONE_SIDED
layout(location = 7) uniform vec4 tint;
#endif
invariant gl_Position;  // as the visibility pass's: the same depths, pixel for pixel
out vec4 v_color;
out vec2 v_light;  // the light on the front, and on the back
void main() {
  gl_Position = view_projection * vec4(placed(position), 1.0);
  v_light = lights(normalize(placed_normal(normal)));
  v_color = vec4(color.rgb * material_color.rgb, material_color.a);
#ifdef ONE_SIDED
  v_color.rgb = min(mix(v_color.rgb, tint.rgb, tint.a) * v_light.x, vec3(1.0));
#endif
}
)";

// The light from the vertex shader (kLightFunctions) on the side seen. ONE_SIDED (opaque,
// untextured, single-sided batches, which show only fronts): the vertex shader hands over the
// colour lit and tinted, which the fragment shader writes as it comes (one varying of four
// floats instead of six, and nothing computed per pixel: 4-7% of a frame on llvmpipe).
constexpr const char* kFragmentShader = R"(#version 450 core
layout(location = 7) uniform vec4 tint;  // DrawList::tints: a colour mixed in, alpha its share
in vec4 v_color;
in vec2 v_light;
layout(location = 0) out vec4 frag_color;
void main() {
#ifdef ONE_SIDED
  frag_color = v_color;
#else
  if (faded_out()) discard;
  float light = gl_FrontFacing ? v_light.x : v_light.y;
  vec3 base = mix(v_color.rgb, tint.rgb, tint.a);
  frag_color = vec4(min(base * light, vec3(1.0)), v_color.a);
#endif
}
)";

// The scene program of a scene with textures: the same lighting, the colour times the
// material's texture (scene_textures.hpp: an array and layer per material, read per instance
// like the colour; the renderer draws each array's materials in their own multi-draws, the
// array on unit 0), wrapped here, sampled with the derivatives of the unwrapped coordinates
// (taken before any branch) so that mipmaps are chosen across a wrap's seam too; mask
// materials cut out below their cutoff and are then opaque, blend materials multiply alpha.
// Untextured materials, in any scene, keep the program above, pixel for pixel.
constexpr const char* kTexturedSceneVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 color;
layout(location = 3) in vec4 material_color;
layout(location = 4) in vec2 texcoord;
layout(location = 5) in ivec3 texturing;
layout(location = 6) in float cutoff;
layout(location = 0) uniform mat4 view_projection;
invariant gl_Position;  // as the visibility pass's
out vec4 v_color;
out vec2 v_light;  // the light on the front, and on the back
out vec2 v_texcoord;
flat out ivec3 v_texturing;
flat out float v_cutoff;
void main() {
  gl_Position = view_projection * vec4(placed(position), 1.0);
  v_light = lights(normalize(placed_normal(normal)));
  v_color = vec4(color.rgb * material_color.rgb, material_color.a);
  v_texcoord = texcoord;
  v_texturing = texturing;
  v_cutoff = cutoff;
}
)";

constexpr const char* kTexturedSceneFragmentShader = R"(#version 450 core
layout(binding = 0) uniform sampler2DArray textures;  // the batch's array
layout(location = 7) uniform vec4 tint;
in vec4 v_color;
in vec2 v_light;
in vec2 v_texcoord;
flat in ivec3 v_texturing;  // array, layer, wrap_u | wrap_v << 2 | alpha << 4
flat in float v_cutoff;
layout(location = 0) out vec4 frag_color;
float wrap(float t, int mode) {
  if (mode == 0) return fract(t);                  // repeat
  if (mode == 2) return 1.0 - abs(mod(t, 2.0) - 1.0);  // mirror
  return clamp(t, 0.0, 1.0);                        // clamp
}
void main() {
  vec2 dx = dFdx(v_texcoord), dy = dFdy(v_texcoord);
  if (faded_out()) discard;
  vec4 c = v_color;
  {
    int modes = v_texturing.z;
    vec2 uv = vec2(wrap(v_texcoord.x, modes & 3), wrap(v_texcoord.y, (modes >> 2) & 3));
    vec4 t = textureGrad(textures, vec3(uv, float(v_texturing.y)), dx, dy);
    int alpha = (modes >> 4) & 3;
    c.rgb *= t.rgb;
    if (alpha == 1) {
      if (c.a * t.a < v_cutoff) discard;
      c.a = 1.0;
    } else if (alpha == 2) {
      c.a *= t.a;
    }
  }
  float light = gl_FrontFacing ? v_light.x : v_light.y;
  c.rgb = mix(c.rgb, tint.rgb, tint.a);
  frag_color = vec4(min(c.rgb * light, vec3(1.0)), c.a);
}
)";

// Proxies carry colours shaded when they were baked (gpu/lighting.hpp): no lighting here.
constexpr const char* kProxyVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 2) in vec4 color;
layout(location = 0) uniform mat4 view_projection;
out vec4 v_color;
void main() {
  gl_Position = view_projection * vec4(position, 1.0);
  v_color = color;
}
)";

constexpr const char* kProxyFragmentShader = R"(#version 450 core
in vec4 v_color;
layout(location = 0) out vec4 frag_color;
void main() { frag_color = v_color; }
)";

// Far-field images are shaded when baked, like proxies.
constexpr const char* kQuadVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 4) in vec2 texcoord;
layout(location = 0) uniform mat4 view_projection;
out vec2 v_texcoord;
void main() {
  gl_Position = view_projection * vec4(position, 1.0);
  v_texcoord = texcoord;
}
)";

constexpr const char* kQuadFragmentShader = R"(#version 450 core
layout(binding = 0) uniform sampler2D far_image;
layout(location = 5) uniform float opacity;
// (offset, sign): the part of a signed difference drawn, max(sign (texel - offset), 0).
layout(location = 6) uniform vec2 part = vec2(0.0, 1.0);
in vec2 v_texcoord;
layout(location = 0) out vec4 frag_color;
void main() {
  vec4 texel = texture(far_image, v_texcoord);
  frag_color = vec4(max(part.y * (texel.rgb - part.x), 0.0), texel.a * opacity);
}
)";

// Textured technique meshes (cluster boxes, billboards): vertex colour x texture, unlit like
// proxies; a texel of alpha 0 (the background an impostor was rendered on) is discarded so
// that it writes no depth.
constexpr const char* kTexturedVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 2) in vec4 color;
layout(location = 4) in vec2 texcoord;
layout(location = 0) uniform mat4 view_projection;
out vec4 v_color;
out vec2 v_texcoord;
void main() {
  gl_Position = view_projection * vec4(position, 1.0);
  v_color = color;
  v_texcoord = texcoord;
}
)";

constexpr const char* kTexturedFragmentShader = R"(#version 450 core
layout(binding = 0) uniform sampler2D image;
in vec4 v_color;
in vec2 v_texcoord;
layout(location = 0) out vec4 frag_color;
void main() {
  vec4 c = v_color * texture(image, v_texcoord);
  if (c.a < 0.5 / 255.0) discard;
  frag_color = c;
}
)";

GLuint compile(GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE, length = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(length > 0 ? length : 1), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    FF_ASSERT(ok, "%s shader does not compile:\n%s",
              stage == GL_VERTEX_SHADER ? "vertex" : "fragment", log.c_str());
  }
  return shader;
}

GLuint link(const char* name, const char* vertex, const char* fragment) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDetachShader(program, vs);
  glDetachShader(program, fs);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE, length = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(length > 0 ? length : 1), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    FF_ASSERT(ok, "%s program does not link:\n%s", name, log.c_str());
  }
  return program;
}

}  // namespace

namespace {

// A scene fragment shader with kFadeFunctions after its #version line, FADED defined or not.
std::string with_fade(const char* source, bool faded) {
  std::string text = source;
  text.insert(text.find('\n') + 1, std::string(faded ? "#define FADED\n" : "") + kFadeFunctions);
  return text;
}

// A scene vertex shader with kPlacementFunctions (PLACED defined or not) and kLightFunctions
// after its #version line.
std::string with_placement(const char* source, bool placed) {
  std::string text = source;
  text.insert(text.find('\n') + 1, std::string(placed ? "#define PLACED\n" : "") +
                                       kPlacementFunctions + kLightFunctions);
  return text;
}

}  // namespace

GLuint build_scene_program(bool faded, bool placed, bool one_sided) {
  std::string vs = with_placement(kVertexShader, placed), fs = with_fade(kFragmentShader, faded);
  if (one_sided) {
    vs.insert(vs.find('\n') + 1, "#define ONE_SIDED\n");
    fs.insert(fs.find('\n') + 1, "#define ONE_SIDED\n");
  }
  return link(one_sided ? "one-sided scene" : faded ? "faded scene" : "scene", vs.c_str(),
              fs.c_str());
}

GLuint build_textured_scene_program(bool faded, bool placed) {
  return link(faded ? "faded textured scene" : "textured scene",
              with_placement(kTexturedSceneVertexShader, placed).c_str(),
              with_fade(kTexturedSceneFragmentShader, faded).c_str());
}

namespace {

// Visible triangles (paper 003, Sec. 3.1.1): the scene's positions only, and per draw command
// (an instanced attribute read at its baseInstance) the number of its first triangle, so that
// a fragment knows its triangle as that plus gl_PrimitiveID. Both passes run this shader, and
// `invariant` makes their depths equal, as the second pass's GL_EQUAL test needs.
constexpr const char* kVisibilityVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 8) in uint first_triangle;
layout(location = 0) uniform mat4 view_projection;
invariant gl_Position;
flat out uint v_first;
void main() {
  gl_Position = view_projection * vec4(placed(position), 1.0);
  v_first = first_triangle;
}
)";

constexpr const char* kVisibilityDepthFragmentShader = R"(#version 450 core
void main() {}
)";

// Only fragments that pass the depth test run (early tests), and each sets its triangle's
// bit in the occupancy vector.
constexpr const char* kVisibilityMarkFragmentShader = R"(#version 450 core
layout(early_fragment_tests) in;
layout(std430, binding = 0) buffer Occupancy { uint bits[]; };
flat in uint v_first;
void main() {
  uint t = v_first + uint(gl_PrimitiveID);
  atomicOr(bits[t >> 5u], 1u << (t & 31u));
}
)";

}  // namespace

GLuint build_visibility_depth_program(bool placed) {
  return link("visibility depth", with_placement(kVisibilityVertexShader, placed).c_str(),
              kVisibilityDepthFragmentShader);
}

GLuint build_visibility_mark_program(bool placed) {
  return link("visibility mark", with_placement(kVisibilityVertexShader, placed).c_str(),
              kVisibilityMarkFragmentShader);
}

GLuint build_quad_program() {
  return link("quad", kQuadVertexShader, kQuadFragmentShader);
}

GLuint build_textured_program() {
  return link("textured mesh", kTexturedVertexShader, kTexturedFragmentShader);
}

GLuint build_proxy_program() {
  return link("proxy", kProxyVertexShader, kProxyFragmentShader);
}

}  // namespace farfield::gpu
