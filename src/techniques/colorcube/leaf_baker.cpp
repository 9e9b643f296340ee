#include "farfield/techniques/colorcube/leaf_baker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "farfield/core/assert.hpp"
#include "farfield/gpu/lighting.hpp"

namespace farfield {

namespace {

// One direction's render: c slabs of R x R pixels, nearest fragment per slab and pixel.
struct SlabImages {
  int resolution = 0, slabs = 0;
  std::vector<float> depth;      // slab-major, then row-major
  std::vector<glm::vec3> color;  // valid where depth < infinity

  SlabImages(int r, int c)
      : resolution(r),
        slabs(c),
        depth(size_t(r) * r * c, std::numeric_limits<float>::infinity()),
        color(size_t(r) * r * c) {}
  size_t at(int slab, int x, int y) const {
    return (size_t(slab) * resolution + y) * resolution + x;
  }
};

float edge(const glm::vec2& a, const glm::vec2& b, const glm::vec2& p) {
  return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

// Renders the triangles as seen by a viewer on the `face` side of `cell`, looking inwards.
void render_direction(const Scene& scene, std::span<const uint32_t> materials,
                      std::span<const uint32_t> triangles, const Bounds3& cell, int face,
                      const LeafTextures& textures, SlabImages& out) {
  const int axis = face_axis(face), sign = face_sign(face);
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const float size = cell.max[axis] - cell.min[axis];
  const float pixel = size / float(out.resolution);
  const float slab_depth = size / float(out.slabs);
  glm::vec3 toward_viewer(0.0f);
  toward_viewer[axis] = float(sign);

  for (uint32_t t : triangles) {
    const uint32_t* idx = scene.indices.data() + size_t(t) * 3;
    const Vertex* vert[3] = {&scene.vertices[idx[0]], &scene.vertices[idx[1]],
                             &scene.vertices[idx[2]]};
    const glm::vec3 p0 = vert[0]->position, p1 = vert[1]->position, p2 = vert[2]->position;
    const glm::vec3 geometric = glm::cross(p1 - p0, p2 - p0);
    const float facing = glm::dot(geometric, toward_viewer);
    if (facing == 0.0f) continue;  // seen edge-on: covers nothing
    const Material& material = scene.materials[materials[t]];
    if (facing < 0.0f && !material.transparent() && !material.double_sided)
      continue;                                       // culled like the renderer does
    const float side = facing < 0.0f ? -1.0f : 1.0f;  // back faces lit from the viewer's side
    const glm::vec3 tint(material.base_color);
    glm::vec2 s[3];
    float d[3];
    for (int i = 0; i < 3; ++i) {
      const glm::vec3& p = vert[i]->position;
      s[i] = {(p[u] - cell.min[u]) / pixel, (p[v] - cell.min[v]) / pixel};
      d[i] = sign > 0 ? cell.max[axis] - p[axis] : p[axis] - cell.min[axis];
    }
    const float area = edge(s[0], s[1], s[2]);
    if (area == 0.0f) continue;
    const int x0 = std::max(0, int(std::floor(std::min({s[0].x, s[1].x, s[2].x}))));
    const int x1 = std::min(out.resolution - 1, int(std::ceil(std::max({s[0].x, s[1].x, s[2].x}))));
    const int y0 = std::max(0, int(std::floor(std::min({s[0].y, s[1].y, s[2].y}))));
    const int y1 = std::min(out.resolution - 1, int(std::ceil(std::max({s[0].y, s[1].y, s[2].y}))));
    glm::vec3 normals[3], colors[3];
    for (int i = 0; i < 3; ++i) {
      normals[i] = side * unpack_normal(vert[i]->normal);
      colors[i] = glm::vec3(unpack_color(vert[i]->color)) * tint;
    }
    // Texture coordinates are affine in the orthographic image: their gradient per pixel,
    // from the barycentric gradients, gives the footprint in texels (the mip level).
    const TextureSampler* sampler = nullptr;
    glm::vec2 uv[3]{}, duv_dx{}, duv_dy{};
    float footprint = 0.0f;
    if (material.textured() && !textures.vertex_uv.empty() &&
        textures.vertex_uv[idx[0]] != kNoTexture) {
      sampler = &textures.samplers[material.texture];
      for (int i = 0; i < 3; ++i) uv[i] = scene.uvs[textures.vertex_uv[idx[i]]];
      for (int i = 0; i < 3; ++i) {
        const glm::vec2 &a = s[(i + 1) % 3], &b = s[(i + 2) % 3];
        duv_dx += uv[i] * (-(b.y - a.y) / area);
        duv_dy += uv[i] * ((b.x - a.x) / area);
      }
      const glm::vec2 texels(float(sampler->width()), float(sampler->height()));
      footprint = std::max(glm::length(duv_dx * texels), glm::length(duv_dy * texels));
    }
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const glm::vec2 c(float(x) + 0.5f, float(y) + 0.5f);
        float w0 = edge(s[1], s[2], c), w1 = edge(s[2], s[0], c), w2 = edge(s[0], s[1], c);
        if (area < 0.0f) {
          w0 = -w0;
          w1 = -w1;
          w2 = -w2;
        }
        if (w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) continue;
        const float sum = w0 + w1 + w2;
        const float b0 = w0 / sum, b1 = w1 / sum, b2 = w2 / sum;
        const float depth = b0 * d[0] + b1 * d[1] + b2 * d[2];
        if (depth < 0.0f || depth >= size) continue;  // outside the cell
        const int slab = std::min(out.slabs - 1, int(depth / slab_depth));
        const size_t at = out.at(slab, x, y);
        if (depth >= out.depth[at]) continue;
        glm::vec3 color = b0 * colors[0] + b1 * colors[1] + b2 * colors[2];
        if (sampler) {
          const glm::vec4 texel = sampler->sample(b0 * uv[0] + b1 * uv[1] + b2 * uv[2], footprint,
                                                  material.wrap_u, material.wrap_v);
          if (material.alpha_mode == AlphaMode::mask &&
              material.base_color.a * texel.a < material.alpha_cutoff)
            continue;  // cut out, as the shader discards it
          color *= glm::vec3(texel);
        }
        glm::vec3 n = b0 * normals[0] + b1 * normals[1] + b2 * normals[2];
        const float length = glm::length(n);
        n = length > 0.0f ? n / length : toward_viewer;
        out.depth[at] = depth;
        out.color[at] = gpu::shade(n, color);
      }
    }
  }
}

}  // namespace

std::vector<uint32_t> triangle_materials(const Scene& scene) {
  std::vector<uint32_t> materials(scene.triangle_count(), 0);
  for (const Object& o : scene.objects)
    std::fill_n(materials.begin() + o.first_index / 3, o.triangle_count(), o.material);
  return materials;
}

Result<LeafTextures> leaf_textures(const Scene& scene) {
  LeafTextures out;
  if (scene.textures.empty()) return out;
  auto samplers = scene_texture_samplers(scene);
  if (!samplers) return samplers.error();
  out.samplers = std::move(*samplers);
  out.vertex_uv.assign(scene.vertices.size(), kNoTexture);
  for (const Object& o : scene.objects)
    if (scene.textured(o))
      for (uint32_t i = 0; i < o.vertex_count; ++i)
        out.vertex_uv[o.first_vertex + i] = o.first_uv + i;
  return out;
}

std::vector<ColorCube> bake_leaf(const Scene& scene, std::span<const uint32_t> materials,
                                 std::span<const uint32_t> triangles, const Bounds3& cell,
                                 const LeafBakeOptions& o, const LeafTextures& textures) {
  FF_ASSERT(o.oversampling >= 1 && o.oversampling <= 5, "oversampling %d", o.oversampling);
  FF_ASSERT(o.cluster >= 1 && o.cluster <= 64, "cluster %d", o.cluster);
  const int c = o.cluster, k = o.oversampling, r = c * k;
  std::vector<ColorCube> cubes(size_t(c) * c * c);
  for (int face = 0; face < 6; ++face) {
    SlabImages images(r, c);
    render_direction(scene, materials, triangles, cell, face, textures, images);
    const int axis = face_axis(face), u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int slab = 0; slab < c; ++slab) {
      for (int cy = 0; cy < c; ++cy) {
        for (int cx = 0; cx < c; ++cx) {
          glm::vec3 sum(0.0f);
          int covered = 0;
          for (int y = cy * k; y < (cy + 1) * k; ++y) {
            for (int x = cx * k; x < (cx + 1) * k; ++x) {
              const size_t at = images.at(slab, x, y);
              if (images.depth[at] == std::numeric_limits<float>::infinity()) continue;
              sum += images.color[at];
              ++covered;
            }
          }
          int coord[3];
          coord[axis] = face_sign(face) > 0 ? c - 1 - slab : slab;  // slab 0 is nearest the viewer
          coord[u] = cx;
          coord[v] = cy;
          FaceColor& f =
              cubes[size_t(coord[0]) + size_t(c) * (coord[1] + size_t(c) * coord[2])].faces[face];
          if (covered == 0) continue;
          f.rgb = sum / float(covered);
          f.coverage = o.coverage == CoverageMode::binary ? 1.0f : float(covered) / float(k * k);
        }
      }
    }
  }
  return cubes;
}

}  // namespace farfield
