#include "farfield/gpu/device.hpp"

#include <algorithm>

#include "farfield/core/assert.hpp"

namespace farfield::gpu {

Result<MeshHandle> MemoryDevice::create_mesh(std::span<const ProxyVertex> vertices,
                                             std::span<const uint32_t> indices) {
  meshes_.push_back(
      {ProxyMesh{{vertices.begin(), vertices.end()}, {indices.begin(), indices.end()}}, true});
  return MeshHandle{uint32_t(meshes_.size())};
}

Result<MeshHandle> MemoryDevice::create_textured_mesh(std::span<const TexturedVertex> vertices,
                                                      std::span<const uint32_t> indices) {
  ProxyMesh copy;
  copy.vertices.reserve(vertices.size());
  for (const TexturedVertex& v : vertices) copy.vertices.push_back({v.position, v.color});
  copy.indices.assign(indices.begin(), indices.end());
  meshes_.push_back({std::move(copy), true});
  return MeshHandle{uint32_t(meshes_.size())};
}

Result<MeshHandle> MemoryDevice::create_scene_mesh(std::span<const Vertex> vertices,
                                                   std::span<const glm::vec2> uvs,
                                                   std::span<const uint32_t> indices) {
  FF_ASSERT(uvs.empty() || uvs.size() == vertices.size(),
            "%zu texture coordinates for %zu vertices", uvs.size(), vertices.size());
  ProxyMesh copy;
  copy.vertices.reserve(vertices.size());
  for (const Vertex& v : vertices) copy.vertices.push_back({v.position, v.color});
  copy.indices.assign(indices.begin(), indices.end());
  meshes_.push_back({std::move(copy), true});
  return MeshHandle{uint32_t(meshes_.size())};
}

TextureHandle MemoryDevice::create_texture() {
  textures_.push_back(true);
  return TextureHandle{uint32_t(textures_.size())};
}

void MemoryDevice::free(MeshHandle mesh) {
  if (!mesh) return;
  FF_ASSERT(mesh.id <= meshes_.size() && meshes_[mesh.id - 1].live, "mesh %u is not live", mesh.id);
  meshes_[mesh.id - 1] = {};
}

void MemoryDevice::free(TextureHandle texture) {
  if (!texture) return;
  FF_ASSERT(texture.id <= textures_.size() && textures_[texture.id - 1], "texture %u is not live",
            texture.id);
  textures_[texture.id - 1] = false;
}

uint64_t MemoryDevice::resource_bytes() const {
  uint64_t bytes = 0;
  for (const Entry& e : meshes_)
    bytes +=
        e.mesh.vertices.size() * sizeof(ProxyVertex) + e.mesh.indices.size() * sizeof(uint32_t);
  return bytes;
}

const ProxyMesh& MemoryDevice::mesh(MeshHandle handle) const {
  FF_ASSERT(handle && handle.id <= meshes_.size() && meshes_[handle.id - 1].live,
            "mesh %u is not live", handle.id);
  return meshes_[handle.id - 1].mesh;
}

size_t MemoryDevice::live_meshes() const {
  return size_t(
      std::count_if(meshes_.begin(), meshes_.end(), [](const Entry& e) { return e.live; }));
}

size_t MemoryDevice::live_textures() const {
  return size_t(std::count(textures_.begin(), textures_.end(), true));
}

void OwnedResources::bind(Device& device) {
  release();
  device_ = &device;
}

Result<MeshHandle> OwnedResources::mesh(std::span<const ProxyVertex> vertices,
                                        std::span<const uint32_t> indices) {
  FF_ASSERT(device_ != nullptr, "OwnedResources::mesh before bind()");
  auto made = device_->create_mesh(vertices, indices);
  if (made) meshes_.push_back(*made);
  return made;
}

Result<MeshHandle> OwnedResources::textured_mesh(std::span<const TexturedVertex> vertices,
                                                 std::span<const uint32_t> indices) {
  FF_ASSERT(device_ != nullptr, "OwnedResources::textured_mesh before bind()");
  auto made = device_->create_textured_mesh(vertices, indices);
  if (made) meshes_.push_back(*made);
  return made;
}

Result<MeshHandle> OwnedResources::scene_mesh(std::span<const Vertex> vertices,
                                              std::span<const glm::vec2> uvs,
                                              std::span<const uint32_t> indices) {
  FF_ASSERT(device_ != nullptr, "OwnedResources::scene_mesh before bind()");
  auto made = device_->create_scene_mesh(vertices, uvs, indices);
  if (made) meshes_.push_back(*made);
  return made;
}

TextureHandle OwnedResources::texture() {
  FF_ASSERT(device_ != nullptr, "OwnedResources::texture before bind()");
  textures_.push_back(device_->create_texture());
  return textures_.back();
}

void OwnedResources::release() {
  if (device_ == nullptr) return;
  for (MeshHandle m : meshes_) device_->free(m);
  for (TextureHandle t : textures_) device_->free(t);
  meshes_.clear();
  textures_.clear();
}

}  // namespace farfield::gpu
