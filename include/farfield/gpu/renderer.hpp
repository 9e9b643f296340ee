// Draws a Scene's DrawLists with OpenGL 4.5 core. The whole scene lives in GPU buffers of at
// most 1 GiB each (scene_chunks.hpp), an instance's geometry only once, its prototype's
// (InstanceDrawing); a DrawList becomes multi-draw-indirect commands, opaque
// ranges first, then transparent ranges blended without depth writes. Technique meshes and textures
// are made through the Device interface and named by handle in the lists. Shading: paper 000,
// Sec. 5.3, two directional lights opposite each other 14 degrees above the horizon, plus ambient;
// colour = vertex colour x material base colour (x its texture in a textured scene: the
// scene's textures live in array textures by size, scene_textures.hpp, so textured and
// untextured ranges go out in the same multi-draws; an untextured scene keeps the untextured
// program). Depth: reversed-Z float buffer (View's projection).
//
// Needs a current Context. Not thread-safe.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include "farfield/core/image.hpp"
#include "farfield/core/result.hpp"
#include "farfield/core/view.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/gpu/device.hpp"
#include "farfield/gpu/draw_list.hpp"
#include "farfield/gpu/scene_chunks.hpp"

namespace farfield::gpu {

struct FrameStats {
  double gpu_ms = 0.0;      // GL timestamps around the frame's draws (0 if unavailable);
                            // on llvmpipe they see only part of the work: quote frame_ms
  uint64_t triangles = 0;   // submitted
  uint64_t draw_calls = 0;  // draw commands submitted (a gathered batch of many mesh
                            // ranges counts once)
  double upload_ms = 0.0;   // CPU time taking in the list's uploads (textures and meshes)
};

// How a scene's instances (Scene::instances) are drawn: `placed`, their prototype's geometry
// uploaded once and each instance's draws reading it with the instance's placement (a 3 x 4
// matrix per draw command; a translated copy's positions come out bit for bit as held), or
// `expanded`, every object's own geometry uploaded as held (for comparison).
enum class InstanceDrawing : uint8_t { placed, expanded };

class Renderer final : public Device {
 public:
  // Uploads the scene in chunks of at most `chunk_bytes` a buffer; fails (with the byte
  // count) when the GPU cannot hold it.
  static Result<std::unique_ptr<Renderer>> create(
      const Scene& scene, uint64_t chunk_bytes = kSceneChunkBytes,
      InstanceDrawing instance_drawing = InstanceDrawing::placed);
  ~Renderer() override;

  Result<MeshHandle> create_mesh(std::span<const ProxyVertex> vertices,
                                 std::span<const uint32_t> indices) override;
  Result<MeshHandle> create_textured_mesh(std::span<const TexturedVertex> vertices,
                                          std::span<const uint32_t> indices) override;
  Result<MeshHandle> create_scene_mesh(std::span<const Vertex> vertices,
                                       std::span<const glm::vec2> uvs,
                                       std::span<const uint32_t> indices) override;
  TextureHandle create_texture() override;
  void free(MeshHandle mesh) override;
  void free(TextureHandle texture) override;
  uint64_t resource_bytes() const override;

  // Renders into the current framebuffer (0 = window) or an offscreen target sized
  // view.width x view.height (see set_offscreen). Clears to the sky colour first.
  FrameStats draw(const View& view, const DrawList& list);
  // The same with any projection (bakes render through box faces, 90 x 90 degrees, and up).
  FrameStats draw_with(const glm::mat4& view_projection, int width, int height,
                       const DrawList& list);
  // The triangles of the list's scene ranges (the scene's own buffers; meshes are not
  // looked at) that the frame `view` would show: each opaque one nearest at some pixel
  // (triangles tied at a pixel all count), and each see-through one (blended, or cut out by
  // its texture's alpha) in front of the opaque ones at some pixel. Ascending triangle numbers
  // (index / 3). Drawing only these gives the frame the whole list gives, pixel for pixel
  // (paper 003, Sec. 3.1.1: there an ID buffer, which keeps one triangle a pixel and so
  // misses what shows through a transparent surface). Uses the offscreen target, as draw.
  // With `pixel` (x, y from the top left), that pixel's only.
  std::vector<uint32_t> visible_triangles(const View& view, const DrawList& list,
                                          const glm::ivec2* pixel = nullptr);
  // The scene triangle the list shows at pixel (x, y from the top left) of the frame `view`:
  // the nearest along the ray through the pixel's centre among those visible there
  // (see-through ones included); none where the list's scene ranges show nothing there
  // (the sky, or only technique meshes: stand-ins are not pickable). Paper 003, Sec. 3: the
  // hybrid renderer keeps picking; this works for every technique that draws scene geometry.
  // `scene`: the one this renderer draws.
  std::optional<uint32_t> pick(const Scene& scene, const View& view, const DrawList& list, int x,
                               int y);
  // The two lights (lighting.hpp) turned to `heading_deg` and raised to `elevation_deg`, for
  // every frame drawn after (paper 003, Sec. 3: the hybrid renderer can relight; images
  // baked earlier keep the light they were baked with).
  void set_light(float heading_deg, float elevation_deg);
  // Waits until everything drawn so far is finished (the benchmark protocol's glFinish).
  void finish();

  // The raw bound of the benchmark: every triangle of the scene in one indexed draw with
  // the same shading and no per-object work (opaque material, no blending pass).
  FrameStats draw_everything_at_once(const View& view);

  // Offscreen rendering at width x height (colour RGBA8, depth float32); 0 x 0 returns to
  // the default framebuffer.
  void set_offscreen(int width, int height);
  // Reads back the last frame (glFinish first). Offscreen target, or the default framebuffer.
  Image capture();
  // The alpha channel of the last frame, rows from the top: the clear colour's alpha where
  // nothing was drawn (see set_clear_alpha), the surfaces' coverage elsewhere.
  std::vector<uint8_t> capture_alpha();
  // The depth buffer of the last frame, rows from the top: reversed-Z (1 at the near plane,
  // 0 where nothing was drawn), as the projection put it.
  std::vector<float> capture_depth();
  // How scene textures are sampled: trilinear from their mipmaps (the default), or the
  // nearest texel (for comparisons with a CPU ray cast).
  enum class TextureFilter { trilinear, nearest };
  void set_texture_filter(TextureFilter filter);
  // GPU memory of the scene's textures (mipmaps included); 0 for an untextured scene.
  uint64_t scene_texture_bytes() const;
  // GPU memory of the scene's own geometry (vertices, indices, texture coordinates).
  uint64_t scene_geometry_bytes() const;
  // Whether the scene's instances are drawn from their prototypes' geometry (InstanceDrawing).
  bool draws_instanced() const;
  // The alpha the sky is cleared to (1 by default; 0 lets a bake find the empty pixels).
  void set_clear_alpha(float alpha);

 private:
  Renderer();
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace farfield::gpu
