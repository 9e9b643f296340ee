#include "farfield/techniques/clusters/cluster_stream.hpp"

#include <algorithm>

#include "farfield/core/bounds.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/chunk_stream.hpp"

namespace farfield {

namespace {

// A pool key: what it is in the top byte, which in the rest.
enum class Item : uint64_t { chunk = 0, lod_page = 1, tree_page = 2 };
uint64_t key_of(Item item, uint32_t index) { return uint64_t(item) << 56 | index; }

// The top pages held for the whole walk: breadth first from the root's, while they stay
// within this share of the budget (and this many bytes).
constexpr uint64_t kPinnedShare = 16;
constexpr uint64_t kPinnedMaxBytes = uint64_t(64) << 20;

uint64_t page_bytes(const MeshPage& page, bool textured) {
  return uint64_t(page.vertex_count) * (sizeof(Vertex) + (textured ? sizeof(glm::vec2) : 0)) +
         uint64_t(page.index_count) * sizeof(uint32_t);
}

// Read on the loader thread, which opens the pack on its first page (a Store is one
// connection: the walk's own stays on its thread).
struct PageLoader {
  std::string pack;
  const ChunkedScene* scene;
  const LodSet* lods;
  const ClusterTree* tree;
  std::shared_ptr<std::optional<Store>> opened = std::make_shared<std::optional<Store>>();

  Result<std::shared_ptr<const SceneMeshData>> operator()(uint64_t key) {
    std::optional<Store>& store = *opened;
    const auto item = Item(key >> 56);
    const uint32_t index = uint32_t(key & ((uint64_t(1) << 56) - 1));
    if (item == Item::chunk) return read_chunk_mesh(*scene, index);
    if (!store) {
      auto open = Store::open(pack, Store::Mode::kRead);
      if (!open) return open.error();
      store.emplace(std::move(*open));
    }
    const bool lod = item == Item::lod_page;
    auto page = read_mesh_page(*store, lod ? kLodPagePrefix : kTreePagePrefix, index,
                               lod ? lods->pages[index] : tree->pages[index]);
    if (!page) return page.error();
    return std::shared_ptr<const SceneMeshData>(std::move(*page));
  }
};

}  // namespace

ClusterStream::ClusterStream(const ChunkedScene& scene, const LodSet& lods, const ClusterTree& tree,
                             const BoxSet& boxes, BoxAtlas& atlas, gpu::Device& device)
    : scene_(scene), lods_(lods), tree_(tree), boxes_(boxes), atlas_(atlas), device_(device) {}

ClusterStream::~ClusterStream() {
  pool_.reset();
  if (pinned_) device_.free(pinned_);
}

Result<std::unique_ptr<ClusterStream>> ClusterStream::create(const ChunkedScene& scene,
                                                             const Store& store, const LodSet& lods,
                                                             const ClusterTree& tree,
                                                             const BoxSet& boxes, BoxAtlas& atlas,
                                                             gpu::Device& device,
                                                             uint64_t budget_bytes, bool averages) {
  std::unique_ptr<ClusterStream> s(new ClusterStream(scene, lods, tree, boxes, atlas, device));
  s->averages_ = averages && !boxes.boxes.empty();
  const size_t nodes = tree.nodes.size();
  s->anchors_ = ChoiceAnchors(tree, boxes, scene.index().objects.size());
  s->box_object_.assign(boxes.boxes.size(), UINT32_MAX);
  for (uint32_t o = 0; o < boxes.object_box.size(); ++o)
    if (const uint32_t b = boxes.object_box[o]; b != BoxSet::kNone) s->box_object_[b] = o;
  s->standing_.assign(nodes, 0);

  // The top of the hierarchy, end to end as a whole load lays it out.
  const bool textured = scene.uv_count() > 0;
  const uint64_t pinned_limit = std::min(budget_bytes / kPinnedShare, kPinnedMaxBytes);
  uint32_t pinned = 0;
  for (uint64_t bytes = 0; pinned < tree.pages.size(); ++pinned) {
    bytes += page_bytes(tree.pages[pinned], textured);
    if (pinned > 0 && bytes > pinned_limit) break;
    s->pinned_bytes_ = bytes;
  }
  if (pinned > 0) {
    std::vector<Vertex> vertices;
    std::vector<glm::vec2> uvs;
    std::vector<uint32_t> indices;
    if (auto read = read_mesh_pages(store, kTreePagePrefix,
                                    std::span(tree.pages).first(pinned), vertices, uvs, indices);
        !read)
      return read.error();
    auto mesh = device.create_scene_mesh(vertices, uvs, indices);
    if (!mesh) return mesh.error();
    s->pinned_ = *mesh;
    s->pinned_pages_ = pinned;
  }

  // Enough meshes for the budget's worth of the smallest pages and chunks, within reason.
  uint64_t smallest = UINT64_MAX;
  for (const SceneChunk& k : scene.chunks()) smallest = std::min(smallest, k.byte_size());
  for (const MeshPage& p : lods.pages) smallest = std::min(smallest, page_bytes(p, textured));
  for (size_t p = pinned; p < tree.pages.size(); ++p)
    smallest = std::min(smallest, page_bytes(tree.pages[p], textured));
  smallest = std::max<uint64_t>(smallest, 4096);
  const uint64_t items = scene.chunks().size() + lods.pages.size() + tree.pages.size();
  const uint32_t meshes = uint32_t(
      std::clamp<uint64_t>(budget_bytes / smallest + 1, 1, std::min<uint64_t>(items + 1, 8192)));
  auto pool = gpu::MeshPool::create(device, {budget_bytes, meshes},
                                    PageLoader{store.path(), &scene, &lods, &tree});
  if (!pool) return pool.error();
  s->pool_ = std::move(*pool);
  return s;
}

std::optional<MeshHandle> ClusterStream::resident_lod_page(uint32_t page) {
  return pool_->peek(key_of(Item::lod_page, page));
}

std::optional<MeshHandle> ClusterStream::resident_tree_page(uint32_t page) {
  if (page < pinned_pages_) return pinned_;
  return pool_->peek(key_of(Item::tree_page, page));
}

ClusterStream::Source ClusterStream::source_of(const Choice& c, const glm::vec3& eye) const {
  switch (c.kind) {
    case Choice::Kind::cluster: {
      const uint32_t page = tree_.node_page[c.index];
      return {page < pinned_pages_ ? kPinned : key_of(Item::tree_page, page),
              -distance_to(tree_.nodes[c.index].bounds, eye), tree_index_base(page)};
    }
    case Choice::Kind::lod: {
      const uint32_t page = lods_.lod_page[c.index];
      return {key_of(Item::lod_page, page),
              -distance_to(scene_.index().objects[lods_.lods[c.index].object].bounds, eye),
              lods_.pages[page].first_index};
    }
    case Choice::Kind::whole: {
      const uint32_t k = scene_.chunk_of(c.index);
      return {key_of(Item::chunk, k), -distance_to(scene_.index().objects[c.index].bounds, eye),
              scene_.chunks()[k].first_index};
    }
    case Choice::Kind::box: {
      const TexturedBox& box = boxes_.boxes[c.index];
      return {kNoMesh, -distance_to(box.bounds, eye), c.index};
    }
    case Choice::Kind::average:
      return {kInMemory, 0.0f, 0};
  }
  return {kNoMesh, 0.0f, 0};
}

void ClusterStream::prefetch(std::span<const Choice> choices, const glm::vec3& eye) {
  for (const Choice& c : choices) {
    const Source s = source_of(c, eye);
    if (s.key == kNoMesh)
      atlas_.want(s.index_base, s.priority, true);
    else if (s.key != kPinned && s.key != kInMemory)
      pool_->prefetch(s.key, s.priority);
  }
}

uint32_t ClusterStream::tree_index_base(uint32_t page) const {
  return page < pinned_pages_ ? 0u : tree_.pages[page].first_index;
}

ClusterStream::StandIn ClusterStream::node_stand_in(uint32_t node, Placed& out) {
  for (uint32_t n = node; n != UINT32_MAX; n = anchors_.parent[n]) {
    if (tree_.nodes[n].clustered())
      if (auto mesh = resident_tree_page(tree_.node_page[n])) {
        out = {{Choice::Kind::cluster, n}, *mesh, tree_index_base(tree_.node_page[n])};
        if (!standing_[n]) standing_list_.push_back(n);
        standing_[n] = 1;
        return StandIn::node;
      }
    if (n < boxes_.node_box.size() && boxes_.node_box[n] != BoxSet::kNone &&
        atlas_.drawable(boxes_.node_box[n])) {
      out = {{Choice::Kind::box, boxes_.node_box[n]}, {}, 0};
      if (!standing_[n]) standing_list_.push_back(n);
      standing_[n] = 1;
      return StandIn::node;
    }
    if (averages_ && n < boxes_.node_box.size() && boxes_.node_box[n] != BoxSet::kNone) {
      out = {{Choice::Kind::average, boxes_.node_box[n]}, {}, 0};
      if (!standing_[n]) standing_list_.push_back(n);
      standing_[n] = 1;
      return StandIn::node;
    }
  }
  return StandIn::none;
}

ClusterStream::StandIn ClusterStream::stand_in(const Choice& c, Placed& out) {
  uint32_t object = UINT32_MAX, finer_than = 0;
  switch (c.kind) {
    case Choice::Kind::cluster:
      return c.index > 0 ? node_stand_in(anchors_.parent[c.index], out) : StandIn::none;
    case Choice::Kind::box:
      object = box_object_[c.index];
      if (object == UINT32_MAX)
        return node_stand_in(anchors_.box_node[c.index],
                             out);  // a node's box: its cluster, or above
      // An object's box: its average-colour box (coarser, always in memory), else its
      // coarsest resident level, else what stands in above it.
      if (averages_) {
        out = {{Choice::Kind::average, c.index}, {}, 0};
        return StandIn::object;
      }
      for (uint32_t k = lods_.first_lod[object + 1]; k-- > lods_.first_lod[object];)
        if (auto mesh = resident_lod_page(lods_.lod_page[k])) {
          out = {{Choice::Kind::lod, k}, *mesh, lods_.pages[lods_.lod_page[k]].first_index};
          return StandIn::object;
        }
      return node_stand_in(anchors_.object_node[object], out);
    case Choice::Kind::average:
      return StandIn::none;  // always drawable
    case Choice::Kind::lod:
      object = lods_.lods[c.index].object;
      finer_than = c.index + 1;
      break;
    case Choice::Kind::whole:
      object = c.index;
      finer_than = lods_.first_lod[object];
      break;
  }
  // The finest resident level coarser than the one asked for.
  for (uint32_t k = finer_than; k < lods_.first_lod[object + 1]; ++k)
    if (auto mesh = resident_lod_page(lods_.lod_page[k])) {
      out = {{Choice::Kind::lod, k}, *mesh, lods_.pages[lods_.lod_page[k]].first_index};
      return StandIn::object;
    }
  if (object < boxes_.object_box.size() && boxes_.object_box[object] != BoxSet::kNone &&
      atlas_.drawable(boxes_.object_box[object])) {
    out = {{Choice::Kind::box, boxes_.object_box[object]}, {}, 0};
    return StandIn::object;
  }
  if (averages_ && object < boxes_.object_box.size() &&
      boxes_.object_box[object] != BoxSet::kNone) {
    out = {{Choice::Kind::average, boxes_.object_box[object]}, {}, 0};
    return StandIn::object;
  }
  return node_stand_in(anchors_.object_node[object], out);
}

bool ClusterStream::covered(uint32_t node, bool self) const {
  for (uint32_t n = self ? node : anchors_.parent[node]; n != UINT32_MAX; n = anchors_.parent[n])
    if (standing_[n]) return true;
  return false;
}

uint64_t ClusterStream::place(std::span<const Choice> choices, const glm::vec3& eye,
                              std::vector<Placed>& out) {
  out.clear();
  candidates_.clear();
  for (uint32_t n : standing_list_) standing_[n] = 0;
  standing_list_.clear();
  uint64_t stood_in = 0;
  for (const Choice& c : choices) {
    const Source source = source_of(c, eye);
    Placed placed{c, {}, source.index_base};
    std::optional<MeshHandle> mesh;
    if (source.key == kPinned) {
      mesh = pinned_;
    } else if (source.key == kInMemory) {
      mesh = MeshHandle{};
    } else if (source.key == kNoMesh) {
      if (atlas_.drawable(source.index_base)) {
        mesh = MeshHandle{};
        placed.index_base = 0;
      } else {
        atlas_.want(source.index_base, source.priority);
      }
    } else {
      mesh = pool_->want(source.key, source.priority);
    }
    if (mesh) {
      placed.mesh = *mesh;
      candidates_.push_back({placed, anchors_.of(c, lods_), StandIn::none});
      continue;
    }
    ++stood_in;
    if (const StandIn kind = stand_in(c, placed); kind != StandIn::none)
      candidates_.push_back({placed, anchors_.of(placed.choice, lods_), kind});
  }
  // A node standing in draws everything beneath it: what lies there goes. A node stands in
  // once, however many choices it stood in for.
  for (const Candidate& c : candidates_) {
    if (c.stand_in == StandIn::node) {
      if (covered(c.node, false) || standing_[c.node] == 2) continue;
      standing_[c.node] = 2;
    } else if (covered(c.node, true)) {
      continue;
    }
    out.push_back(c.placed);
  }
  return stood_in;
}

}  // namespace farfield
