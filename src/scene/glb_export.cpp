#include "farfield/scene/glb_export.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <utility>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "farfield/core/atomic_file.hpp"
#include "farfield/core/text.hpp"
#include "farfield/scene/instances.hpp"

namespace farfield {

namespace {

using nlohmann::json;

// glTF 2.0's enumerations (the specification's numbers, from OpenGL).
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kUnsignedByte = 5121, kUnsignedInt = 5125, kFloat = 5126;
constexpr int kLinear = 9729, kLinearMipmapLinear = 9987;
constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kJsonChunk = 0x4E4F534A, kBinChunk = 0x004E4942;
constexpr uint64_t kGlbLimit = UINT32_MAX;  // the header's length field

// glTF asks a node's matrix to be translation, rotation and scale: true where the linear part's
// columns are orthogonal (a rotation times a scale per axis; instances do not mirror).
bool decomposes(const glm::mat3& m) {
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      if (std::abs(glm::dot(m[a], m[b])) > 1e-5f * glm::length(m[a]) * glm::length(m[b]))
        return false;
  return true;
}

int gl_wrap(TextureWrap w) {
  switch (w) {
    case TextureWrap::clamp:
      return 33071;  // CLAMP_TO_EDGE
    case TextureWrap::mirror:
      return 33648;  // MIRRORED_REPEAT
    default:
      return 10497;  // REPEAT
  }
}

// One bufferView's bytes, accessors appended at 4-byte aligned offsets.
struct View {
  std::string bytes;
  size_t append(const void* data, size_t size) {
    const size_t at = bytes.size();
    bytes.append(static_cast<const char*>(data), size);
    bytes.resize((bytes.size() + 3) & ~size_t(3), '\0');
    return at;
  }
};

}  // namespace

Result<std::string> encode_glb(const Scene& scene, const GlbOptions& options,
                               GlbSummary* summary) {
  std::vector<uint32_t> chosen;
  for (uint32_t i : options.object_list) {
    if (i >= scene.objects.size())
      return make_error("object ", std::to_string(i), " of a scene of ",
                        counted(scene.objects.size(), "object"));
    chosen.push_back(i);
  }
  for (uint32_t i = 0; i < scene.objects.size() && options.object_list.empty(); ++i) {
    const std::string name(scene.object_name(scene.objects[i]));
    if (options.objects.empty() || fnmatch(options.objects.c_str(), name.c_str(), 0) == 0)
      chosen.push_back(i);
  }
  if (chosen.empty())
    return make_error("no object matches --objects '", options.objects, "' (the scene has ",
                      counted(scene.objects.size(), "object"),
                      scene.objects.empty()
                          ? std::string()
                          : ", the first named '" +
                                std::string(scene.object_name(scene.objects[0])) + "'",
                      ")");
  // An instance whose prototype is exported too is a node that places the prototype's mesh
  // with its transform (glTF's own instancing), where that is a glTF node matrix.
  std::vector<bool> is_chosen(scene.objects.size(), false);
  for (uint32_t i : chosen) is_chosen[i] = true;
  std::map<uint32_t, const Instance*> placed;  // object -> its instance, where it shares
  for (uint32_t i : chosen)
    if (const Instance* instance = instance_of(scene, i);
        instance && is_chosen[instance->prototype] && decomposes(instance->linear))
      placed.emplace(i, instance);
  // The binary part's size first: a scene past the container's limit is refused before
  // anything is built.
  uint64_t bin_bytes = 0;
  std::map<uint32_t, uint32_t> materials;  // scene material -> glTF material
  for (uint32_t i : chosen) {
    const Object& o = scene.objects[i];
    if (placed.contains(i)) continue;
    const bool textured = scene.textured(o);
    bin_bytes += uint64_t(o.vertex_count) * (12 + 12 + 4 + (textured ? 8 : 0)) + 16;
    bin_bytes += uint64_t(o.index_count) * 4;
    materials.emplace(o.material, 0);
  }
  std::map<uint32_t, uint32_t> images;  // scene texture -> glTF image
  for (const auto& [m, unused] : materials)
    if (scene.materials[m].textured()) images.emplace(scene.materials[m].texture, 0);
  for (const auto& [t, unused] : images) bin_bytes += scene.textures[t].encoded.size() + 4;
  if (bin_bytes + (uint64_t(64) << 20) > kGlbLimit)
    return make_error("the glb would hold ", number_text(double(bin_bytes) / 1e9),
                      " GB of geometry and images, past the GLB container's 4 GiB; export part "
                      "of the scene with --objects PATTERN (",
                      counted(chosen.size(), "object"), " chosen)");

  View positions, normals, colors, uvs, indices;
  json accessors = json::array(), meshes = json::array(), nodes = json::array();
  auto accessor = [&](int view, size_t offset, int component, bool normalized, size_t count,
                      const char* type) {
    json a = {{"bufferView", view}, {"byteOffset", offset}, {"componentType", component},
              {"count", count}, {"type", type}};
    if (normalized) a["normalized"] = true;
    accessors.push_back(std::move(a));
    return int(accessors.size() - 1);
  };
  // Views 0..4: positions, normals, colours, texture coordinates, indices; then images.
  enum { kPositions, kNormals, kColors, kUvs, kIndices };
  uint32_t next_material = 0;
  for (auto& [m, gltf] : materials) gltf = next_material++;
  uint64_t triangles = 0, vertices = 0;
  std::vector<glm::vec3> position, normal;
  std::vector<uint32_t> local;
  std::map<uint32_t, size_t> mesh_of;  // object -> its glTF mesh
  for (uint32_t i : chosen) {
    const Object& o = scene.objects[i];
    triangles += o.triangle_count();
    vertices += o.vertex_count;
    if (placed.contains(i)) continue;
    const Vertex* v = scene.vertices.data() + o.first_vertex;
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    normal.resize(o.vertex_count);
    position.resize(o.vertex_count);
    for (uint32_t k = 0; k < o.vertex_count; ++k) {
      position[k] = v[k].position;
      lo = glm::min(lo, v[k].position);
      hi = glm::max(hi, v[k].position);
      // glTF asks for unit normals; the stored ones are 10-bit, a degenerate one zero.
      const glm::vec3 n = unpack_normal(v[k].normal);
      const float length = glm::length(n);
      normal[k] = length > 1e-6f ? n / length : glm::vec3(0.0f, 1.0f, 0.0f);
    }
    json attributes;
    const int at = accessor(kPositions, positions.append(position.data(), 12 * o.vertex_count),
                            kFloat, false, o.vertex_count, "VEC3");
    // Required for positions, and checked against the data by validators: the floats as stored.
    accessors[size_t(at)]["min"] = {lo.x, lo.y, lo.z};
    accessors[size_t(at)]["max"] = {hi.x, hi.y, hi.z};
    attributes["POSITION"] = at;
    attributes["NORMAL"] = accessor(kNormals, normals.append(normal.data(), 12 * o.vertex_count),
                                    kFloat, false, o.vertex_count, "VEC3");
    std::vector<uint32_t> rgba(o.vertex_count);
    for (uint32_t k = 0; k < o.vertex_count; ++k) rgba[k] = v[k].color;
    attributes["COLOR_0"] = accessor(kColors, colors.append(rgba.data(), 4 * o.vertex_count),
                                     kUnsignedByte, true, o.vertex_count, "VEC4");
    if (scene.textured(o))
      attributes["TEXCOORD_0"] =
          accessor(kUvs, uvs.append(scene.uvs.data() + o.first_uv, 8 * size_t(o.vertex_count)),
                   kFloat, false, o.vertex_count, "VEC2");
    local.assign(scene.indices.begin() + o.first_index,
                 scene.indices.begin() + o.first_index + o.index_count);
    for (uint32_t& index : local) index -= o.first_vertex;
    const int index_accessor = accessor(kIndices, indices.append(local.data(), 4 * local.size()),
                                        kUnsignedInt, false, local.size(), "SCALAR");
    const std::string name(scene.object_name(o));
    meshes.push_back({{"name", name},
                      {"primitives",
                       {{{"attributes", attributes},
                         {"indices", index_accessor},
                         {"material", materials.at(o.material)},
                         {"mode", 4}}}}});
    mesh_of[i] = meshes.size() - 1;
  }
  for (uint32_t i : chosen) {
    const Object& o = scene.objects[i];
    json node = {{"name", std::string(scene.object_name(o))},
                 {"extras", {{"kind", std::string(object_kind_name(o.kind))}}}};
    if (auto it = placed.find(i); it != placed.end()) {
      const Instance& instance = *it->second;
      const glm::mat3& m = instance.linear;
      node["mesh"] = mesh_of.at(instance.prototype);
      node["matrix"] = {m[0][0], m[0][1], m[0][2], 0.0f, m[1][0], m[1][1], m[1][2], 0.0f,
                        m[2][0], m[2][1], m[2][2], 0.0f, instance.offset.x, instance.offset.y,
                        instance.offset.z, 1.0f};
    } else {
      node["mesh"] = mesh_of.at(i);
    }
    nodes.push_back(std::move(node));
  }

  // The binary chunk: the views one after the other, then the images.
  std::string bin;
  json buffer_views = json::array();
  const View* parts[] = {&positions, &normals, &colors, &uvs, &indices};
  // Vertex attributes of several accessors in one view need its stride; indices have none.
  const int strides[] = {12, 12, 4, 8, 0};
  int view_number[5];
  for (int k = 0; k < 5; ++k) {
    view_number[k] = int(buffer_views.size());
    if (parts[k]->bytes.empty()) continue;  // glTF forbids empty views (no textured object)
    json view = {{"buffer", 0},
                 {"byteOffset", bin.size()},
                 {"byteLength", parts[k]->bytes.size()},
                 {"target", strides[k] ? kArrayBuffer : kElementArrayBuffer}};
    if (strides[k]) view["byteStride"] = strides[k];
    buffer_views.push_back(std::move(view));
    bin += parts[k]->bytes;
  }
  for (json& a : accessors) a["bufferView"] = view_number[a["bufferView"].get<int>()];
  json gltf_images = json::array(), samplers = json::array(), textures = json::array();
  for (auto& [t, gltf] : images) {
    const Texture& texture = scene.textures[t];
    buffer_views.push_back(
        {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", texture.encoded.size()}});
    bin.append(reinterpret_cast<const char*>(texture.encoded.data()), texture.encoded.size());
    bin.resize((bin.size() + 3) & ~size_t(3), '\0');
    gltf = uint32_t(gltf_images.size());
    gltf_images.push_back({{"name", texture.name},
                           {"bufferView", buffer_views.size() - 1},
                           {"mimeType", texture.codec == TextureCodec::jpeg ? "image/jpeg"
                                                                            : "image/png"}});
  }
  json gltf_materials = json::array();
  std::map<std::pair<uint32_t, std::pair<int, int>>, int> texture_of;  // image, wraps -> texture
  std::map<std::pair<int, int>, int> sampler_of;
  for (const auto& [m, gltf] : materials) {
    const Material& material = scene.materials[m];
    json pbr = {{"baseColorFactor",
                 {material.base_color.r, material.base_color.g, material.base_color.b,
                  material.base_color.a}},
                {"metallicFactor", 0.0},
                {"roughnessFactor", 1.0}};
    if (material.textured()) {
      const std::pair<int, int> wraps(gl_wrap(material.wrap_u), gl_wrap(material.wrap_v));
      if (!sampler_of.count(wraps)) {
        sampler_of[wraps] = int(samplers.size());
        samplers.push_back({{"magFilter", kLinear},
                            {"minFilter", kLinearMipmapLinear},
                            {"wrapS", wraps.first},
                            {"wrapT", wraps.second}});
      }
      const auto key = std::pair(images.at(material.texture), wraps);
      if (!texture_of.count(key)) {
        texture_of[key] = int(textures.size());
        textures.push_back({{"source", key.first}, {"sampler", sampler_of[wraps]}});
      }
      pbr["baseColorTexture"] = {{"index", texture_of[key]}};
    }
    json out = {{"name", "material " + std::to_string(m)}, {"pbrMetallicRoughness", pbr}};
    if (material.transparent()) {
      out["alphaMode"] = "BLEND";
    } else if (material.alpha_mode == AlphaMode::mask) {
      out["alphaMode"] = "MASK";
      out["alphaCutoff"] = material.alpha_cutoff;
    }
    if (material.double_sided) out["doubleSided"] = true;
    gltf_materials.push_back(std::move(out));
  }

  json root_nodes = json::array();
  for (size_t k = 0; k < nodes.size(); ++k) root_nodes.push_back(k);
  json gltf = {{"asset", {{"version", "2.0"}, {"generator", "farfield"}}},
               {"scene", 0},
               {"scenes", {{{"nodes", root_nodes}}}},
               {"nodes", nodes},
               {"meshes", meshes},
               {"materials", gltf_materials},
               {"accessors", accessors},
               {"bufferViews", buffer_views},
               {"buffers", {{{"byteLength", bin.size()}}}}};
  if (!gltf_images.empty()) {
    gltf["images"] = gltf_images;
    gltf["samplers"] = samplers;
    gltf["textures"] = textures;
  }
  std::string text = gltf.dump();
  text.resize((text.size() + 3) & ~size_t(3), ' ');
  const uint64_t total = 12 + 8 + text.size() + 8 + bin.size();
  if (total > kGlbLimit)
    return make_error("the glb would be ", number_text(double(total) / 1e9),
                      " GB, past the GLB container's 4 GiB; export part of the scene with "
                      "--objects PATTERN");
  std::string glb;
  glb.reserve(total);
  auto word = [&](uint32_t w) { glb.append(reinterpret_cast<const char*>(&w), 4); };
  word(kGlbMagic);
  word(2);
  word(uint32_t(total));
  word(uint32_t(text.size()));
  word(kJsonChunk);
  glb += text;
  word(uint32_t(bin.size()));
  word(kBinChunk);
  glb += bin;
  if (summary) {
    summary->objects = chosen.size();
    summary->triangles = triangles;
    summary->vertices = vertices;
    summary->materials = materials.size();
    summary->textures = images.size();
    summary->bytes = glb.size();
  }
  return glb;
}

Result<GlbSummary> write_glb(const Scene& scene, const std::string& path,
                             const GlbOptions& options) {
  GlbSummary summary;
  auto glb = encode_glb(scene, options, &summary);
  if (!glb) return make_error(path, ": ", glb.error().message);
  if (auto ok = write_file_atomically(path, *glb); !ok) return ok.error();
  return summary;
}

}  // namespace farfield
