// Scene: a static 3D environment held as flat arrays (DESIGN.md, "Scene").
//
// Conventions: metres, right-handed, +Y up (the ground is the XZ plane), counter-clockwise
// front faces. Indices are absolute into `vertices`, so the whole scene can be drawn with one
// indexed draw. An object (the papers' "conceptual object": a building, a tree, a mesh node)
// owns one contiguous range of indices and one contiguous range of vertices.
//
// Memory: 20 bytes per vertex, 12 bytes per triangle of indices, 64 bytes per object plus
// its name; a textured object's vertices add 8 bytes each (their texture coordinates, kept
// apart in `uvs` so that untextured ones pay nothing), and textures are held compressed as
// they came (PNG or JPEG); see docs/scene.md for bytes per triangle of typical scenes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "farfield/core/bounds.hpp"
#include "farfield/scene/cells.hpp"

namespace farfield {

// What an object is; generators set it, importers use `mesh`. Stored as a byte on disk:
// append new kinds at the end, never renumber.
enum class ObjectKind : uint8_t {
  mesh = 0,  // imported or otherwise unclassified geometry
  building = 1,
  tree = 2,
  fountain = 3,
  park = 4,  // one L-shaped grass strip
  street = 5,
  curb = 6,
  ground = 7,   // the raised ground (sidewalk) of a block
  terrain = 8,  // one tile of a landscape's height field
  count_ = 9,
};

std::string_view object_kind_name(ObjectKind kind);

// Per-vertex colour modulates the material's base colour (a building's alternating floors,
// a tree's trunk and crown), so an object keeps one material and one draw range.
struct Vertex {
  glm::vec3 position;  // metres
  uint32_t normal;     // unit normal packed as GL_INT_2_10_10_10_REV (snorm x, y, z; w unused)
  uint32_t color;      // RGBA8 unorm, R in the low byte
};
static_assert(sizeof(Vertex) == 20);

inline constexpr uint32_t kNoTexture = UINT32_MAX;

// How a material's alpha is used (glTF 2.0's alphaMode).
enum class AlphaMode : uint8_t {
  opaque = 0,  // alpha ignored
  mask = 1,    // drawn opaque where alpha >= alpha_cutoff, cut out elsewhere (foliage, fences)
  blend = 2,   // semi-transparent, drawn after opaque geometry
  count_ = 3,
};
// Texture coordinates outside [0, 1] (glTF's REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT).
enum class TextureWrap : uint8_t { repeat = 0, clamp = 1, mirror = 2, count_ = 3 };

struct Material {
  glm::vec4 base_color{1.0f};     // linear RGB in [0,1], times the texture (glTF's factor)
  uint32_t texture = kNoTexture;  // base-colour texture, into Scene::textures
  AlphaMode alpha_mode = AlphaMode::opaque;
  TextureWrap wrap_u = TextureWrap::repeat, wrap_v = TextureWrap::repeat;
  uint8_t double_sided = 0;   // 1: back faces drawn too (glTF doubleSided: leaves, panes)
  float alpha_cutoff = 0.5f;  // for AlphaMode::mask
  uint32_t reserved2 = 0;
  bool textured() const { return texture != kNoTexture; }
  // Blended: AlphaMode::blend, or a base alpha below 1 (the generators' glass).
  bool transparent() const { return alpha_mode == AlphaMode::blend || base_color.a < 1.0f; }
  bool operator==(const Material&) const = default;
};
static_assert(sizeof(Material) == 32);

// A texture as stored: the compressed image (decoded when drawn or baked: texture_image.hpp).
enum class TextureCodec : uint8_t { png = 0, jpeg = 1, count_ = 2 };
struct Texture {
  std::string name;  // where it came from (a file name, or "embedded N"), for messages
  TextureCodec codec = TextureCodec::png;
  uint32_t width = 0, height = 0;
  bool has_alpha = false;  // some texel has alpha < 1
  std::vector<std::byte> encoded;
};

struct Object {
  uint32_t name_offset = 0;  // into Scene::names
  uint32_t name_size = 0;
  ObjectKind kind = ObjectKind::mesh;
  uint8_t reserved[3] = {0, 0, 0};
  uint32_t material = 0;      // into Scene::materials
  uint32_t first_index = 0;   // into Scene::indices; a multiple of 3
  uint32_t index_count = 0;   // a multiple of 3
  uint32_t first_vertex = 0;  // the vertices this object's indices refer to
  uint32_t vertex_count = 0;
  Bounds3 bounds;
  // When the material is textured: vertex first_vertex + i has texture coordinates
  // Scene::uvs[first_uv + i]. Unused (0) otherwise.
  uint32_t first_uv = 0;
  uint32_t reserved2 = 0;
  uint32_t triangle_count() const { return index_count / 3; }
};
static_assert(sizeof(Object) == 64);

// Object `object` repeats object `prototype`'s model: its vertices are the prototype's moved by
// `linear` then `offset` (instances.hpp: transform_vertex), its indices and texture
// coordinates the prototype's, its material the prototype's. A scene file stores such an
// object's geometry once, with the prototype's (docs/ffscene.md, "Instances"); in memory it is
// held expanded like any other object, so that everything that reads objects reads it as one.
struct Instance {
  uint32_t object = 0;
  uint32_t prototype = 0;  // an earlier object, not itself an instance
  glm::mat3 linear{1.0f};  // rotation and scale, determinant > 0 (no mirroring)
  glm::vec3 offset{0.0f};  // metres
  bool operator==(const Instance&) const = default;
};
static_assert(sizeof(Instance) == 56);

struct Scene {
  std::vector<Object> objects;
  std::vector<Material> materials;
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;
  std::string names;           // object names, concatenated without separators
  std::vector<glm::vec2> uvs;  // textured objects' texture coordinates (Object::first_uv)
  std::vector<Texture> textures;
  // Rooms and the portals that join them (cells.hpp); empty for scenes without.
  std::vector<Cell> cells;
  std::vector<uint32_t> cell_objects;  // Cell::first_object
  std::vector<Portal> portals;
  std::vector<glm::vec3> portal_points;  // Portal::first_point
  // Objects that repeat another's model, by increasing `object`; empty for scenes without.
  std::vector<Instance> instances;
  Bounds3 bounds;                        // of all vertices

  uint64_t triangle_count() const { return indices.size() / 3; }
  bool textured(const Object& o) const { return materials[o.material].textured(); }
  uint64_t texture_bytes() const;  // compressed, as stored
  std::string_view object_name(const Object& o) const {
    return std::string_view(names).substr(o.name_offset, o.name_size);
  }
  std::string_view cell_name(const Cell& c) const {
    return std::string_view(names).substr(c.name_offset, c.name_size);
  }
  std::span<const uint32_t> objects_of(const Cell& c) const {
    return std::span(cell_objects).subspan(c.first_object, c.object_count);
  }
  std::span<const glm::vec3> points_of(const Portal& p) const {
    return std::span(portal_points).subspan(p.first_point, p.point_count);
  }
  // Bytes held by the arrays (not counting vector slack).
  uint64_t byte_size() const;
};

// Unit normal <-> GL_INT_2_10_10_10_REV.
uint32_t pack_normal(const glm::vec3& n);
glm::vec3 unpack_normal(uint32_t packed);
uint32_t pack_color(const glm::vec4& rgba);  // each channel clamped to [0,1]
glm::vec4 unpack_color(uint32_t packed);

// Appends objects to a scene while keeping its invariants: begin_object, then vertices and
// triangles (indices relative to the object's first vertex), then end_object, which computes
// the object's bounds and grows the scene's.
class SceneBuilder {
 public:
  explicit SceneBuilder(Scene& scene) : scene_(scene) {}

  uint32_t add_material(const Material& m);  // reuses an identical existing material
  uint32_t add_texture(Texture texture);
  void begin_object(std::string_view name, ObjectKind kind, uint32_t material);
  // `uv` is kept when the object's material is textured, and ignored otherwise.
  uint32_t add_vertex(const glm::vec3& position, const glm::vec3& normal, uint32_t color,
                      glm::vec2 uv = {});
  // Local vertex numbers, counted from the object's first vertex.
  void add_triangle(uint32_t a, uint32_t b, uint32_t c);
  uint32_t vertex_count() const;  // in the current object
  // Finishes the object; an object without triangles is dropped.
  void end_object();
  // A whole object that repeats `prototype` (an earlier object of this scene, not itself an
  // instance) moved by `instance.linear` and `instance.offset`: its geometry expanded from the
  // prototype's, recorded in Scene::instances. Returns the new object's number.
  uint32_t add_instance(std::string_view name, ObjectKind kind, uint32_t prototype,
                        const glm::mat3& linear, const glm::vec3& offset);

 private:
  Scene& scene_;
  Object current_{};
  bool open_ = false;
  bool textured_ = false;  // the open object's material has a texture
};

// The scene's detail: the median of its triangles' longest edges (metres; 0 for no triangles),
// from at most `samples` triangles spread evenly over the index array. Techniques size their
// smallest representations by it (a colour cube smaller than a triangle gains nothing).
float median_triangle_edge(const Scene& scene, uint64_t samples = 1u << 20);
// The same over triangles whose indices count from the first of `vertices`.
float median_triangle_edge(std::span<const Vertex> vertices, std::span<const uint32_t> indices,
                           uint64_t samples = 1u << 20);

// The object whose index range holds `triangle` (index / 3); none past the scene's.
std::optional<uint32_t> object_of_triangle(const Scene& scene, uint64_t triangle);

// XXH3-64 of the scene's arrays: a bake records it and refuses to serve another scene.
uint64_t scene_fingerprint(const Scene& scene);

// The same fingerprint where the geometry is held elsewhere (a file being written, a scene left
// on disk): `index` holds everything but vertices, indices and texture coordinates, of which
// there are `uv_count`; `geometry` hands the bytes of the array asked for to `feed`, in order,
// in as many pieces as it likes.
enum class GeometryArray : uint8_t { vertices, indices, uvs };
using ByteSink = std::function<void(std::span<const std::byte>)>;
uint64_t scene_fingerprint(const Scene& index, uint64_t uv_count,
                           const std::function<void(GeometryArray, const ByteSink& feed)>& geometry);

// Checks every invariant a renderer relies on (ranges, indices, materials, names, bounds, and
// instances: validate_instances).
// Returns a message naming the first broken one, or an empty string.
std::string validate_scene(const Scene& scene);

// The part of validate_scene that needs no geometry: objects' ranges against the arrays' sizes,
// names, kinds, materials, textures, cells and portals.
std::string validate_scene_index(const Scene& index, uint64_t vertex_count, uint64_t index_count,
                                 uint64_t uv_count);

// The rest, for objects [first_object, first_object + object_count) of `index` whose geometry
// is held in arrays that start at the scene's vertex `vertex_base` (indices absolute, as in
// the scene), index `index_base` and texture coordinate `uv_base`: each object's indices
// within its vertices, finite positions and coordinates.
struct GeometrySpan {
  std::span<const Vertex> vertices;
  std::span<const uint32_t> indices;
  std::span<const glm::vec2> uvs;
  uint64_t vertex_base = 0, index_base = 0, uv_base = 0;
  // The scene's stored form (instances.hpp): instances hold no geometry of their own.
  bool stored = false;
};
std::string validate_geometry(const Scene& index, uint32_t first_object, uint32_t object_count,
                              const GeometrySpan& geometry);

}  // namespace farfield
