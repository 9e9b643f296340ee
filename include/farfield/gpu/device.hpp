// Render resources by handle (DESIGN.md): techniques create their meshes and textures through
// a Device when they load, name them by handle in their DrawLists, and free them when they
// go, so that several techniques' resources live side by side in one renderer. The Renderer
// is the Device of a GL context; MemoryDevice hands out handles without a GPU, so that a
// technique can be loaded and its selection checked on the CPU alone.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "farfield/core/result.hpp"
#include "farfield/gpu/draw_list.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield::gpu {

class Device {
 public:
  virtual ~Device() = default;
  // Immutable meshes; fail (with the byte count) when the GPU cannot hold them.
  virtual Result<MeshHandle> create_mesh(std::span<const ProxyVertex> vertices,
                                         std::span<const uint32_t> indices) = 0;
  virtual Result<MeshHandle> create_textured_mesh(std::span<const TexturedVertex> vertices,
                                                  std::span<const uint32_t> indices) = 0;
  // Geometry in the scene's vertex format (simplified objects, merged cluster meshes), drawn
  // by DrawRanges that name it, lit and textured as the scene is with the scene's materials;
  // `uvs` one per vertex, or empty where no range draws a textured material.
  virtual Result<MeshHandle> create_scene_mesh(std::span<const Vertex> vertices,
                                               std::span<const glm::vec2> uvs,
                                               std::span<const uint32_t> indices) = 0;
  // A texture, empty until a TextureUpload gives it pixels (and its size).
  virtual TextureHandle create_texture() = 0;
  virtual void free(MeshHandle mesh) = 0;
  virtual void free(TextureHandle texture) = 0;
  // Bytes the live meshes and textures hold (textures as their last upload sized them).
  virtual uint64_t resource_bytes() const = 0;
};

// A Device without a GPU. It keeps a copy of each mesh (mesh() below) for tests.
class MemoryDevice final : public Device {
 public:
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

  // The proxy mesh of a live handle (textured and scene meshes: their positions and colours).
  const ProxyMesh& mesh(MeshHandle handle) const;
  size_t live_meshes() const;
  size_t live_textures() const;

 private:
  struct Entry {
    ProxyMesh mesh;
    bool live = false;
  };
  std::vector<Entry> meshes_;
  std::vector<bool> textures_;
};

// The resources one owner (a technique) created, freed together when it is destroyed. The
// device must outlive it.
class OwnedResources {
 public:
  OwnedResources() = default;
  OwnedResources(const OwnedResources&) = delete;
  OwnedResources& operator=(const OwnedResources&) = delete;
  ~OwnedResources() { release(); }

  // Frees what was made, then makes new resources on `device`.
  void bind(Device& device);
  Result<MeshHandle> mesh(std::span<const ProxyVertex> vertices, std::span<const uint32_t> indices);
  Result<MeshHandle> textured_mesh(std::span<const TexturedVertex> vertices,
                                   std::span<const uint32_t> indices);
  Result<MeshHandle> scene_mesh(std::span<const Vertex> vertices, std::span<const glm::vec2> uvs,
                                std::span<const uint32_t> indices);
  TextureHandle texture();
  void release();

 private:
  Device* device_ = nullptr;
  std::vector<MeshHandle> meshes_;
  std::vector<TextureHandle> textures_;
};

}  // namespace farfield::gpu
