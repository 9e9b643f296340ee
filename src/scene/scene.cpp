#include "farfield/scene/scene.hpp"

#include <xxhash.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>

#include "farfield/core/assert.hpp"
#include "farfield/scene/instances.hpp"

namespace farfield {

std::string_view object_kind_name(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::mesh:
      return "mesh";
    case ObjectKind::building:
      return "building";
    case ObjectKind::tree:
      return "tree";
    case ObjectKind::fountain:
      return "fountain";
    case ObjectKind::park:
      return "park";
    case ObjectKind::street:
      return "street";
    case ObjectKind::curb:
      return "curb";
    case ObjectKind::ground:
      return "ground";
    case ObjectKind::terrain:
      return "terrain";
    case ObjectKind::count_:
      break;
  }
  return "unknown";
}

uint64_t Scene::byte_size() const {
  uint64_t texture_names = 0;
  for (const Texture& t : textures) texture_names += t.name.size() + sizeof(Texture);
  return objects.size() * sizeof(Object) + materials.size() * sizeof(Material) +
         vertices.size() * sizeof(Vertex) + indices.size() * sizeof(uint32_t) + names.size() +
         uvs.size() * sizeof(glm::vec2) + texture_names + texture_bytes() +
         cells.size() * sizeof(Cell) + cell_objects.size() * sizeof(uint32_t) +
         portals.size() * sizeof(Portal) + portal_points.size() * sizeof(glm::vec3) +
         instances.size() * sizeof(Instance);
}

uint64_t Scene::texture_bytes() const {
  uint64_t bytes = 0;
  for (const Texture& t : textures) bytes += t.encoded.size();
  return bytes;
}

std::optional<uint32_t> object_of_triangle(const Scene& scene, uint64_t triangle) {
  // Objects need not lie in index order: a scan (a click's worth of work).
  for (uint32_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    if (3 * triangle >= o.first_index && 3 * triangle < uint64_t(o.first_index) + o.index_count)
      return i;
  }
  return std::nullopt;
}

float median_triangle_edge(std::span<const Vertex> vertices, std::span<const uint32_t> indices,
                           uint64_t samples) {
  const uint64_t n = indices.size() / 3;
  if (n == 0 || samples == 0) return 0.0f;
  const uint64_t count = std::min(n, samples);
  std::vector<float> edges(count);
  for (uint64_t i = 0; i < count; ++i) {
    const uint32_t* t = indices.data() + (i * n / count) * 3;
    const glm::vec3 a = vertices[t[0]].position, b = vertices[t[1]].position,
                    c = vertices[t[2]].position;
    edges[i] = std::max({glm::distance(a, b), glm::distance(b, c), glm::distance(c, a)});
  }
  std::nth_element(edges.begin(), edges.begin() + count / 2, edges.end());
  return edges[count / 2];
}

float median_triangle_edge(const Scene& scene, uint64_t samples) {
  return median_triangle_edge(scene.vertices, scene.indices, samples);
}

namespace {

uint32_t pack_snorm10(float v) {
  const float c = std::clamp(v, -1.0f, 1.0f);
  const int32_t i = static_cast<int32_t>(std::lround(c * 511.0f));
  return static_cast<uint32_t>(i) & 0x3ffu;
}

float unpack_snorm10(uint32_t bits) {
  int32_t i = static_cast<int32_t>(bits & 0x3ffu);
  if (i & 0x200) i -= 0x400;  // sign-extend
  return std::max(static_cast<float>(i) / 511.0f, -1.0f);
}

uint32_t pack_unorm8(float v) {
  return static_cast<uint32_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

uint32_t pack_normal(const glm::vec3& n) {
  return pack_snorm10(n.x) | (pack_snorm10(n.y) << 10) | (pack_snorm10(n.z) << 20);
}

glm::vec3 unpack_normal(uint32_t packed) {
  return {unpack_snorm10(packed), unpack_snorm10(packed >> 10), unpack_snorm10(packed >> 20)};
}

uint32_t pack_color(const glm::vec4& c) {
  return pack_unorm8(c.r) | (pack_unorm8(c.g) << 8) | (pack_unorm8(c.b) << 16) |
         (pack_unorm8(c.a) << 24);
}

glm::vec4 unpack_color(uint32_t p) {
  return glm::vec4(p & 0xff, (p >> 8) & 0xff, (p >> 16) & 0xff, (p >> 24) & 0xff) / 255.0f;
}

uint32_t SceneBuilder::add_material(const Material& m) {
  auto& materials = scene_.materials;
  for (size_t i = 0; i < materials.size(); ++i) {
    if (materials[i] == m) return static_cast<uint32_t>(i);
  }
  materials.push_back(m);
  return static_cast<uint32_t>(materials.size() - 1);
}

uint32_t SceneBuilder::add_texture(Texture texture) {
  FF_ASSERT(scene_.textures.size() < kNoTexture - 1, "texture table full");
  scene_.textures.push_back(std::move(texture));
  return static_cast<uint32_t>(scene_.textures.size() - 1);
}

void SceneBuilder::begin_object(std::string_view name, ObjectKind kind, uint32_t material) {
  FF_ASSERT(!open_, "object already open while beginning '%.*s'", int(name.size()), name.data());
  FF_ASSERT(material < scene_.materials.size(), "material %u of %zu", material,
            scene_.materials.size());
  FF_ASSERT(scene_.names.size() + name.size() <= UINT32_MAX, "name table full");
  current_ = Object{};
  current_.name_offset = static_cast<uint32_t>(scene_.names.size());
  current_.name_size = static_cast<uint32_t>(name.size());
  scene_.names.append(name);
  current_.kind = kind;
  current_.material = material;
  current_.first_index = static_cast<uint32_t>(scene_.indices.size());
  current_.first_vertex = static_cast<uint32_t>(scene_.vertices.size());
  textured_ = scene_.materials[material].textured();
  if (textured_) {
    FF_ASSERT(scene_.uvs.size() < UINT32_MAX, "more than 2^32-1 texture coordinates");
    current_.first_uv = static_cast<uint32_t>(scene_.uvs.size());
  }
  open_ = true;
}

uint32_t SceneBuilder::add_vertex(const glm::vec3& position, const glm::vec3& normal,
                                  uint32_t color, glm::vec2 uv) {
  FF_ASSERT(open_, "no object open");
  FF_ASSERT(scene_.vertices.size() < UINT32_MAX, "more than 2^32-1 vertices");
  scene_.vertices.push_back(Vertex{position, pack_normal(normal), color});
  if (textured_) {
    FF_ASSERT(scene_.uvs.size() < UINT32_MAX, "more than 2^32-1 texture coordinates");
    scene_.uvs.push_back(uv);
  }
  current_.bounds.expand(position);
  return vertex_count() - 1;
}

uint32_t SceneBuilder::vertex_count() const {
  return static_cast<uint32_t>(scene_.vertices.size()) - current_.first_vertex;
}

void SceneBuilder::add_triangle(uint32_t a, uint32_t b, uint32_t c) {
  const uint32_t n = vertex_count();
  FF_ASSERT(a < n && b < n && c < n, "triangle (%u,%u,%u) of an object with %u vertices", a, b, c,
            n);
  const uint32_t base = current_.first_vertex;
  scene_.indices.insert(scene_.indices.end(), {base + a, base + b, base + c});
}

void SceneBuilder::end_object() {
  FF_ASSERT(open_, "no object open");
  open_ = false;
  current_.index_count = static_cast<uint32_t>(scene_.indices.size()) - current_.first_index;
  current_.vertex_count = vertex_count();
  if (current_.index_count == 0) {  // nothing to draw: roll back the name and vertices
    scene_.names.resize(current_.name_offset);
    scene_.vertices.resize(current_.first_vertex);
    if (textured_) scene_.uvs.resize(current_.first_uv);
    return;
  }
  scene_.bounds.expand(current_.bounds);
  scene_.objects.push_back(current_);
}

uint32_t SceneBuilder::add_instance(std::string_view name, ObjectKind kind, uint32_t prototype,
                                    const glm::mat3& linear, const glm::vec3& offset) {
  FF_ASSERT(!open_, "object open while adding instance '%.*s'", int(name.size()), name.data());
  FF_ASSERT(prototype < scene_.objects.size() && !instance_of(scene_, prototype),
            "prototype %u of %zu objects", prototype, scene_.objects.size());
  const Instance instance{uint32_t(scene_.objects.size()), prototype, linear, offset};
  const InstanceTransform move(instance);
  const Object p = scene_.objects[prototype];
  begin_object(name, kind, p.material);
  const uint32_t base = current_.first_vertex;
  for (uint32_t v = 0; v < p.vertex_count; ++v) {
    FF_ASSERT(scene_.vertices.size() < UINT32_MAX, "more than 2^32-1 vertices");
    const Vertex moved = move(scene_.vertices[p.first_vertex + v]);
    scene_.vertices.push_back(moved);
    current_.bounds.expand(moved.position);
    if (textured_) {
      const glm::vec2 uv = scene_.uvs[p.first_uv + v];
      scene_.uvs.push_back(uv);
    }
  }
  for (uint32_t k = 0; k < p.index_count; ++k)
    scene_.indices.push_back(scene_.indices[p.first_index + k] - p.first_vertex + base);
  end_object();
  scene_.instances.push_back(instance);
  return instance.object;
}

uint64_t scene_fingerprint(const Scene& s) {
  return scene_fingerprint(s, s.uvs.size(), [&](GeometryArray array, const ByteSink& feed) {
    switch (array) {
      case GeometryArray::vertices: return feed(std::as_bytes(std::span(s.vertices)));
      case GeometryArray::indices: return feed(std::as_bytes(std::span(s.indices)));
      case GeometryArray::uvs: return feed(std::as_bytes(std::span(s.uvs)));
    }
  });
}

uint64_t scene_fingerprint(const Scene& s, uint64_t uv_count,
                           const std::function<void(GeometryArray, const ByteSink&)>& geometry) {
  XXH3_state_t* state = XXH3_createState();
  XXH3_64bits_reset(state);
  const ByteSink feed = [&](std::span<const std::byte> bytes) {
    XXH3_64bits_update(state, bytes.data(), bytes.size());
  };
  XXH3_64bits_update(state, s.objects.data(), s.objects.size() * sizeof(Object));
  // Base colours alone, then the rest only where a scene has textures or another material
  // field than the colour: such a scene keeps the fingerprint it had before materials grew,
  // and so its bakes.
  bool extended = !s.textures.empty() || uv_count > 0;
  for (const Material& m : s.materials) {
    XXH3_64bits_update(state, &m.base_color, 16);
    extended = extended || !(m == Material{.base_color = m.base_color});
  }
  geometry(GeometryArray::vertices, feed);
  geometry(GeometryArray::indices, feed);
  XXH3_64bits_update(state, s.names.data(), s.names.size());
  if (extended) {
    XXH3_64bits_update(state, s.materials.data(), s.materials.size() * sizeof(Material));
    if (uv_count > 0) geometry(GeometryArray::uvs, feed);
    for (const Texture& t : s.textures) {
      XXH3_64bits_update(state, t.encoded.data(), t.encoded.size());
      const uint32_t header[3] = {t.width, t.height, uint32_t(t.codec)};
      XXH3_64bits_update(state, header, sizeof header);
    }
  }
  // Cells and portals only where a scene has them: scenes without keep their fingerprint.
  if (!s.cells.empty()) {
    XXH3_64bits_update(state, s.cells.data(), s.cells.size() * sizeof(Cell));
    XXH3_64bits_update(state, s.cell_objects.data(), s.cell_objects.size() * sizeof(uint32_t));
    XXH3_64bits_update(state, s.portals.data(), s.portals.size() * sizeof(Portal));
    XXH3_64bits_update(state, s.portal_points.data(), s.portal_points.size() * sizeof(glm::vec3));
  }
  // Instances likewise.
  if (!s.instances.empty())
    XXH3_64bits_update(state, s.instances.data(), s.instances.size() * sizeof(Instance));
  const uint64_t hash = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  return hash;
}

std::string validate_scene(const Scene& s) {
  if (std::string problem =
          validate_scene_index(s, s.vertices.size(), s.indices.size(), s.uvs.size());
      !problem.empty())
    return problem;
  if (std::string problem =
          validate_geometry(s, 0, uint32_t(s.objects.size()),
                            {.vertices = s.vertices, .indices = s.indices, .uvs = s.uvs});
      !problem.empty())
    return problem;
  return validate_instances(s, InstanceForm::held, true);
}

std::string validate_scene_index(const Scene& s, uint64_t vertex_count, uint64_t index_count,
                                 uint64_t uv_count) {
  auto fail = [](size_t object, const char* what) {
    return "object " + std::to_string(object) + ": " + what;
  };
  if (index_count % 3 != 0) return "index count is not a multiple of 3";
  for (size_t i = 0; i < s.objects.size(); ++i) {
    const Object& o = s.objects[i];
    if (uint64_t(o.name_offset) + o.name_size > s.names.size()) return fail(i, "name out of range");
    if (static_cast<uint8_t>(o.kind) >= static_cast<uint8_t>(ObjectKind::count_))
      return fail(i, "unknown kind");
    if (o.material >= s.materials.size()) return fail(i, "material out of range");
    if (s.materials[o.material].textured() && uint64_t(o.first_uv) + o.vertex_count > uv_count)
      return fail(i, "texture coordinates out of range");
    if (o.first_index % 3 != 0 || o.index_count % 3 != 0)
      return fail(i, "index range not made of whole triangles");
    if (uint64_t(o.first_index) + o.index_count > index_count)
      return fail(i, "index range out of range");
    if (uint64_t(o.first_vertex) + o.vertex_count > vertex_count)
      return fail(i, "vertex range out of range");
  }
  for (size_t i = 0; i < s.materials.size(); ++i) {
    const Material& m = s.materials[i];
    const std::string at = "material " + std::to_string(i) + ": ";
    if (m.textured() && m.texture >= s.textures.size()) return at + "texture out of range";
    if (uint8_t(m.alpha_mode) >= uint8_t(AlphaMode::count_)) return at + "unknown alpha mode";
    if (uint8_t(m.wrap_u) >= uint8_t(TextureWrap::count_) ||
        uint8_t(m.wrap_v) >= uint8_t(TextureWrap::count_))
      return at + "unknown wrap mode";
    if (!(m.alpha_cutoff >= 0.0f && m.alpha_cutoff <= 1.0f))
      return at + "alpha cutoff not in [0, 1]";
    if (m.double_sided > 1) return at + "double-sided flag not 0 or 1";
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(m.base_color[c])) return at + "base colour not finite";
  }
  for (size_t i = 0; i < s.textures.size(); ++i) {
    const Texture& t = s.textures[i];
    const std::string at = "texture " + std::to_string(i) + ": ";
    if (uint8_t(t.codec) >= uint8_t(TextureCodec::count_)) return at + "unknown codec";
    if (t.width == 0 || t.height == 0 || t.encoded.empty()) return at + "empty image";
  }
  return validate_cells(s);
}

std::string validate_geometry(const Scene& s, uint32_t first_object, uint32_t object_count,
                              const GeometrySpan& g) {
  const uint64_t vertex_end = g.vertex_base + g.vertices.size();
  for (uint32_t i = first_object; i < first_object + object_count; ++i) {
    const Object& o = s.objects[i];
    if (g.stored && instance_of(s, i)) continue;  // its geometry is its prototype's
    FF_ASSERT(o.first_index >= g.index_base && o.first_index + o.index_count <=
                                                  g.index_base + g.indices.size(),
              "object %u's indices lie outside the span given", i);
    const uint32_t* idx = g.indices.data() + (o.first_index - g.index_base);
    for (uint32_t k = 0; k < o.index_count; ++k) {
      if (idx[k] - o.first_vertex >= o.vertex_count)  // unsigned: also catches idx < first
        return "object " + std::to_string(i) + ": index outside the object's vertex range";
    }
  }
  for (const glm::vec2& uv : g.uvs)
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return "a texture coordinate is not finite";
  for (uint32_t index : g.indices) {
    if (index < g.vertex_base || index >= vertex_end) return "an index is out of the vertex range";
  }
  for (const Vertex& v : g.vertices) {
    if (!std::isfinite(v.position.x) || !std::isfinite(v.position.y) ||
        !std::isfinite(v.position.z))
      return "a vertex position is not finite";
  }
  return {};
}

}  // namespace farfield
