// The GL objects behind the Renderer's mesh and texture handles (gpu/device.hpp). Handles are
// slot numbers plus one; a freed slot is reused by the next resource made.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <span>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/gpu/draw_list.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield::gpu {

// Immutable storage (or dynamic with GL_DYNAMIC_STORAGE_BIT); an error message naming `what`
// when the GL cannot allocate it.
Result<void> make_buffer(GLuint& buffer, const char* what, size_t bytes, const void* data,
                         GLbitfield flags);

// Vertex attribute `index` of `vao`, read from its binding `binding`.
void set_attribute(GLuint vao, GLuint index, GLint size, GLenum type, GLboolean normalized,
                   size_t offset, GLuint binding = 0);

// What a mesh's vertices are: ProxyVertex, TexturedVertex, or the scene's Vertex (with an
// optional texture coordinate buffer), which the renderer draws as scene geometry.
enum class MeshKind : uint8_t { proxy, textured, scene };

struct GpuMesh {
  GLuint vertex_buffer = 0, index_buffer = 0, vao = 0;
  GLuint uv_buffer = 0;  // scene meshes with texture coordinates
  uint32_t index_count = 0;
  MeshKind kind = MeshKind::proxy;
  bool live = false;
  uint64_t bytes = 0;  // of its buffers
  // Scene meshes replaced while walking (replace_scene_mesh): their buffers' sizes, bytes,
  // and whether new contents may be written into them.
  uint64_t vertex_capacity = 0, index_capacity = 0, uv_capacity = 0;
  bool rewritable = false;
  std::vector<uint32_t> indices;  // CPU copy (proxy and textured meshes): many small ranges are
                                  // gathered into one draw
};

struct GpuTexture {
  GLuint texture = 0;
  int width = 0, height = 0;
  bool mipmaps = false;
  bool live = false;
};

class GpuResources {
 public:
  GpuResources() = default;
  GpuResources(const GpuResources&) = delete;
  GpuResources& operator=(const GpuResources&) = delete;
  ~GpuResources();

  // Vertices of ProxyVertex (textured = false) or TexturedVertex (true).
  Result<MeshHandle> add_mesh(const void* vertices, size_t vertex_count, bool textured,
                              std::span<const uint32_t> indices);
  // Buffers and a VAO reading the vertices (binding 0) and texture coordinates (binding 3);
  // the renderer binds the scene's materials to it.
  Result<MeshHandle> add_scene_mesh(std::span<const Vertex> vertices,
                                    std::span<const glm::vec2> uvs,
                                    std::span<const uint32_t> indices);
  // New contents for a live scene mesh, under the same handle (streamed geometry): into its
  // buffers where they fit (those it had from an earlier replacement), else new ones.
  Result<void> replace_scene_mesh(MeshHandle handle, std::span<const Vertex> vertices,
                                  std::span<const glm::vec2> uvs,
                                  std::span<const uint32_t> indices);
  // New contents for a live textured mesh, under the same handle (streamed box pages).
  Result<void> replace_textured_mesh(MeshHandle handle, std::span<const TexturedVertex> vertices,
                                     std::span<const uint32_t> indices);
  TextureHandle add_texture();
  void free(MeshHandle mesh);
  void free(TextureHandle texture);
  // Assert that the handle is live.
  const GpuMesh& mesh(MeshHandle handle) const;
  const GpuTexture& texture(TextureHandle handle) const;
  // (Re)allocates the texture when the size or mip mode changes, then writes the pixels.
  void upload(const TextureUpload& upload);
  uint64_t bytes() const;

 private:
  std::vector<GpuMesh> meshes_;
  std::vector<GpuTexture> textures_;
  std::vector<uint32_t> free_meshes_, free_textures_;  // reusable slots
  MeshHandle store(GpuMesh mesh);
};

}  // namespace farfield::gpu
