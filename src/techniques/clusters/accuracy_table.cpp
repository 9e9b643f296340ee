#include "farfield/techniques/clusters/accuracy_table.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "farfield/core/image_similarity.hpp"
#include "farfield/core/text.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/instances.hpp"
#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/object_set.hpp"

namespace farfield {

namespace {

constexpr const char* kDirections = "clusters/accuracy_directions";
constexpr const char* kLodErrors = "clusters/accuracy_lods";
constexpr const char* kBoxErrors = "clusters/accuracy_boxes";
constexpr const char* kNodeErrors = "clusters/accuracy_nodes";

// An image and which of its pixels something covers.
struct Shot {
  Image image;
  std::vector<uint8_t> covered;
};

Shot half_size(const Shot& s) {
  const int w = std::max(1, s.image.width / 2), h = std::max(1, s.image.height / 2);
  Shot out;
  out.image = Image(w, h);
  out.covered.assign(size_t(w) * size_t(h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int sum[3] = {0, 0, 0};
      uint8_t any = 0;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const int sx = std::min(2 * x + dx, s.image.width - 1);
          const int sy = std::min(2 * y + dy, s.image.height - 1);
          const uint8_t* p = s.image.pixel(sx, sy);
          for (int c = 0; c < 3; ++c) sum[c] += p[c];
          any |= s.covered[size_t(sy) * size_t(s.image.width) + size_t(sx)];
        }
      uint8_t* q = out.image.pixel(x, y);
      for (int c = 0; c < 3; ++c) q[c] = uint8_t((sum[c] + 2) / 4);
      out.covered[size_t(y) * size_t(w) + size_t(x)] = any;
    }
  return out;
}

double similarity(const Shot& a, const Shot& b, Comparator comparator) {
  if (comparator == Comparator::edges) return edge_similarity(a.image, b.image);
  std::vector<uint8_t> either(a.covered.size());
  for (size_t p = 0; p < either.size(); ++p) either[p] = a.covered[p] | b.covered[p];
  return structural_similarity(a.image, b.image, either);
}

// The image error in metres of `shot` against `reference`, texels of `texel_m` at the finest
// level (the header's rule).
float image_error(const Shot& reference, const Shot& shot, float texel_m, float size_m,
                  const AccuracyOptions& o) {
  Shot a = reference, b = shot;
  double failed = 0.0;  // the similarity at the level before
  for (int level = 0; level < o.levels; ++level) {
    const double s = similarity(a, b, o.comparator);
    if (s >= o.threshold) {
      if (level == 0)
        return texel_m *
               float(std::clamp((1.0 - s) / std::max(1.0 - o.threshold, 1e-6), 0.0, 1.0));
      // The texel at which the similarity reaches the threshold, between the level that failed
      // and this one, on the scale of log texel size (not this level's texel, which made every
      // error a power of two of the finest texel and overstated it by up to 2x).
      const double at = std::clamp((o.threshold - failed) / std::max(s - failed, 1e-9), 0.0, 1.0);
      return texel_m * std::exp2(float(level - 1) + float(at));
    }
    failed = s;
    if (level + 1 < o.levels) {
      a = half_size(a);
      b = half_size(b);
    }
  }
  return size_m;
}

// Orthographic and reversed-Z (the renderer's), looking at the sphere around `box` from
// `towards`.
glm::mat4 looking_at(const Bounds3& box, const glm::vec3& towards) {
  const glm::vec3 c = box.center();
  const float r = std::max(0.5f * glm::length(box.size()), 1e-4f);
  const float margin = 0.01f * r + 0.01f;
  const glm::vec3 eye = c + towards * (r + margin);
  const glm::vec3 up = std::abs(towards.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
  return glm::orthoRH_ZO(-r, r, -r, r, 2.0f * r + 2.0f * margin, 0.5f * margin) *
         glm::lookAtRH(eye, c, up);
}

Shot render(gpu::Renderer& renderer, const glm::mat4& view_projection, int px,
            const DrawList& list) {
  renderer.draw_with(view_projection, px, px, list);
  Shot s;
  s.image = renderer.capture();
  s.covered = renderer.capture_alpha();
  for (uint8_t& c : s.covered) c = c != 0;
  return s;
}

// A set's pages on the renderer (mesh_pages.hpp), each uploaded when first drawn and freed
// when the caller is past it.
class PagesOnRenderer {
 public:
  PagesOnRenderer(gpu::Renderer& renderer, const Store* store, std::string prefix,
                  std::span<const MeshPage> pages, std::span<const Vertex> vertices,
                  std::span<const glm::vec2> uvs, std::span<const uint32_t> indices)
      : renderer_(renderer), store_(store), prefix_(std::move(prefix)), pages_(pages),
        vertices_(vertices), uvs_(uvs), indices_(indices) {}
  ~PagesOnRenderer() { free_before(UINT32_MAX); }

  // Indices [first, first + count) of the set, in page `page`, as a range of its mesh, placed
  // by `instance` (DrawRange::instance).
  Result<DrawRange> range(uint32_t page, uint32_t first, uint32_t count, uint32_t material,
                          uint32_t instance = kNoInstance) {
    auto it = meshes_.find(page);
    if (it == meshes_.end()) {
      auto data = mesh_page(store_, prefix_, pages_, page, vertices_, uvs_, indices_);
      if (!data) return data.error();
      auto made = renderer_.create_scene_mesh((*data)->vertices, (*data)->uvs, (*data)->indices);
      if (!made) return made.error();
      it = meshes_.emplace(page, *made).first;
    }
    return DrawRange{first - pages_[page].first_index, count, material, it->second, instance};
  }
  void free_before(uint32_t page) {
    while (!meshes_.empty() && meshes_.begin()->first < page) {
      renderer_.free(meshes_.begin()->second);
      meshes_.erase(meshes_.begin());
    }
  }

 private:
  gpu::Renderer& renderer_;
  const Store* store_;
  std::string prefix_;
  std::span<const MeshPage> pages_;
  std::span<const Vertex> vertices_;
  std::span<const glm::vec2> uvs_;
  std::span<const uint32_t> indices_;
  std::map<uint32_t, MeshHandle> meshes_;
};

void add_range(const Scene& scene, DrawRange range, DrawList& list) {
  (scene.materials[range.material].transparent() ? list.transparent : list.opaque).push_back(range);
}

}  // namespace

std::vector<glm::vec3> sphere_directions(int count) {
  std::vector<glm::vec3> out;
  const float golden = 3.14159265f * (3.0f - std::sqrt(5.0f));
  for (int k = 0; k < count; ++k) {
    const float y = 1.0f - 2.0f * (float(k) + 0.5f) / float(count);
    const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
    const float a = golden * float(k);
    out.push_back({r * std::cos(a), y, r * std::sin(a)});
  }
  return out;
}

uint32_t AccuracyTable::nearest(const glm::vec3& towards_viewer) const {
  uint32_t best = 0;
  float best_dot = -INFINITY;
  // Without a branch: which direction wins is unpredictable, and a mispredicted branch costs
  // more than the selects (a node's or object's direction is asked for wherever it is seen).
  for (uint32_t k = 0; k < directions.size(); ++k) {
    const float d = glm::dot(directions[k], towards_viewer);
    const bool better = d > best_dot;
    best_dot = better ? d : best_dot;
    best = better ? k : best;
  }
  return best;
}

Result<AccuracyTable> bake_accuracy_table(const Scene& scene, const LodSet& lods,
                                          const ClusterTree& tree, const BoxSet& boxes,
                                          gpu::Renderer& renderer, const AccuracyOptions& o,
                                          Progress& progress, const Store* store) {
  if (o.directions < 1 || o.directions > 4096 || o.levels < 1 ||
      (o.resolution_px >> (o.levels - 1)) < 2 || o.resolution_px > 4096)
    return make_error(formatted("accuracy tables: %d directions and %d levels from %d px",
                                o.directions, o.levels, o.resolution_px));
  AccuracyTable table;
  table.directions = sphere_directions(o.directions);
  const size_t k_count = table.directions.size();
  table.lod_error.assign(lods.lods.size() * k_count, 0.0f);
  table.box_error.assign(boxes.boxes.size() * k_count, 0.0f);
  table.node_error.assign(tree.nodes.size() * k_count, 0.0f);

  // The representations go to the renderer a page at a time, as a walk's would: the subjects
  // are taken in page order and a page goes once the subjects after it no longer use it, so
  // that a scene's levels and clusters are never all in memory at once.
  PagesOnRenderer lod_pages(renderer, store, kLodPagePrefix, lods.pages, lods.vertices, lods.uvs,
                            lods.indices);
  PagesOnRenderer cluster_pages(renderer, store, kTreePagePrefix, tree.pages, tree.vertices,
                                tree.uvs, tree.indices);
  const BoxMeshes box_mesh = box_meshes(boxes);
  std::vector<MeshHandle> page_meshes;
  std::vector<TextureHandle> page_textures;
  DrawList uploads;
  for (size_t p = 0; p < box_mesh.pages.size(); ++p) {
    auto made =
        renderer.create_textured_mesh(box_mesh.pages[p].vertices, box_mesh.pages[p].indices);
    if (!made) return made.error();
    page_meshes.push_back(*made);
    page_textures.push_back(renderer.create_texture());
    uploads.uploads.push_back({page_textures.back(), boxes.page_px, boxes.page_px, 4,
                               boxes.pages[p].data(), nullptr, true});
  }
  const int px = o.resolution_px;
  renderer.set_offscreen(px, px);
  renderer.set_clear_alpha(0.0f);
  if (!uploads.uploads.empty()) renderer.draw_with(glm::mat4(1.0f), px, px, uploads);

  auto box_draw = [&](uint32_t box, DrawList& list) {
    const uint32_t page = boxes.boxes[box].page;
    list.meshes.push_back({page_meshes[page], box_mesh.first_index[box], box_mesh.index_count[box],
                           page_textures[page]});
  };
  // One subject: its full geometry (`full`), and each representation drawn by `reps`.
  ObjectSet objects(scene);
  DrawList full, rep;
  struct Rep {
    float* errors;  // k_count of them
    std::function<void(DrawList&)> draw;
  };
  std::vector<Rep> reps;
  auto measure = [&](const Bounds3& bounds) {
    const float size = std::max(glm::length(bounds.size()), 1e-4f);
    const float texel = size / float(px);
    for (size_t k = 0; k < k_count; ++k) {
      const glm::mat4 vp = looking_at(bounds, table.directions[k]);
      const Shot reference = render(renderer, vp, px, full);
      for (Rep& r : reps) {
        rep.clear();
        r.draw(rep);
        r.errors[k] = image_error(reference, render(renderer, vp, px, rep), texel, size, o);
      }
    }
  };

  uint64_t subjects = 0;
  for (uint32_t obj = 0; obj < scene.objects.size(); ++obj)
    subjects +=
        lods.first_lod[obj + 1] > lods.first_lod[obj] || boxes.object_box[obj] != BoxSet::kNone;
  for (const ClusterNode& n : tree.nodes) subjects += n.clustered();
  progress.start("bake accuracy tables", subjects);

  // Objects by the page of their finest level (those with none last).
  std::vector<uint32_t> by_page(scene.objects.size());
  std::iota(by_page.begin(), by_page.end(), 0u);
  auto first_page = [&](uint32_t obj) {
    return lods.first_lod[obj] < lods.first_lod[obj + 1] ? lods.lod_page[lods.first_lod[obj]]
                                                         : UINT32_MAX;
  };
  std::stable_sort(by_page.begin(), by_page.end(),
                   [&](uint32_t l, uint32_t r) { return first_page(l) < first_page(r); });
  // A copy only moved (instances.hpp: moved_copy_of) whose representations match its
  // prototype's, level for level and box for box, is seen from every direction as the
  // prototype is: it takes the prototype's errors instead of being rendered again.
  auto copied_from = [&](uint32_t obj) -> const Instance* {
    const Instance* copy = moved_copy_of(scene, obj);
    if (!copy) return nullptr;
    const uint32_t p = copy->prototype;
    const bool same = lods.first_lod[obj + 1] - lods.first_lod[obj] ==
                          lods.first_lod[p + 1] - lods.first_lod[p] &&
                      (boxes.object_box[obj] == BoxSet::kNone) ==
                          (boxes.object_box[p] == BoxSet::kNone);
    return same ? copy : nullptr;
  };
  for (size_t i = 0; i < by_page.size(); ++i) {
    const uint32_t obj = by_page[i];
    const uint32_t begin = lods.first_lod[obj], end = lods.first_lod[obj + 1];
    const uint32_t box = boxes.object_box[obj];
    if (begin == end && box == BoxSet::kNone) continue;
    if (copied_from(obj)) {
      progress.advance();
      lod_pages.free_before(i + 1 < by_page.size() ? first_page(by_page[i + 1]) : UINT32_MAX);
      continue;
    }
    const Object& object = scene.objects[obj];
    full.clear();
    objects.clear();
    objects.insert(obj);
    objects.emit(full);
    reps.clear();
    for (uint32_t l = begin; l < end; ++l) {
      auto range = lod_pages.range(lods.lod_page[l], lods.lods[l].first_index,
                                   lods.lods[l].index_count, object.material,
                                   lods.instance_of(obj));
      if (!range) return range.error();
      reps.push_back({&table.lod_error[size_t(l) * k_count],
                      [&, r = *range](DrawList& list) { add_range(scene, r, list); }});
    }
    if (box != BoxSet::kNone)
      reps.push_back({&table.box_error[size_t(box) * k_count],
                      [&, box](DrawList& list) { box_draw(box, list); }});
    measure(object.bounds);
    // Finer levels first: a coarser level is never claimed better than a finer one.
    for (uint32_t l = begin + 1; l < end; ++l)
      for (size_t k = 0; k < k_count; ++k)
        table.lod_error[size_t(l) * k_count + k] = std::max(
            table.lod_error[size_t(l) * k_count + k], table.lod_error[size_t(l - 1) * k_count + k]);
    progress.advance();
    // The objects after this one begin at their finest level's page.
    lod_pages.free_before(i + 1 < by_page.size() ? first_page(by_page[i + 1]) : UINT32_MAX);
  }
  for (const Instance& instance : scene.instances)
    if (copied_from(instance.object)) {
      const uint32_t obj = instance.object, p = instance.prototype;
      std::copy_n(&table.lod_error[size_t(lods.first_lod[p]) * k_count],
                  size_t(lods.first_lod[p + 1] - lods.first_lod[p]) * k_count,
                  &table.lod_error[size_t(lods.first_lod[obj]) * k_count]);
      if (boxes.object_box[obj] != BoxSet::kNone)
        std::copy_n(&table.box_error[size_t(boxes.object_box[p]) * k_count], k_count,
                    &table.box_error[size_t(boxes.object_box[obj]) * k_count]);
    }
  // Nodes are breadth first, their pages in the same order.
  for (uint32_t n = 0; n < tree.nodes.size(); ++n) {
    const ClusterNode& node = tree.nodes[n];
    cluster_pages.free_before(tree.node_page[n]);
    if (!node.clustered()) continue;
    full.clear();
    objects.clear();
    for (uint32_t k = node.objects_begin; k < node.objects_end; ++k)
      objects.insert(tree.objects[k]);
    objects.emit(full);
    reps.clear();
    std::vector<DrawRange> parts;
    for (uint32_t p = node.parts_begin; p < node.parts_end; ++p) {
      auto range = cluster_pages.range(tree.node_page[n], tree.parts[p].first_index,
                                       tree.parts[p].index_count, tree.parts[p].material);
      if (!range) return range.error();
      parts.push_back(*range);
    }
    reps.push_back({&table.node_error[size_t(n) * k_count], [&](DrawList& list) {
                      for (const DrawRange& r : parts) add_range(scene, r, list);
                    }});
    const uint32_t box = boxes.node_box[n];
    if (box != BoxSet::kNone)
      reps.push_back({&table.box_error[size_t(box) * k_count],
                      [&, box](DrawList& list) { box_draw(box, list); }});
    measure(node.bounds);
    progress.advance();
  }
  progress.finish();
  renderer.set_clear_alpha(1.0f);
  renderer.set_offscreen(0, 0);
  for (MeshHandle m : page_meshes) renderer.free(m);
  for (TextureHandle t : page_textures) renderer.free(t);
  return table;
}

Result<void> save_accuracy_table(const AccuracyTable& table, Store& store) {
  auto transaction = store.begin();
  if (!transaction) return transaction.error();
  if (auto erased = store.erase("clusters/accuracy_"); !erased) return erased.error();
  if (!table.empty()) {
    if (auto ok = store.put(kDirections, bytes_of(table.directions)); !ok) return ok;
    if (auto ok = store.put(kLodErrors, bytes_of(table.lod_error)); !ok) return ok;
    if (auto ok = store.put(kBoxErrors, bytes_of(table.box_error)); !ok) return ok;
    if (auto ok = store.put(kNodeErrors, bytes_of(table.node_error)); !ok) return ok;
  }
  return transaction->commit();
}

Result<AccuracyTable> load_accuracy_table(const Store& store, const LodSet& lods,
                                          const ClusterTree& tree, const BoxSet& boxes) {
  AccuracyTable table;
  auto present = store.contains(kDirections);
  if (!present) return present.error();
  if (!*present) return table;
  auto directions = read_array<glm::vec3>(store, kDirections);
  if (!directions) return directions.error();
  auto lod_error = read_array<float>(store, kLodErrors);
  if (!lod_error) return lod_error.error();
  auto box_error = read_array<float>(store, kBoxErrors);
  if (!box_error) return box_error.error();
  auto node_error = read_array<float>(store, kNodeErrors);
  if (!node_error) return node_error.error();
  const size_t k = directions->size();
  auto inconsistent = [&](const char* what) {
    return make_error(store.path(), ": clusters bake is inconsistent (accuracy tables: ", what,
                      ")");
  };
  if (k == 0) return inconsistent("no directions");
  for (const glm::vec3& d : *directions)
    if (!(std::abs(glm::length(d) - 1.0f) < 1e-3f))
      return inconsistent("a direction not of unit length");
  if (lod_error->size() != lods.lods.size() * k || box_error->size() != boxes.boxes.size() * k ||
      node_error->size() != tree.nodes.size() * k)
    return inconsistent("not one error per representation and direction");
  for (const auto* errors : {&*lod_error, &*box_error, &*node_error})
    for (float e : *errors)
      if (!(e >= 0.0f) || !std::isfinite(e)) return inconsistent("an error not finite");
  table.directions = std::move(*directions);
  table.lod_error = std::move(*lod_error);
  table.box_error = std::move(*box_error);
  table.node_error = std::move(*node_error);
  return table;
}

}  // namespace farfield
