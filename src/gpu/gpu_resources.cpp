#include "gpu_resources.hpp"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <string>

#include "farfield/core/assert.hpp"
#include "shaders.hpp"

namespace farfield::gpu {

Result<void> make_buffer(GLuint& buffer, const char* what, size_t bytes, const void* data,
                         GLbitfield flags) {
  glCreateBuffers(1, &buffer);
  while (glGetError() != GL_NO_ERROR) {
  }
  // Zero-sized storage is invalid in GL; an empty scene gets a placeholder.
  glNamedBufferStorage(buffer, GLsizeiptr(std::max<size_t>(bytes, 4)), bytes ? data : nullptr,
                       flags);
  if (const GLenum error = glGetError(); error != GL_NO_ERROR)
    return make_error("cannot allocate ", std::to_string(bytes), " bytes of GPU memory for the ",
                      what, error == GL_OUT_OF_MEMORY ? " (out of memory)" : "");
  return {};
}

namespace {

void delete_mesh(GpuMesh& m) {
  const GLuint buffers[] = {m.vertex_buffer, m.index_buffer, m.uv_buffer};
  glDeleteBuffers(3, buffers);
  glDeleteVertexArrays(1, &m.vao);
  m = GpuMesh{};
}

}  // namespace

void set_attribute(GLuint vao, GLuint index, GLint size, GLenum type, GLboolean normalized,
                   size_t offset, GLuint binding) {
  glEnableVertexArrayAttrib(vao, index);
  glVertexArrayAttribFormat(vao, index, size, type, normalized, GLuint(offset));
  glVertexArrayAttribBinding(vao, index, binding);
}

GpuResources::~GpuResources() {
  for (GpuMesh& m : meshes_) delete_mesh(m);
  for (GpuTexture& t : textures_) glDeleteTextures(1, &t.texture);
}

namespace {

// Buffers and a VAO for vertices of ProxyVertex (textured = false) or TexturedVertex (true).
Result<GpuMesh> make_mesh(const void* vertices, size_t vertex_count, bool textured,
                          std::span<const uint32_t> indices) {
  const size_t stride = textured ? sizeof(TexturedVertex) : sizeof(ProxyVertex);
  FF_ASSERT(indices.size() % 3 == 0 && indices.size() <= UINT32_MAX, "%zu mesh indices",
            indices.size());
  for (uint32_t i : indices)
    FF_ASSERT(i < vertex_count, "mesh index %u beyond its %zu vertices", i, vertex_count);
  GpuMesh m;
  m.kind = textured ? MeshKind::textured : MeshKind::proxy;
  if (auto made = make_buffer(m.vertex_buffer, "mesh vertices", vertex_count * stride, vertices, 0);
      !made) {
    delete_mesh(m);
    return made.error();
  }
  if (auto made = make_buffer(m.index_buffer, "mesh indices", indices.size() * sizeof(uint32_t),
                              indices.data(), 0);
      !made) {
    delete_mesh(m);
    return made.error();
  }
  glCreateVertexArrays(1, &m.vao);
  glVertexArrayVertexBuffer(m.vao, 0, m.vertex_buffer, 0, GLsizei(stride));
  glVertexArrayElementBuffer(m.vao, m.index_buffer);
  if (textured) {
    set_attribute(m.vao, kPositionAttrib, 3, GL_FLOAT, GL_FALSE,
                  offsetof(TexturedVertex, position));
    set_attribute(m.vao, kTexcoordAttrib, 2, GL_FLOAT, GL_FALSE, offsetof(TexturedVertex, uv));
    set_attribute(m.vao, kColorAttrib, 4, GL_UNSIGNED_BYTE, GL_TRUE,
                  offsetof(TexturedVertex, color));
  } else {
    set_attribute(m.vao, kPositionAttrib, 3, GL_FLOAT, GL_FALSE, offsetof(ProxyVertex, position));
    set_attribute(m.vao, kColorAttrib, 4, GL_UNSIGNED_BYTE, GL_TRUE, offsetof(ProxyVertex, color));
  }
  m.index_count = uint32_t(indices.size());
  m.indices.assign(indices.begin(), indices.end());
  m.bytes = vertex_count * stride + indices.size() * sizeof(uint32_t);
  return m;
}

}  // namespace

Result<MeshHandle> GpuResources::add_mesh(const void* vertices, size_t vertex_count, bool textured,
                                          std::span<const uint32_t> indices) {
  auto m = make_mesh(vertices, vertex_count, textured, indices);
  if (!m) return m.error();
  return store(std::move(*m));
}

Result<void> GpuResources::replace_textured_mesh(MeshHandle handle,
                                                 std::span<const TexturedVertex> vertices,
                                                 std::span<const uint32_t> indices) {
  FF_ASSERT(mesh(handle).kind == MeshKind::textured, "mesh %u is not a textured mesh", handle.id);
  auto m = make_mesh(vertices.data(), vertices.size(), true, indices);
  if (!m) return m.error();
  GpuMesh& slot = meshes_[handle.id - 1];
  delete_mesh(slot);
  slot = std::move(*m);
  slot.live = true;
  return {};
}

namespace {

// Buffers and a VAO reading the vertices (binding 0) and texture coordinates (binding 3).
void check_scene_mesh(std::span<const Vertex> vertices, std::span<const glm::vec2> uvs,
                      std::span<const uint32_t> indices) {
  FF_ASSERT(indices.size() % 3 == 0 && indices.size() <= UINT32_MAX, "%zu mesh indices",
            indices.size());
  FF_ASSERT(uvs.empty() || uvs.size() == vertices.size(),
            "%zu texture coordinates for %zu vertices", uvs.size(), vertices.size());
  for (uint32_t i : indices)
    FF_ASSERT(i < vertices.size(), "mesh index %u beyond its %zu vertices", i, vertices.size());
}

// `flags` for its buffers' storage (GL_DYNAMIC_STORAGE_BIT: rewritable).
Result<GpuMesh> make_scene_mesh(std::span<const Vertex> vertices, std::span<const glm::vec2> uvs,
                                std::span<const uint32_t> indices, GLbitfield flags) {
  check_scene_mesh(vertices, uvs, indices);
  GpuMesh m;
  m.kind = MeshKind::scene;
  auto fail = [&](Result<void> made) {
    delete_mesh(m);
    return made.error();
  };
  if (auto made = make_buffer(m.vertex_buffer, "scene mesh vertices",
                              vertices.size() * sizeof(Vertex), vertices.data(), flags);
      !made)
    return fail(made);
  if (auto made = make_buffer(m.index_buffer, "scene mesh indices",
                              indices.size() * sizeof(uint32_t), indices.data(), flags);
      !made)
    return fail(made);
  glCreateVertexArrays(1, &m.vao);
  glVertexArrayVertexBuffer(m.vao, 0, m.vertex_buffer, 0, sizeof(Vertex));
  glVertexArrayElementBuffer(m.vao, m.index_buffer);
  if (!uvs.empty()) {
    if (auto made = make_buffer(m.uv_buffer, "scene mesh texture coordinates",
                                uvs.size() * sizeof(glm::vec2), uvs.data(), flags);
        !made)
      return fail(made);
    glVertexArrayVertexBuffer(m.vao, 3, m.uv_buffer, 0, sizeof(glm::vec2));
    set_attribute(m.vao, kTexcoordAttrib, 2, GL_FLOAT, GL_FALSE, 0, 3);
  }
  m.index_count = uint32_t(indices.size());
  m.vertex_capacity = vertices.size() * sizeof(Vertex);
  m.index_capacity = indices.size() * sizeof(uint32_t);
  m.uv_capacity = uvs.size() * sizeof(glm::vec2);
  m.bytes = m.vertex_capacity + m.index_capacity + m.uv_capacity;
  m.rewritable = (flags & GL_DYNAMIC_STORAGE_BIT) != 0;
  return m;
}

}  // namespace

Result<MeshHandle> GpuResources::add_scene_mesh(std::span<const Vertex> vertices,
                                                std::span<const glm::vec2> uvs,
                                                std::span<const uint32_t> indices) {
  auto m = make_scene_mesh(vertices, uvs, indices, 0);
  if (!m) return m.error();
  return store(std::move(*m));
}

Result<void> GpuResources::replace_scene_mesh(MeshHandle handle, std::span<const Vertex> vertices,
                                              std::span<const glm::vec2> uvs,
                                              std::span<const uint32_t> indices) {
  FF_ASSERT(mesh(handle).kind == MeshKind::scene, "mesh %u is not a scene mesh", handle.id);
  GpuMesh& slot = meshes_[handle.id - 1];
  const uint64_t vertex_bytes = vertices.size() * sizeof(Vertex);
  const uint64_t index_bytes = indices.size() * sizeof(uint32_t);
  const uint64_t uv_bytes = uvs.size() * sizeof(glm::vec2);
  // Written into the buffers there where they fit: a new buffer costs a page fault a page
  // (on this 2-core VM 3.6 ms a MB: a frame's 4 MB of streamed pages took 15 ms).
  if (slot.rewritable && vertex_bytes <= slot.vertex_capacity &&
      index_bytes <= slot.index_capacity && uv_bytes <= slot.uv_capacity &&
      (uvs.empty() == (slot.uv_buffer == 0))) {
    check_scene_mesh(vertices, uvs, indices);
    if (vertex_bytes)
      glNamedBufferSubData(slot.vertex_buffer, 0, GLsizeiptr(vertex_bytes), vertices.data());
    if (index_bytes)
      glNamedBufferSubData(slot.index_buffer, 0, GLsizeiptr(index_bytes), indices.data());
    if (uv_bytes) glNamedBufferSubData(slot.uv_buffer, 0, GLsizeiptr(uv_bytes), uvs.data());
    slot.index_count = uint32_t(indices.size());
    return {};
  }
  auto m = make_scene_mesh(vertices, uvs, indices, GL_DYNAMIC_STORAGE_BIT);
  if (!m) return m.error();
  delete_mesh(slot);
  slot = std::move(*m);
  slot.live = true;
  return {};
}

MeshHandle GpuResources::store(GpuMesh m) {
  m.live = true;
  uint32_t slot;
  if (!free_meshes_.empty()) {
    slot = free_meshes_.back();
    free_meshes_.pop_back();
    meshes_[slot] = std::move(m);
  } else {
    slot = uint32_t(meshes_.size());
    meshes_.push_back(std::move(m));
  }
  return MeshHandle{slot + 1};
}

TextureHandle GpuResources::add_texture() {
  GpuTexture t;
  t.live = true;
  if (!free_textures_.empty()) {
    const uint32_t slot = free_textures_.back();
    free_textures_.pop_back();
    textures_[slot] = t;
    return TextureHandle{slot + 1};
  }
  textures_.push_back(t);
  return TextureHandle{uint32_t(textures_.size())};
}

void GpuResources::free(MeshHandle handle) {
  if (!handle) return;
  mesh(handle);  // asserts that it is live
  delete_mesh(meshes_[handle.id - 1]);
  free_meshes_.push_back(handle.id - 1);
}

void GpuResources::free(TextureHandle handle) {
  if (!handle) return;
  texture(handle);
  GpuTexture& t = textures_[handle.id - 1];
  glDeleteTextures(1, &t.texture);
  t = GpuTexture{};
  free_textures_.push_back(handle.id - 1);
}

const GpuMesh& GpuResources::mesh(MeshHandle handle) const {
  FF_ASSERT(handle && handle.id <= meshes_.size() && meshes_[handle.id - 1].live,
            "mesh handle %u names no live mesh", handle.id);
  return meshes_[handle.id - 1];
}

const GpuTexture& GpuResources::texture(TextureHandle handle) const {
  FF_ASSERT(handle && handle.id <= textures_.size() && textures_[handle.id - 1].live,
            "texture handle %u names no live texture", handle.id);
  return textures_[handle.id - 1];
}

void GpuResources::upload(const TextureUpload& u) {
  FF_ASSERT(
      u.width > 0 && u.height > 0 && (u.channels == 3 || u.channels == 4) && u.pixels != nullptr,
      "bad texture upload: texture %u, %dx%d, %d channels", u.texture.id, u.width, u.height,
      u.channels);
  texture(u.texture);
  GpuTexture& t = textures_[u.texture.id - 1];
  if (t.width != u.width || t.height != u.height || t.mipmaps != u.mipmaps) {
    glDeleteTextures(1, &t.texture);
    glCreateTextures(GL_TEXTURE_2D, 1, &t.texture);
    const int levels = u.mipmaps ? int(std::bit_width(unsigned(std::max(u.width, u.height)))) : 1;
    glTextureStorage2D(t.texture, levels, GL_RGBA8, u.width, u.height);
    glTextureParameteri(t.texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t.texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    t.width = u.width;
    t.height = u.height;
    t.mipmaps = u.mipmaps;
  }
  glTextureParameteri(t.texture, GL_TEXTURE_MIN_FILTER,
                      u.mipmaps ? GL_LINEAR_MIPMAP_LINEAR
                      : u.nearest ? GL_NEAREST
                                  : GL_LINEAR);
  glTextureParameteri(t.texture, GL_TEXTURE_MAG_FILTER, u.nearest ? GL_NEAREST : GL_LINEAR);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
  // Row 0 of the pixels (the image's top) lands at t = 0; quads and meshes map it so.
  glTextureSubImage2D(t.texture, 0, 0, 0, u.width, u.height, u.channels == 4 ? GL_RGBA : GL_RGB,
                      GL_UNSIGNED_BYTE, u.pixels);
  if (u.mipmaps) glGenerateTextureMipmap(t.texture);
}

uint64_t GpuResources::bytes() const {
  uint64_t total = 0;
  for (const GpuMesh& m : meshes_) total += m.bytes;
  for (const GpuTexture& t : textures_)
    if (t.live) total += uint64_t(t.width) * uint64_t(t.height) * 4 * (t.mipmaps ? 4 : 3) / 3;
  return total;
}

}  // namespace farfield::gpu
