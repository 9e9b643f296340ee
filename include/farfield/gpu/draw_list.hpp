// DrawList: what techniques selected for one frame, as plain data (DESIGN.md). Several
// techniques may append to one list (composite): every entry names what it draws, scene
// ranges by index range, technique meshes and textures by the handles the renderer gave out
// (gpu/device.hpp). The renderer makes the `uploads`, `mesh_uploads` and `textured_mesh_uploads`
// first, then draws `opaque` scene ranges (of the scene's buffers or of scene meshes: LODs, merged
// meshes, lit like the scene), `faded` ones, `meshes` (depth-tested, unlit, textured or not), the
// `backdrop`, `transparent` scene ranges blended, and `lines` over the top, each in the order
// given. Capacity is kept between frames: clear() does not free, but it does release the pixels the
// uploads held.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "farfield/scene/scene.hpp"

namespace farfield {

// Names of renderer resources; 0 names none. Handed out by a gpu::Device, valid until freed.
struct MeshHandle {
  uint32_t id = 0;
  explicit operator bool() const { return id != 0; }
  bool operator==(const MeshHandle&) const = default;
};
struct TextureHandle {
  uint32_t id = 0;
  explicit operator bool() const { return id != 0; }
  bool operator==(const TextureHandle&) const = default;
};

// A DrawRange drawn where its geometry lies, moved by no instance.
inline constexpr uint32_t kNoInstance = UINT32_MAX;

struct DrawRange {
  uint32_t first_index;  // into Scene::indices (or the mesh's indices), a multiple of 3
  uint32_t index_count;  // a multiple of 3
  uint32_t material;     // into Scene::materials
  // None: the scene's own buffers; else a scene mesh (Device::create_scene_mesh), drawn with
  // the scene's lighting, materials and textures.
  MeshHandle mesh{};
  // A scene mesh's range only: kNoInstance, or a scene instance (Scene::instances, whose
  // material `material` must be) whose placement moves it, so that a copy is drawn from its
  // prototype's geometry (a clusters level stored once for all copies).
  uint32_t instance = kNoInstance;
};
static_assert(sizeof(DrawRange) == 20);

// Two ranges that draw the same mesh range for instances: the renderer draws a run of such
// opaque ranges as one instanced command.
inline bool same_range_for_instances(const DrawRange& a, const DrawRange& b) {
  return a.instance != kNoInstance && b.instance != kNoInstance && a.mesh == b.mesh &&
         a.first_index == b.first_index && a.index_count == b.index_count &&
         a.material == b.material;
}

// Vertices of technique meshes (stand-ins: colour-cube faces, textured boxes, billboards):
// unlit, their colour already shaded when baked; alpha < 1 is blended. Counter-clockwise
// front faces, back faces culled.
struct ProxyVertex {
  glm::vec3 position;  // metres
  uint32_t color;      // RGBA8 unorm, R in the low byte
};
static_assert(sizeof(ProxyVertex) == 16);

// The same with texture coordinates: colour = vertex colour x texture, texels of alpha 0
// discarded (they write no depth), other alpha blended.
struct TexturedVertex {
  glm::vec3 position;  // metres
  glm::vec2 uv;        // (0, 0) is the image's top-left corner
  uint32_t color;      // RGBA8 unorm, R in the low byte
};
static_assert(sizeof(TexturedVertex) == 24);

struct ProxyMesh {
  std::vector<ProxyVertex> vertices;
  std::vector<uint32_t> indices;  // triangles
};

struct TexturedMesh {
  std::vector<TexturedVertex> vertices;
  std::vector<uint32_t> indices;  // triangles
};

// Above this many consecutive MeshDraws of one mesh and texture a frame's renderer gathers
// their indices into one draw: per-command cost dominates otherwise (thousands of cube-face
// batches); at or below it each is a command of one multi-draw.
inline constexpr size_t kMeshRangesPerCall = 64;

// An opaque scene range drawn in part, so that two representations cross-fade over frames
// (paper 001, Sec. 5.4, which blends them by transparency): a pixel is drawn where a 4 x 4
// ordered-dither threshold is below `coverage`, or, with `complement`, at or above it, so that
// a range faded in at c and another faded out (complement) at c cover every pixel once
// between them, with no sorting and no blending. Drawn after the opaque ranges.
struct FadedRange {
  DrawRange range;
  float coverage;  // in [0, 1]
  bool complement = false;
};

// A range of a technique mesh's triangles, with a texture for a textured mesh (none for a
// proxy mesh).
struct MeshDraw {
  MeshHandle mesh;
  uint32_t first_index;  // into the mesh's indices, a multiple of 3
  uint32_t index_count;  // a multiple of 3
  TextureHandle texture;
};

// New pixels for a texture, sized by the upload (the texture is re-allocated when the size
// changes). `pixels` stay valid while `owner` lives, and the list keeps `owner` until it is
// cleared, so a list may be drawn after the technique that filled it has moved on to the next
// frame (selection one frame ahead). An owner of null: the caller keeps the pixels alive
// until the list is drawn. The renderer lets go of each upload's pixels once they are on the
// GPU (owner released, pixels null: a list drawn again, as for a bird's-eye picture, uploads
// nothing twice), so that a list of many large uploads never holds them all twice.
struct TextureUpload {
  TextureHandle texture;
  int width, height;              // pixels
  int channels;                   // 3 (RGB8) or 4 (RGBA8, alpha = coverage)
  mutable const uint8_t* pixels;  // rows from the top
  mutable std::shared_ptr<const void> owner;
  bool mipmaps = false;  // a full mip chain, trilinear (textured meshes); else one level
  bool nearest = false;  // one level sampled at the nearest texel (image levels that add up)
};

// New contents for a textured mesh (Device::create_textured_mesh), replacing its buffers
// before anything of the list is drawn, as SceneMeshUpload for scene meshes.
struct TexturedMeshUpload {
  MeshHandle mesh;
  std::shared_ptr<const TexturedMesh> data;
};

// Geometry in the scene's vertex format for a scene mesh: `uvs` one per vertex, or empty.
struct SceneMeshData {
  std::vector<Vertex> vertices;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> indices;  // triangles, from the first vertex
  uint64_t byte_size() const {
    return vertices.size() * sizeof(Vertex) + uvs.size() * sizeof(glm::vec2) +
           indices.size() * sizeof(uint32_t);
  }
};

// New contents for a scene mesh (Device::create_scene_mesh), replacing its buffers before
// anything of the list is drawn: streamed geometry, where a mesh of a bounded pool takes the
// chunk it holds now (gpu/mesh_pool.hpp). The list keeps the data until it is cleared.
struct SceneMeshUpload {
  MeshHandle mesh;
  std::shared_ptr<const SceneMeshData> data;
};

// A quadrilateral showing a texture: corners at the image's top-left, top-right,
// bottom-right and bottom-left. Blended with the texture's alpha times `opacity` over what
// is there; or added to it scaled by that: image differences (paper 003, Sec. 2.3), whose
// texels are >= 0 (add) or signed and stored offset by 128 (add_signed).
struct TexturedQuad {
  std::array<glm::vec3, 4> corners;
  TextureHandle texture;
  float opacity = 1.0f;
  enum class Blend : uint8_t { over, add, add_signed } blend = Blend::over;
};

// How the backdrop quads are drawn.
enum class BackdropMode : uint8_t {
  // Behind everything, in order, filling only what no geometry covers, so that all geometry
  // lands in front of them (a near object that crosses the far-field box is not cut).
  far,
  // At their place in the world, depth-tested, both sides (bird's-eye pictures).
  in_world,
};

// A line in the picture (bird's-eye annotations: frusta, viewcells), drawn over everything.
struct LineSegment {
  glm::vec3 from, to;
  uint32_t color;  // RGBA8, R in the low byte
};

// What a list's uploads bring in, by kind (textures cost a frame more a byte than meshes:
// their mipmaps).
struct UploadBytes {
  uint64_t meshes = 0, textures = 0;
  uint64_t total() const { return meshes + textures; }
};

struct DrawList {
  std::vector<DrawRange> opaque;
  std::vector<DrawRange> transparent;
  // Scene triangles too scattered for ranges of the scene's indices (paper 003's visible
  // triangles: a city's are runs of one or two): their indices, the scene's own (three a
  // triangle), in `scene_indices`, and runs of them of one material each (DrawRange::
  // first_index and index_count into scene_indices; `mesh` unused). Drawn lit as the ranges
  // are, a run one draw command: the opaque runs after the opaque ranges, grouped by how
  // their materials are drawn as those are; the transparent runs after the transparent
  // ranges, in order.
  std::vector<uint32_t> scene_indices;
  std::vector<uint32_t> scene_triangles;  // per triangle of scene_indices, its number (index / 3)
  std::vector<DrawRange> indexed_opaque, indexed_transparent;
  std::vector<FadedRange> faded;
  std::vector<MeshDraw> meshes;
  std::vector<TextureUpload> uploads;
  std::vector<SceneMeshUpload> mesh_uploads;
  std::vector<TexturedMeshUpload> textured_mesh_uploads;
  std::vector<TexturedQuad> backdrop;
  BackdropMode backdrop_mode = BackdropMode::far;
  std::vector<LineSegment> lines;
  // Drawn over the last frame instead of clearing it first: a frame drawn in parts (the
  // reference of a scene larger than the GPU's cache, eval/chunked_reference.hpp).
  bool draw_over = false;
  // The frame time the technique expects this list to take (its cost model), ms; < 0: none.
  double predicted_ms = -1.0;
  // CPU time of the frame's occlusion culling (spatial/occlusion_map.hpp), ms; < 0: none.
  double occlusion_ms = -1.0;
  // Scene geometry coloured by where it comes from (paper 001, Fig. D: by representation):
  // the ranges of a mesh (id 0: the scene's own buffers) take this colour, alpha its share.
  struct Tint {
    uint32_t mesh;
    glm::vec4 colour;
  };
  std::vector<Tint> tints;

  void clear() {
    opaque.clear();
    transparent.clear();
    scene_indices.clear();
    scene_triangles.clear();
    indexed_opaque.clear();
    indexed_transparent.clear();
    faded.clear();
    meshes.clear();
    uploads.clear();
    mesh_uploads.clear();
    textured_mesh_uploads.clear();
    backdrop.clear();
    backdrop_mode = BackdropMode::far;
    lines.clear();
    draw_over = false;
    predicted_ms = -1.0;
    occlusion_ms = -1.0;
    tints.clear();
  }
  // Where the ranges and meshes end now, so that what is appended after (a technique's own
  // part of a list others fill too) can be counted apart.
  struct Ends {
    size_t opaque = 0, transparent = 0, faded = 0, meshes = 0;
  };
  Ends ends() const { return {opaque.size(), transparent.size(), faded.size(), meshes.size()}; }
  // The triangles of the opaque, transparent and faded ranges and the meshes after `from`.
  uint64_t triangle_count_since(const Ends& from) const {
    uint64_t n = 0;
    for (size_t k = from.opaque; k < opaque.size(); ++k) n += opaque[k].index_count / 3;
    for (size_t k = from.transparent; k < transparent.size(); ++k)
      n += transparent[k].index_count / 3;
    for (size_t k = from.faded; k < faded.size(); ++k) n += faded[k].range.index_count / 3;
    for (size_t k = from.meshes; k < meshes.size(); ++k) n += meshes[k].index_count / 3;
    return n;
  }
  // Scene, mesh and backdrop triangles together (two per quad).
  uint64_t triangle_count() const {
    uint64_t n = 2 * backdrop.size() + triangle_count_since({});
    for (const auto* ranges : {&indexed_opaque, &indexed_transparent})
      for (const auto& r : *ranges) n += r.index_count / 3;
    return n;
  }
  // Of those, the technique meshes' (stand-ins: two per colour-cube face, LODs, ...).
  uint64_t mesh_triangle_count() const {
    uint64_t n = 0;
    for (const auto& m : meshes) n += m.index_count / 3;
    for (const auto* ranges : {&opaque, &transparent})
      for (const auto& r : *ranges)
        if (r.mesh) n += r.index_count / 3;
    for (const auto& f : faded)
      if (f.range.mesh) n += f.range.index_count / 3;
    return n;
  }
  // Bytes the uploads copy into GPU memory (those not yet made).
  UploadBytes upload_bytes() const {
    UploadBytes n;
    for (const TextureUpload& u : uploads)
      if (u.pixels) n.textures += uint64_t(u.width) * uint64_t(u.height) * uint64_t(u.channels);
    for (const SceneMeshUpload& u : mesh_uploads) n.meshes += u.data->byte_size();
    for (const TexturedMeshUpload& u : textured_mesh_uploads)
      n.meshes += u.data->vertices.size() * sizeof(TexturedVertex) +
                  u.data->indices.size() * sizeof(uint32_t);
    return n;
  }
};

}  // namespace farfield
