#include "farfield/techniques/clusters/box_set.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <set>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "farfield/core/shelf_packer.hpp"
#include "farfield/core/text.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/instances.hpp"
#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/object_set.hpp"

namespace farfield {

namespace {

constexpr const char* kBoxes = "clusters/boxes";
constexpr const char* kObjectBoxes = "clusters/box_of_objects";
constexpr const char* kNodeBoxes = "clusters/box_of_nodes";
constexpr const char* kPagePrefix = "clusters/box_page_";

// A side's frame: its outward normal, and the image's right and up directions (right x up =
// normal, so that the quad is counter-clockwise seen from outside).
struct SideFrame {
  glm::vec3 normal, right, up;
};
SideFrame side_frame(int side) {
  static const glm::vec3 kNormals[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                        {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  static const glm::vec3 kUps[6] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1},
                                    {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
  const glm::vec3 n = kNormals[side], u = kUps[side];
  return {n, glm::cross(-n, u), u};
}

// Half the side's extent along its right and up directions, and the box's depth behind it.
struct SideExtent {
  float half_width, half_height, depth;
};
SideExtent side_extent(const Bounds3& box, int side) {
  const SideFrame f = side_frame(side);
  const glm::vec3 half = 0.5f * box.size();
  return {std::abs(glm::dot(half, f.right)), std::abs(glm::dot(half, f.up)),
          2.0f * std::abs(glm::dot(half, f.normal))};
}

int side_px(float length_m, float texel_m, const BoxSetOptions& o) {
  return std::clamp(int(std::ceil(length_m / texel_m)), o.min_side_px, o.max_side_px);
}

// A side with no area (a flat object seen edge on) is never drawn.
bool side_has_area(const SideExtent& e, const Bounds3& box) {
  const float scale = std::max(1e-6f * glm::length(box.size()), 1e-9f);
  return e.half_width > scale && e.half_height > scale;
}

struct Subject {
  uint32_t object = BoxSet::kNone, node = BoxSet::kNone;  // one of them
  Bounds3 bounds;
};

// Objects and clusters depth first (a node's own objects after it), so that neighbours in the
// hierarchy are neighbours in the pages.
std::vector<Subject> subjects_of(const Scene& scene, const ClusterTree& tree,
                                 const BoxSetOptions& o) {
  std::vector<Subject> out;
  if (tree.nodes.empty()) return out;
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const uint32_t n = stack.back();
    stack.pop_back();
    const ClusterNode& node = tree.nodes[n];
    if (node.clustered() && o.clusters) out.push_back({BoxSet::kNone, n, node.bounds});
    for (uint32_t k = node.objects_begin; k < node.own_end; ++k) {
      const uint32_t object = tree.objects[k];
      const Object& obj = scene.objects[object];
      const Material& m = scene.materials[obj.material];
      if (obj.index_count / 3 >= o.min_triangles && !m.transparent() && !obj.bounds.empty())
        out.push_back({object, BoxSet::kNone, obj.bounds});
    }
    for (uint32_t c = node.child_count; c-- > 0;) stack.push_back(node.first_child + c);
  }
  return out;
}

float longest(const Bounds3& box) {
  const glm::vec3 s = box.size();
  return std::max({s.x, s.y, s.z, 1e-6f});
}

// Per subject the texel size, metres: as fine as max_side_px allows where the texel budget
// permits; where it does not, coarser in proportion to the box's error (a box is drawn where
// its error projects below clusters.error_px, so the boxes of large error are seen from
// farthest), with a sixty-fourth of its size standing in for an error near 0. A copy's
// (`source`: its prototype's subject) texels are its prototype's, counted once.
std::vector<float> texel_sizes(const std::vector<Subject>& subjects,
                               const std::vector<float>& errors,
                               const std::vector<uint32_t>& source, const BoxSetOptions& o) {
  auto sizes = [&](double share) {
    std::vector<float> texel(subjects.size());
    for (size_t k = 0; k < subjects.size(); ++k) {
      const float size = longest(subjects[k].bounds);
      texel[k] =
          std::max(size / float(o.max_side_px), float(share) * std::max(errors[k], size / 64.0f));
    }
    return texel;
  };
  auto fits = [&](double share) {
    const std::vector<float> texel = sizes(share);
    double sum = 0;
    for (size_t k = 0; k < subjects.size(); ++k)
      for (int side = 0; side < 6 && source[k] == BoxSet::kNone; ++side) {
        const SideExtent e = side_extent(subjects[k].bounds, side);
        if (side_has_area(e, subjects[k].bounds))
          sum += double(side_px(2 * e.half_width, texel[k], o)) *
                 side_px(2 * e.half_height, texel[k], o);
      }
    return sum <= o.max_texels;
  };
  if (fits(0.0)) return sizes(0.0);
  double fine = 0.0, coarse = 1.0;
  while (!fits(coarse) && coarse < 1e6) coarse *= 2.0;
  for (int step = 0; step < 30; ++step) {
    const double mid = 0.5 * (fine + coarse);
    (fits(mid) ? coarse : fine) = mid;
  }
  return sizes(coarse);
}

// Orthographic, reversed-Z (the renderer's: 1 at the near plane), looking at a side from
// `margin` outside it.
glm::mat4 side_view_projection(const Bounds3& box, int side, float margin, float near_m,
                               float far_m) {
  const SideFrame f = side_frame(side);
  const SideExtent e = side_extent(box, side);
  const glm::vec3 face_centre = box.center() + f.normal * (0.5f * e.depth);
  const glm::vec3 eye = face_centre + f.normal * margin;
  const glm::mat4 view = glm::lookAtRH(eye, face_centre, f.up);
  // glm's ZO projection maps its near argument to 0: the planes swapped give reversed Z.
  const glm::mat4 projection =
      glm::orthoRH_ZO(-e.half_width, e.half_width, -e.half_height, e.half_height, far_m, near_m);
  return projection * view;
}

}  // namespace

BoxSideFrame box_side_frame(const Bounds3& box, int side) {
  const SideFrame f = side_frame(side);
  const SideExtent e = side_extent(box, side);
  return {box.center() + f.normal * (0.5f * e.depth), f.right * e.half_width, f.up * e.half_height};
}

void append_quad(TexturedMesh& mesh, const glm::vec3& centre, const glm::vec3& right,
                 const glm::vec3& up, glm::vec2 uv0, glm::vec2 uv1, uint32_t colour) {
  const uint32_t base = uint32_t(mesh.vertices.size());
  mesh.vertices.push_back({centre - right + up, {uv0.x, uv0.y}, colour});  // top left
  mesh.vertices.push_back({centre - right - up, {uv0.x, uv1.y}, colour});  // bottom left
  mesh.vertices.push_back({centre + right - up, {uv1.x, uv1.y}, colour});  // bottom right
  mesh.vertices.push_back({centre + right + up, {uv1.x, uv0.y}, colour});  // top right
  for (uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + k);
}

uint32_t TexturedBox::side_count() const {
  uint32_t n = 0;
  for (const BoxSide& s : sides) n += s.w > 0;
  return n;
}

double BoxSet::mean_texel_m() const {
  double sum = 0;
  uint64_t sides = 0;
  for (const TexturedBox& b : boxes)
    for (int side = 0; side < 6; ++side)
      if (b.sides[side].w > 0) {
        sum += 2.0 * side_extent(b.bounds, side).half_width / b.sides[side].w;
        ++sides;
      }
  return sides ? sum / double(sides) : 0.0;
}

uint64_t BoxSet::texels() const {
  // Boxes may share their sides' texels (copies of one model): each place counted once.
  std::set<std::array<uint32_t, 3>> seen;
  uint64_t n = 0;
  for (const TexturedBox& b : boxes)
    for (const BoxSide& s : b.sides)
      if (s.w > 0 && seen.insert({b.page, s.x, s.y}).second) n += uint64_t(s.w) * s.h;
  return n;
}

namespace {

struct SideImage {
  int w = 0, h = 0;
  std::vector<uint8_t> rgba;  // empty: nothing drawn on the side
};

// One side rendered at its size for `texel_m`; returns the depth of the deepest surface it
// shows behind the side (0 for an empty side).
float render_side(gpu::Renderer& renderer, const DrawList& list, const Bounds3& box, int side,
                  float texel_m, const BoxSetOptions& o, SideImage& image) {
  image = {};
  const SideExtent e = side_extent(box, side);
  if (!side_has_area(e, box)) return 0.0f;
  const int w = side_px(2 * e.half_width, texel_m, o), h = side_px(2 * e.half_height, texel_m, o);
  const float margin = 0.01f * glm::length(box.size()) + 0.01f;
  const float near_m = 0.5f * margin, far_m = e.depth + 2.0f * margin;
  renderer.set_offscreen(w, h);
  renderer.draw_with(side_view_projection(box, side, margin, near_m, far_m), w, h, list);
  const Image rgb = renderer.capture();
  const std::vector<uint8_t> alpha = renderer.capture_alpha();
  const std::vector<float> depth = renderer.capture_depth();
  float deepest = 0.0f;
  bool any = false;
  std::vector<uint8_t> rgba(alpha.size() * 4);
  for (size_t p = 0; p < alpha.size(); ++p) {
    std::copy_n(&rgb.rgb[3 * p], 3, &rgba[4 * p]);
    rgba[4 * p + 3] = alpha[p];
    if (alpha[p] == 0) continue;
    any = true;
    // Reversed Z, linear in an orthographic view: the distance from the eye, less the margin.
    deepest = std::max(deepest, far_m - depth[p] * (far_m - near_m) - margin);
  }
  if (any) image = {w, h, std::move(rgba)};
  return deepest;
}

void draw_list_of(const Subject& s, const ClusterTree& tree, ObjectSet& objects, DrawList& list) {
  objects.clear();
  if (s.object != BoxSet::kNone)
    objects.insert(s.object);
  else
    for (uint32_t k = tree.nodes[s.node].objects_begin; k < tree.nodes[s.node].objects_end; ++k)
      objects.insert(tree.objects[k]);
  list.clear();
  objects.emit(list);
}

}  // namespace

Result<BoxSet> bake_box_set(const Scene& scene, const ClusterTree& tree, gpu::Renderer& renderer,
                            const BoxSetOptions& options, Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (options.max_side_px + kBoxGutterPx > options.page_px || options.min_side_px < 1 ||
      options.min_side_px > options.max_side_px || options.page_px > 16384)
    return make_error(formatted("boxes: sides of %d to %d texels do not fit pages of %d",
                                options.min_side_px, options.max_side_px, options.page_px));
  BoxSet set;
  set.page_px = options.page_px;
  set.object_box.assign(scene.objects.size(), BoxSet::kNone);
  set.node_box.assign(tree.nodes.size(), BoxSet::kNone);
  const std::vector<Subject> subjects = subjects_of(scene, tree, options);

  ObjectSet objects(scene);
  DrawList list;
  SideImage images[6];
  renderer.set_clear_alpha(0.0f);
  // A copy only moved (instances.hpp: moved_copy_of) looks from every side as its prototype
  // does: its box takes the prototype's images and error instead of rendering them again.
  std::vector<uint32_t> source(subjects.size(), BoxSet::kNone);  // the prototype's subject
  {
    std::vector<uint32_t> subject_of(scene.objects.size(), BoxSet::kNone);
    for (size_t k = 0; k < subjects.size(); ++k)
      if (subjects[k].object != BoxSet::kNone) subject_of[subjects[k].object] = uint32_t(k);
    for (size_t k = 0; k < subjects.size(); ++k)
      if (subjects[k].object != BoxSet::kNone)
        if (const Instance* copy = moved_copy_of(scene, subjects[k].object))
          source[k] = subject_of[copy->prototype];
  }
  progress.start("bake textured boxes", 2 * subjects.size());
  // First each box's error from small images (32 texels on its longest edge), which sets
  // its texel size; then its sides at that size.
  std::vector<float> estimates(subjects.size());
  for (size_t k = 0; k < subjects.size(); ++k) {
    if (source[k] != BoxSet::kNone) {
      progress.advance();
      continue;
    }
    draw_list_of(subjects[k], tree, objects, list);
    const float texel = longest(subjects[k].bounds) / 32.0f;
    for (int side = 0; side < 6; ++side)
      estimates[k] = std::max(estimates[k], render_side(renderer, list, subjects[k].bounds, side,
                                                        texel, options, images[side]));
    progress.advance();
  }
  for (size_t k = 0; k < subjects.size(); ++k)
    if (source[k] != BoxSet::kNone) estimates[k] = estimates[source[k]];
  std::vector<float> texels = texel_sizes(subjects, estimates, source, options);
  for (size_t k = 0; k < subjects.size(); ++k)
    if (source[k] != BoxSet::kNone) texels[k] = texels[source[k]];

  // Every box's sides first (the texel budget bounds them), then packed the tallest first,
  // each box on the first page with room for all its sides: shelves of like heights, pages
  // left open. Packed in the order they were drawn, pages were a third full (47 pages of
  // 2048^2 for 61.7 Mtexel on the 10M city), and the renderer holds every page.
  struct Drawn {
    TexturedBox box;
    std::array<SideImage, 6> images;
    int tallest = 0;
  };
  std::vector<Drawn> made(subjects.size());
  for (size_t k = 0; k < subjects.size(); ++k) {
    if (source[k] != BoxSet::kNone) continue;
    const Subject& s = subjects[k];
    draw_list_of(s, tree, objects, list);
    Drawn& d = made[k];
    d.box.bounds = s.bounds;
    for (int side = 0; side < 6; ++side) {
      d.box.error_m = std::max(d.box.error_m, render_side(renderer, list, s.bounds, side,
                                                          texels[k], options, d.images[side]));
      if (!d.images[side].rgba.empty()) d.tallest = std::max(d.tallest, d.images[side].h);
    }
    progress.advance();
  }
  // A copy's box: its own bounds, its prototype's error and, once packed, its sides' texels.
  for (size_t k = 0; k < subjects.size(); ++k)
    if (source[k] != BoxSet::kNone) {
      made[k].box = made[source[k]].box;
      made[k].box.bounds = subjects[k].bounds;
      made[k].tallest = made[source[k]].tallest;
      progress.advance();
    }
  std::vector<Drawn> drawn;
  std::vector<uint32_t> box_of_subject(subjects.size(), BoxSet::kNone);
  for (size_t k = 0; k < subjects.size(); ++k) {
    const Subject& s = subjects[k];
    Drawn d = std::move(made[k]);
    if (d.tallest == 0) continue;
    const uint32_t id = uint32_t(set.boxes.size());
    set.boxes.push_back(d.box);
    (s.object != BoxSet::kNone ? set.object_box[s.object] : set.node_box[s.node]) = id;
    box_of_subject[k] = id;
    drawn.push_back(std::move(d));
  }
  progress.finish();
  std::vector<uint32_t> by_height;
  for (size_t k = 0; k < subjects.size(); ++k)
    if (box_of_subject[k] != BoxSet::kNone && source[k] == BoxSet::kNone)
      by_height.push_back(box_of_subject[k]);
  std::stable_sort(by_height.begin(), by_height.end(),
                   [&](uint32_t l, uint32_t r) { return drawn[l].tallest > drawn[r].tallest; });
  std::vector<ShelfPacker> packers;
  const size_t page_bytes = size_t(options.page_px) * size_t(options.page_px) * 4;
  for (uint32_t id : by_height) {
    Drawn& d = drawn[id];
    std::vector<glm::ivec2> sizes;
    for (const SideImage& image : d.images)
      if (!image.rgba.empty()) sizes.push_back({image.w, image.h});
    std::optional<std::vector<glm::ivec2>> at;
    uint32_t page = 0;
    for (; page < packers.size() && !at; ++page) at = packers[page].place(sizes);
    if (at) {
      --page;
    } else {
      packers.emplace_back(options.page_px, kBoxGutterPx);
      at = packers.back().place(sizes);
      set.pages.emplace_back(page_bytes, 0);
    }
    TexturedBox& box = set.boxes[id];
    box.page = page;
    std::vector<uint8_t>& pixels = set.pages[page];
    size_t placed = 0;
    for (int side = 0; side < 6; ++side) {
      SideImage& image = d.images[side];
      if (image.rgba.empty()) continue;
      const glm::ivec2 p = (*at)[placed++];
      box.sides[side] = {uint16_t(p.x), uint16_t(p.y), uint16_t(image.w), uint16_t(image.h)};
      for (int y = 0; y < image.h; ++y)
        std::copy_n(&image.rgba[size_t(y) * size_t(image.w) * 4], size_t(image.w) * 4,
                    &pixels[(size_t(p.y + y) * size_t(options.page_px) + size_t(p.x)) * 4]);
      image.rgba = {};
    }
  }
  // Copies draw from their prototypes' texels: the atlas holds them once.
  for (size_t k = 0; k < subjects.size(); ++k)
    if (box_of_subject[k] != BoxSet::kNone && source[k] != BoxSet::kNone) {
      TexturedBox& box = set.boxes[box_of_subject[k]];
      const TexturedBox& prototype = set.boxes[box_of_subject[source[k]]];
      box.page = prototype.page;
      std::copy(std::begin(prototype.sides), std::end(prototype.sides), std::begin(box.sides));
    }
  renderer.set_clear_alpha(1.0f);
  renderer.set_offscreen(0, 0);
  set.page_count = uint32_t(set.pages.size());
  set.bake_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return set;
}

TexturedMesh box_mesh(const BoxSet& set, std::span<const uint32_t> boxes,
                      std::span<uint32_t> first_index, std::span<uint32_t> index_count,
                      int page_px) {
  TexturedMesh mesh;
  const int px = page_px > 0 ? page_px : set.page_px;
  const float texel = px > 0 ? 1.0f / float(px) : 0.0f;
  for (size_t i = 0; i < boxes.size(); ++i) {
    const TexturedBox& box = set.boxes[boxes[i]];
    first_index[i] = uint32_t(mesh.indices.size());
    for (int side = 0; side < 6; ++side) {
      const BoxSide& s = box.sides[side];
      if (s.w == 0) continue;
      const auto [c, r, u] = box_side_frame(box.bounds, side);
      const float u0 = float(s.x) * texel, v0 = float(s.y) * texel;
      const float u1 = float(s.x + s.w) * texel, v1 = float(s.y + s.h) * texel;
      append_quad(mesh, c, r, u, {u0, v0}, {u1, v1});
    }
    index_count[i] = uint32_t(mesh.indices.size()) - first_index[i];
  }
  return mesh;
}

BoxMeshes box_meshes(const BoxSet& set) {
  BoxMeshes out;
  out.pages.resize(set.page_count);
  out.first_index.resize(set.boxes.size());
  out.index_count.resize(set.boxes.size());
  std::vector<std::vector<uint32_t>> of_page(set.page_count);
  for (uint32_t b = 0; b < set.boxes.size(); ++b) of_page[set.boxes[b].page].push_back(b);
  std::vector<uint32_t> first, count;
  for (uint32_t p = 0; p < set.page_count; ++p) {
    first.resize(of_page[p].size());
    count.resize(of_page[p].size());
    out.pages[p] = box_mesh(set, of_page[p], first, count);
    for (size_t i = 0; i < of_page[p].size(); ++i) {
      out.first_index[of_page[p][i]] = first[i];
      out.index_count[of_page[p][i]] = count[i];
    }
  }
  return out;
}

Result<void> save_box_set(const BoxSet& set, Store& store) {
  auto transaction = store.begin();
  if (!transaction) return transaction.error();
  if (auto erased = store.erase("clusters/box"); !erased) return erased.error();
  if (auto ok = store.put(kBoxes, bytes_of(set.boxes)); !ok) return ok;
  if (auto ok = store.put(kObjectBoxes, bytes_of(set.object_box)); !ok) return ok;
  if (auto ok = store.put(kNodeBoxes, bytes_of(set.node_box)); !ok) return ok;
  for (size_t p = 0; p < set.pages.size(); ++p)
    if (auto ok = store.put(kPagePrefix + std::to_string(p), bytes_of(set.pages[p])); !ok)
      return ok;
  return transaction->commit();
}

Result<void> read_box_page(const Store& store, const BoxSet& set, uint32_t page,
                           std::vector<uint8_t>& pixels) {
  pixels.resize(size_t(set.page_px) * size_t(set.page_px) * 4);
  return store.get_into(kPagePrefix + std::to_string(page),
                        std::as_writable_bytes(std::span(pixels)));
}

Result<BoxSet> load_box_set(const Store& store, const Scene& scene, const ClusterTree& tree,
                            bool pixels) {
  BoxSet set;
  auto present = store.contains(kBoxes);
  if (!present) return present.error();
  if (!*present) {
    set.object_box.assign(scene.objects.size(), BoxSet::kNone);
    set.node_box.assign(tree.nodes.size(), BoxSet::kNone);
    return set;
  }
  auto inconsistent = [&](const std::string& what) {
    return make_error(store.path(), ": clusters bake is inconsistent (", what, ")");
  };
  auto boxes = read_array<TexturedBox>(store, kBoxes);
  if (!boxes) return boxes.error();
  auto object_box = read_array<uint32_t>(store, kObjectBoxes);
  if (!object_box) return object_box.error();
  auto node_box = read_array<uint32_t>(store, kNodeBoxes);
  if (!node_box) return node_box.error();
  if (object_box->size() != scene.objects.size() || node_box->size() != tree.nodes.size())
    return inconsistent("textured boxes not of this scene's objects and hierarchy");
  for (const auto* ids : {&*object_box, &*node_box})
    for (uint32_t b : *ids)
      if (b != BoxSet::kNone && b >= boxes->size()) return inconsistent("a box past the boxes");
  uint32_t pages = 0;
  for (const TexturedBox& b : *boxes) pages = std::max(pages, b.page + 1);
  // The pages' sizes from the pack's records, their pixels read now or later.
  for (uint32_t p = 0; p < pages; ++p) {
    const std::string name = kPagePrefix + std::to_string(p);
    auto info = store.info(name);
    if (!info) return info.error();
    if (!*info) return make_error(store.path(), ": no blob '", name, "'");
    const uint64_t bytes = (*info)->raw_size;
    const int side = int(std::lround(std::sqrt(double(bytes / 4))));
    if (side <= 0 || bytes != uint64_t(side) * uint64_t(side) * 4 ||
        (set.page_px != 0 && side != set.page_px))
      return inconsistent(formatted("box page %u is not a square RGBA8 page", p));
    set.page_px = side;
  }
  set.page_count = pages;
  for (uint32_t p = 0; pixels && p < pages; ++p) {
    set.pages.emplace_back();
    if (auto read = read_box_page(store, set, p, set.pages.back()); !read) return read.error();
  }
  for (const TexturedBox& b : *boxes) {
    if (!(b.error_m >= 0.0f) || !std::isfinite(b.error_m) || b.bounds.empty())
      return inconsistent("a box's bounds or error");
    for (const BoxSide& s : b.sides)
      if (s.w > 0 && (int(s.x) + s.w > set.page_px || int(s.y) + s.h > set.page_px || s.h == 0))
        return inconsistent("a box's side past its page");
  }
  set.boxes = std::move(*boxes);
  set.object_box = std::move(*object_box);
  set.node_box = std::move(*node_box);
  return set;
}

}  // namespace farfield
