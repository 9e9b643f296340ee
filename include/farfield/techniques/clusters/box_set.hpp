// Textured boxes (paper 001, Sec. 4.1.2 and 5.1): an object, or a cluster's objects, rendered
// orthographically onto each side of its bounding box at bake time, where nothing was drawn
// transparent, and drawn at run time as the box's front sides (12 triangles at most) with
// texels of alpha 0 discarded. The paper draws on black and makes black transparent; the
// renderer clears to alpha 0 instead, so that black surfaces stay.
// Error in metres, comparable with the levels' and clusters' geometric error: the deepest
// surface a side shows behind it (a point shown on a side at depth d moves on screen by up
// to d as the view turns away from the side); what no side shows is not counted.
// Sides are packed in square RGBA8 atlas pages, a box's six on one page, so that the boxes of
// a page are drawn together. Texel size per box: as fine as max_side_px allows, coarser in
// proportion to the box's error as far as needed to keep all sides within the texel budget
// (paper 001's test kept one megatexel).
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "farfield/core/bounds.hpp"
#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/gpu/draw_list.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/techniques/clusters/cluster_tree.hpp"

namespace farfield {

class Store;
namespace gpu {
class Renderer;
}

// A side's image in its page, in texels; w == 0: the side shows nothing and is not drawn.
struct BoxSide {
  uint16_t x = 0, y = 0, w = 0, h = 0;
};

struct TexturedBox {
  Bounds3 bounds;  // of what it stands for
  float error_m = 0;
  uint32_t page = 0;  // atlas page of its sides
  BoxSide sides[6];   // facing +x, -x, +y, -y, +z, -z
  uint32_t side_count() const;
};
static_assert(sizeof(TexturedBox) == 80);

// Side `side` of `box` seen from outside: its centre, and half its extent along the image's
// right and up directions (right x up points outwards: counter-clockwise from outside).
struct BoxSideFrame {
  glm::vec3 centre, right, up;
};
BoxSideFrame box_side_frame(const Bounds3& box, int side);

// Appends the quad centre +- right +- up (counter-clockwise seen from right x up), its
// corners from the top left at texture coordinates (u0, v0) to (u1, v1), all of `colour`.
void append_quad(TexturedMesh& mesh, const glm::vec3& centre, const glm::vec3& right,
                 const glm::vec3& up, glm::vec2 uv0, glm::vec2 uv1, uint32_t colour = 0xffffffffu);

inline constexpr int kBoxGutterPx = 2;  // free texels beside each side, so that mipmaps bleed less

struct BoxSetOptions {
  uint32_t min_triangles = 32;  // an object with fewer gets no box (a box draws up to 12)
  bool clusters = false;        // boxes for the clusters too (the paper's)
  double max_texels = 64e6;     // all sides together (RGBA8: 4 bytes each, a third more mipmapped)
  int max_side_px = 256;        // a side's image, texels on its longer edge at most
  int min_side_px = 4;
  int page_px = 2048;
};

struct BoxSet {
  static constexpr uint32_t kNone = UINT32_MAX;
  int page_px = 0;
  uint32_t page_count = 0;
  // RGBA8, page_px x page_px, rows from the top; empty where loaded without them (read each
  // with read_box_page).
  std::vector<std::vector<uint8_t>> pages;
  // Depth first over the hierarchy. A copy only moved of another object (Scene::instances)
  // shares its prototype's sides: the same page and places, its own bounds.
  std::vector<TexturedBox> boxes;
  std::vector<uint32_t> object_box;         // per scene object: into boxes, or kNone
  std::vector<uint32_t> node_box;           // per ClusterTree node (clustered ones): or kNone
  double bake_s = 0;
  uint64_t texels() const;       // in the pages: shared sides once
  double mean_texel_m() const;  // over the boxes' drawn sides
};

// Boxes for the objects of at least min_triangles (opaque materials) and every cluster of
// `tree` (its objects beneath), rendered by `renderer` (a renderer of `scene`).
Result<BoxSet> bake_box_set(const Scene& scene, const ClusterTree& tree, gpu::Renderer& renderer,
                            const BoxSetOptions& options, Progress& progress);

// The boxes' front sides as textured quads, one mesh per page: box b is indices
// [first_index[b], first_index[b] + index_count[b]) of the mesh of page boxes[b].page.
struct BoxMeshes {
  std::vector<TexturedMesh> pages;
  std::vector<uint32_t> first_index, index_count;
};
BoxMeshes box_meshes(const BoxSet& set);
// The front sides of `boxes` (all of one page, of page_px texels; 0: the set's) as one mesh:
// box boxes[i] is indices [first_index[i], first_index[i] + index_count[i]).
TexturedMesh box_mesh(const BoxSet& set, std::span<const uint32_t> boxes,
                      std::span<uint32_t> first_index, std::span<uint32_t> index_count,
                      int page_px = 0);

// Blobs under "clusters/box*" (replacing a set there) and back; a pack without them holds no
// boxes (an empty set). Refused: sides past their page, pages of the wrong size, boxes not of
// `scene`'s objects or `tree`'s nodes.
Result<void> save_box_set(const BoxSet& set, Store& store);
// Without `pixels` the pages are left in the pack (page_count and page_px from their sizes):
// read each with read_box_page.
Result<BoxSet> load_box_set(const Store& store, const Scene& scene, const ClusterTree& tree,
                            bool pixels = true);
// Page `page`'s pixels into `pixels` (resized; its memory reused).
Result<void> read_box_page(const Store& store, const BoxSet& set, uint32_t page,
                           std::vector<uint8_t>& pixels);

}  // namespace farfield
