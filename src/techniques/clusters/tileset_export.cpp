#include "farfield/techniques/clusters/tileset_export.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "farfield/core/image.hpp"
#include "farfield/core/text.hpp"
#include "farfield/scene/glb_export.hpp"
#include "farfield/store/tiles_package.hpp"

namespace farfield {

namespace {

using nlohmann::json;

// A box in 3D Tiles' frame (+Z up) from one in glTF's (+Y up): (x, y, z) -> (x, -z, y).
json tiles_box(const Bounds3& b) {
  const glm::vec3 c = b.center();
  const glm::vec3 h = glm::max(b.size() * 0.5f, glm::vec3(1e-3f));  // no flat boxes
  return {{"box", {c.x, -c.z, c.y, h.x, 0.0, 0.0, 0.0, h.z, 0.0, 0.0, 0.0, h.y}}};
}

// A node's merged mesh as a scene of one object a material, its textures copied along.
Scene cluster_scene(const Scene& scene, const ClusterTree& tree, uint32_t node) {
  Scene out;
  SceneBuilder builder(out);
  std::map<uint32_t, uint32_t> textures;  // the scene's -> out's
  const ClusterNode& n = tree.nodes[node];
  for (uint32_t p = n.parts_begin; p < n.parts_end; ++p) {
    const ClusterPart& part = tree.parts[p];
    Material material = scene.materials[part.material];
    if (material.textured()) {
      auto [at, added] = textures.emplace(material.texture, 0);
      if (added) at->second = builder.add_texture(scene.textures[material.texture]);
      material.texture = at->second;
    }
    builder.begin_object("cluster " + std::to_string(node), ObjectKind::mesh,
                         builder.add_material(material));
    std::unordered_map<uint32_t, uint32_t> local;
    uint32_t corner[3];
    for (uint32_t i = 0; i < part.index_count; ++i) {
      const uint32_t index = tree.indices[part.first_index + i];
      auto [at, added] = local.emplace(index, 0);
      if (added) {
        const Vertex& v = tree.vertices[index];
        at->second = builder.add_vertex(v.position, unpack_normal(v.normal), v.color,
                                        tree.uvs.empty() ? glm::vec2(0.0f) : tree.uvs[index]);
      }
      corner[i % 3] = at->second;
      if (i % 3 == 2) builder.add_triangle(corner[0], corner[1], corner[2]);
    }
    builder.end_object();
  }
  return out;
}

// A textured box (paper 001, Sec. 5.1) as a scene: its drawn sides as quads of one material
// cut out by alpha, the sides cut from its atlas page into one texture of their own.
Result<Scene> box_scene(const BoxSet& set, const BoxMeshes& meshes, uint32_t b) {
  const TexturedBox& box = set.boxes[b];
  int x0 = set.page_px, y0 = set.page_px, x1 = 0, y1 = 0;
  for (const BoxSide& side : box.sides)
    if (side.w > 0) {
      x0 = std::min(x0, int(side.x));
      y0 = std::min(y0, int(side.y));
      x1 = std::max(x1, int(side.x + side.w));
      y1 = std::max(y1, int(side.y + side.h));
    }
  RgbaImage crop(x1 - x0, y1 - y0);
  const std::vector<uint8_t>& page = set.pages[box.page];
  for (int y = 0; y < crop.height; ++y)
    std::copy_n(page.data() + (size_t(y0 + y) * size_t(set.page_px) + size_t(x0)) * 4,
                size_t(crop.width) * 4, crop.texel(0, y));
  auto png = encode_png(crop);
  if (!png) return png.error();
  Scene out;
  SceneBuilder builder(out);
  const uint32_t texture = builder.add_texture(Texture{.name = "box " + std::to_string(b),
                                                       .codec = TextureCodec::png,
                                                       .width = uint32_t(crop.width),
                                                       .height = uint32_t(crop.height),
                                                       .has_alpha = true,
                                                       .encoded = std::move(*png)});
  const uint32_t material = builder.add_material(Material{.base_color = glm::vec4(1.0f),
                                                          .texture = texture,
                                                          .alpha_mode = AlphaMode::mask,
                                                          .wrap_u = TextureWrap::clamp,
                                                          .wrap_v = TextureWrap::clamp});
  builder.begin_object("box " + std::to_string(b), ObjectKind::mesh, material);
  const TexturedMesh& mesh = meshes.pages[box.page];
  const float px = float(set.page_px);
  for (uint32_t i = meshes.first_index[b]; i < meshes.first_index[b] + meshes.index_count[b];
       i += 3) {
    const TexturedVertex* v[3] = {&mesh.vertices[mesh.indices[i]],
                                  &mesh.vertices[mesh.indices[i + 1]],
                                  &mesh.vertices[mesh.indices[i + 2]]};
    const glm::vec3 normal =
        glm::normalize(glm::cross(v[1]->position - v[0]->position, v[2]->position - v[0]->position));
    uint32_t corner[3];
    for (int c = 0; c < 3; ++c)  // the page's texture coordinates, moved into the crop
      corner[c] = builder.add_vertex(v[c]->position, normal, 0xffffffffu,
                                     {(v[c]->uv.x * px - float(x0)) / float(crop.width),
                                      (v[c]->uv.y * px - float(y0)) / float(crop.height)});
    builder.add_triangle(corner[0], corner[1], corner[2]);
  }
  builder.end_object();
  return out;
}

float deepest_error(const ClusterTree& tree) {
  float e = 0.0f;
  for (const ClusterNode& n : tree.nodes) e = std::max(e, n.error_m);
  return e;
}

}  // namespace

Result<TilesetSummary> write_tileset(const Scene& scene, const ClusterTree& tree,
                                     const BoxSet& boxes, const std::string& out,
                                     Progress& progress) {
  const BoxMeshes box_quads = box_meshes(boxes);
  if (tree.nodes.empty()) return make_error("the cluster hierarchy has no nodes");
  const bool package = out.ends_with(".3dtiles");
  namespace fs = std::filesystem;
  std::error_code error;
  if (!package && fs::exists(out, error) && !fs::is_empty(out, error))
    return make_error(out, ": exists and is not empty; remove it or name another folder");
  // A folder is written beside its name and renamed when whole, as the package is.
  const std::string folder = out + ".partial";
  std::optional<TilesPackageWriter> writer;
  if (package) {
    auto made = TilesPackageWriter::create(out);
    if (!made) return made.error();
    writer.emplace(std::move(*made));
  } else {
    fs::remove_all(folder, error);
    if (!fs::create_directories(folder + "/tiles", error))
      return make_error(out, ": cannot make the folder: ", error.message());
  }
  struct RemovePartial {
    const std::string& folder;
    bool keep = false;
    ~RemovePartial() {
      std::error_code ignored;
      if (!keep) std::filesystem::remove_all(folder, ignored);
    }
  } cleanup{folder, package};
  TilesetSummary summary;
  auto put = [&](const std::string& key, const std::string& bytes) -> Result<void> {
    summary.bytes += bytes.size();
    if (writer) return writer->put(key, bytes);
    std::ofstream file(folder + "/" + key, std::ios::binary);
    file.write(bytes.data(), std::streamsize(bytes.size()));
    if (!file.flush()) return make_error(out, ": cannot write ", key);
    return {};
  };
  auto content = [&](const Scene& from, const GlbOptions& options) -> Result<json> {
    auto glb = encode_glb(from, options);
    if (!glb) return glb.error();
    const std::string key = "tiles/" + std::to_string(summary.contents++) + ".glb";
    if (auto ok = put(key, *glb); !ok) return ok.error();
    return json{{"uri", key}};
  };

  progress.start("write tiles", tree.nodes.size());
  std::function<Result<json>(uint32_t, float)> tile = [&](uint32_t index,
                                                          float parent_error) -> Result<json> {
    const ClusterNode& n = tree.nodes[index];
    ++summary.tiles;
    json t = {{"boundingVolume", tiles_box(n.bounds)}};
    const std::vector<uint32_t> own(tree.objects.begin() + n.objects_begin,
                                    tree.objects.begin() + n.own_end);
    float error = parent_error;
    json children = json::array();
    if (n.clustered()) {
      // paper 001's cluster, as a modern HLOD: its merged mesh stands for everything beneath.
      auto c = content(cluster_scene(scene, tree, index), {});
      if (!c) return c.error();
      t["content"] = *c;
      error = n.error_m;
    } else if (n.leaf() && !own.empty()) {
      auto c = content(scene, {.object_list = own});  // the objects themselves: exact
      if (!c) return c.error();
      t["content"] = *c;
      error = 0.0f;
    }
    t["geometricError"] = error;
    for (uint32_t k = 0; k < n.child_count; ++k) {
      auto child = tile(n.first_child + k, error);
      if (!child) return child.error();
      children.push_back(std::move(*child));
    }
    if (!own.empty() && (n.clustered() || !n.leaf())) {
      // What this node holds itself, at full detail, beside its children.
      Bounds3 bounds = scene.objects[own.front()].bounds;
      for (uint32_t o : own) bounds.expand(scene.objects[o].bounds);
      auto c = content(scene, {.object_list = own});
      if (!c) return c.error();
      ++summary.tiles;
      children.push_back(
          {{"boundingVolume", tiles_box(bounds)}, {"geometricError", 0.0}, {"content", *c}});
    }
    if (!children.empty()) t["children"] = std::move(children);
    progress.advance();
    // paper 001's cluster representation, the textured box, above the merged mesh where it
    // is coarser than the mesh and no coarser than what is above it.
    const uint32_t b = index < boxes.node_box.size() ? boxes.node_box[index] : BoxSet::kNone;
    if (n.clustered() && b != BoxSet::kNone && boxes.boxes[b].side_count() > 0 &&
        boxes.boxes[b].error_m > n.error_m && boxes.boxes[b].error_m <= parent_error) {
      auto box = box_scene(boxes, box_quads, b);
      if (!box) return box.error();
      auto c = content(*box, {});
      if (!c) return c.error();
      ++summary.tiles;
      ++summary.boxes;
      return json{{"boundingVolume", tiles_box(boxes.boxes[b].bounds)},
                  {"geometricError", boxes.boxes[b].error_m},
                  {"content", *c},
                  {"children", json::array({std::move(t)})}};
    }
    return t;
  };
  // The root's error: its mesh's, or (no mesh there) the largest in the tree, so that it is
  // refined as soon as anything below would be.
  const ClusterNode& root_node = tree.nodes[0];
  const float root_error = root_node.clustered() ? root_node.error_m : deepest_error(tree);
  auto root = tile(0, root_error);
  if (!root) return root.error();
  std::function<int(const json&)> depth_of = [&](const json& t) {
    int deepest = 0;
    if (t.contains("children"))
      for (const json& child : t["children"]) deepest = std::max(deepest, 1 + depth_of(child));
    return deepest;
  };
  summary.depth = depth_of(*root);
  (*root)["refine"] = "REPLACE";
  progress.finish();
  summary.root_error_m = (*root)["geometricError"].get<double>();
  // Drawing nothing at all is wrong by about the scene's size.
  const double tileset_error =
      std::max(summary.root_error_m, double(glm::length(scene.bounds.size())));
  const json tileset = {{"asset", {{"version", "1.1"}, {"generator", "farfield"}}},
                        {"geometricError", tileset_error},
                        {"root", *root}};
  if (auto ok = put("tileset.json", tileset.dump(1)); !ok) return ok.error();
  if (writer) {
    if (auto ok = writer->finish(); !ok) return ok.error();
  } else {
    fs::rename(folder, out, error);
    if (error) return make_error(out, ": cannot move the tileset into place: ", error.message());
    cleanup.keep = true;
  }
  return summary;
}

}  // namespace farfield
