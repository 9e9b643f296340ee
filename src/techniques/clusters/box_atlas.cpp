#include "farfield/techniques/clusters/box_atlas.hpp"

#include <algorithm>
#include <array>
#include <condition_variable>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "farfield/core/assert.hpp"
#include "farfield/core/parallel.hpp"
#include "farfield/core/shelf_packer.hpp"
#include "farfield/gpu/mesh_pool.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

namespace {

// Tiles cut and waiting for frames, at most.
constexpr size_t kReadAhead = 4;

// A box's drawn sides, tallest first (shelves fill better so).
std::vector<int> sides_tallest_first(const TexturedBox& box) {
  std::vector<int> sides;
  for (int side = 0; side < 6; ++side)
    if (box.sides[side].w > 0) sides.push_back(side);
  std::stable_sort(sides.begin(), sides.end(),
                   [&](int a, int b) { return box.sides[a].h > box.sides[b].h; });
  return sides;
}

}  // namespace

BoxTiling tile_boxes(const BoxSet& set, int tile_px) {
  BoxTiling t;
  t.whole_pages = tile_px <= 0 || tile_px >= set.page_px;
  t.tiles.page_px = t.whole_pages ? set.page_px : tile_px;
  t.tiles.boxes = set.boxes;
  std::vector<std::vector<uint32_t>> of_page(set.page_count), of_tile;
  for (uint32_t b = 0; b < set.boxes.size(); ++b) of_page[set.boxes[b].page].push_back(b);
  if (t.whole_pages) {
    for (uint32_t p = 0; p < set.page_count; ++p) t.page_of_tile.push_back(p);
    t.tile_px.assign(set.page_count, set.page_px);
    of_tile = std::move(of_page);
  }
  for (uint32_t p = 0; !t.whole_pages && p < set.page_count; ++p) {
    // The tile being filled of each size, smallest first.
    std::vector<int> open_px;
    std::vector<std::pair<ShelfPacker, uint32_t>> open;
    for (int px = t.tiles.page_px;; px = std::min(2 * px, set.page_px)) {
      open_px.push_back(px);
      open.push_back({ShelfPacker(px, kBoxGutterPx), UINT32_MAX});
      if (px == set.page_px) break;
    }
    // Boxes that share their sides' texels (copies of one model, box_set.hpp) share them in
    // the tiles too: the first one's places.
    std::map<std::array<uint16_t, 24>, uint32_t> first_with;
    for (uint32_t b : of_page[p]) {
      TexturedBox& box = t.tiles.boxes[b];
      std::array<uint16_t, 24> key;
      for (int side = 0; side < 6; ++side) {
        const BoxSide& s = set.boxes[b].sides[side];
        key[4 * side] = s.x, key[4 * side + 1] = s.y, key[4 * side + 2] = s.w,
                key[4 * side + 3] = s.h;
      }
      if (const auto [at, fresh] = first_with.try_emplace(key, b); !fresh) {
        const TexturedBox& first = t.tiles.boxes[at->second];
        box.page = first.page;
        std::copy(std::begin(first.sides), std::end(first.sides), std::begin(box.sides));
        of_tile[box.page].push_back(b);
        continue;
      }
      const std::vector<int> sides = sides_tallest_first(box);
      std::vector<glm::ivec2> sizes;
      for (int side : sides) sizes.push_back({box.sides[side].w, box.sides[side].h});
      bool placed = false;
      for (size_t k = 0; k < open.size() && !placed; ++k) {
        auto& [packer, tile] = open[k];
        auto at = tile != UINT32_MAX ? packer.place(sizes) : std::nullopt;
        if (!at) {
          ShelfPacker fresh(open_px[k], kBoxGutterPx);
          at = fresh.place(sizes);
          if (!at) continue;  // too large for this size
          packer = fresh;
          tile = uint32_t(t.page_of_tile.size());
          t.page_of_tile.push_back(p);
          t.tile_px.push_back(open_px[k]);
          of_tile.emplace_back();
        }
        box.page = tile;
        for (size_t i = 0; i < sides.size(); ++i) {
          box.sides[sides[i]].x = uint16_t((*at)[i].x);
          box.sides[sides[i]].y = uint16_t((*at)[i].y);
        }
        of_tile[tile].push_back(b);
        placed = true;
      }
      // A box that fits no tile as they are packed (it fitted its page as the bake packed
      // it): the pages themselves.
      if (!placed) return tile_boxes(set, 0);
    }
  }
  for (const std::vector<uint32_t>& boxes : of_tile) {
    t.tile_first.push_back(uint32_t(t.boxes_by_tile.size()));
    t.boxes_by_tile.insert(t.boxes_by_tile.end(), boxes.begin(), boxes.end());
  }
  t.tile_first.push_back(uint32_t(t.boxes_by_tile.size()));
  t.tiles.page_count = uint32_t(t.page_of_tile.size());
  return t;
}

std::vector<uint8_t> cut_tile(const BoxSet& set, const BoxTiling& tiling, uint32_t tile,
                              std::span<const uint8_t> page) {
  const size_t px = size_t(tiling.tile_px[tile]), page_px = size_t(set.page_px);
  std::vector<uint8_t> out(px * px * 4, 0);
  for (uint32_t b : tiling.boxes_of(tile)) {
    const TexturedBox &from = set.boxes[b], &to = tiling.tiles.boxes[b];
    for (int side = 0; side < 6; ++side) {
      const BoxSide &f = from.sides[side], &t = to.sides[side];
      for (size_t y = 0; y < f.h; ++y)
        std::copy_n(&page[((f.y + y) * page_px + f.x) * 4], size_t(f.w) * 4,
                    &out[((t.y + y) * px + t.x) * 4]);
    }
  }
  return out;
}

namespace {

struct CutTile {
  uint32_t tile = 0;
  std::string error;  // empty: cut
  std::shared_ptr<const std::vector<uint8_t>> pixels;
  std::shared_ptr<const TexturedMesh> mesh;
  std::vector<uint32_t> first, count;  // parallel to the tile's boxes
  uint64_t bytes() const {
    return pixels ? pixels->size() + mesh->vertices.size() * sizeof(TexturedVertex) +
                        mesh->indices.size() * sizeof(uint32_t)
                  : 0;
  }
};

CutTile mesh_of(const BoxTiling& tiling, uint32_t tile) {
  CutTile out;
  out.tile = tile;
  const std::span<const uint32_t> boxes = tiling.boxes_of(tile);
  out.first.resize(boxes.size());
  out.count.resize(boxes.size());
  out.mesh = std::make_shared<const TexturedMesh>(
      box_mesh(tiling.tiles, boxes, out.first, out.count, tiling.tile_px[tile]));
  return out;
}

}  // namespace

struct BoxAtlas::Loader {
  Loader(const BoxSet& b, const BoxTiling& t, std::string p)
      : boxes(b), tiling(t), pack(std::move(p)) {}
  const BoxSet& boxes;
  const BoxTiling& tiling;
  std::string pack;
  std::optional<Store> store;  // opened on the loader thread (a Store is one connection)
  // The pages last read, kept for their next tiles (the frames ask for the nearest tiles,
  // which lie on a few pages), in buffers read into again: 16 MB in fresh memory cost
  // 60 ms of page faults here, at the frames' expense.
  struct Page {
    uint32_t page = UINT32_MAX;
    uint64_t used = 0;
    std::vector<uint8_t> pixels;
  };
  std::array<Page, 2> pages;
  uint64_t uses = 0;

  std::mutex mutex;
  std::condition_variable wake, idle;
  std::vector<uint32_t> queue;  // first asked first
  std::optional<uint32_t> in_flight;
  std::vector<CutTile> done;
  bool stop = false;
  std::thread thread;

  bool holds(uint32_t page) const {
    return std::any_of(pages.begin(), pages.end(), [&](const Page& p) { return p.page == page; });
  }

  CutTile cut(uint32_t tile) {
    const uint32_t wanted = tiling.page_of_tile[tile];
    auto in_hand =
        std::find_if(pages.begin(), pages.end(), [&](const Page& p) { return p.page == wanted; });
    if (in_hand == pages.end()) {
      in_hand = std::min_element(pages.begin(), pages.end(),
                                 [](const Page& a, const Page& b) { return a.used < b.used; });
      in_hand->page = UINT32_MAX;
      if (!store) {
        auto opened = Store::open(pack, Store::Mode::kRead);
        if (!opened) return {tile, opened.error().message, {}, {}, {}, {}};
        store.emplace(std::move(*opened));
      }
      if (auto read = read_box_page(*store, boxes, wanted, in_hand->pixels); !read)
        return {tile, read.error().message, {}, {}, {}, {}};
      in_hand->page = wanted;
    }
    in_hand->used = ++uses;
    CutTile out = mesh_of(tiling, tile);
    out.pixels = std::make_shared<const std::vector<uint8_t>>(
        cut_tile(boxes, tiling, tile, in_hand->pixels));
    return out;
  }

  void run() {
    run_below_other_threads();  // reading and cutting must not lengthen frames
    std::unique_lock lock(mutex);
    for (;;) {
      wake.wait(lock, [&] { return stop || (!queue.empty() && done.size() < kReadAhead); });
      if (stop) return;
      // The tiles of the pages in hand first, then the first asked.
      auto next = std::find_if(queue.begin(), queue.end(),
                               [&](uint32_t t) { return holds(tiling.page_of_tile[t]); });
      if (next == queue.end()) next = queue.begin();
      const uint32_t tile = *next;
      queue.erase(next);
      in_flight = tile;
      lock.unlock();
      CutTile item = cut(tile);
      lock.lock();
      in_flight.reset();
      done.push_back(std::move(item));
      idle.notify_all();
    }
  }
};

BoxAtlas::BoxAtlas(const BoxSet& boxes, gpu::OwnedResources& resources, int tile_px)
    : tiling_(tile_boxes(boxes, tile_px)) {
  for (uint32_t t = 0; t < tiles(); ++t) textures_.push_back(resources.texture());
  drawable_.assign(tiles(), 0);
  asked_.assign(tiles(), 0);
  first_.assign(boxes.boxes.size(), 0);
  count_.assign(boxes.boxes.size(), 0);
}

BoxAtlas::~BoxAtlas() {
  if (!loader_) return;
  {
    std::lock_guard lock(loader_->mutex);
    loader_->stop = true;
  }
  loader_->wake.notify_all();
  loader_->thread.join();
}

Result<std::unique_ptr<BoxAtlas>> BoxAtlas::create(BoxSet& boxes, gpu::OwnedResources& resources,
                                                   int tile_px) {
  FF_ASSERT(boxes.pages.size() == boxes.page_count, "%zu box pages of %u", boxes.pages.size(),
            boxes.page_count);
  std::unique_ptr<BoxAtlas> a(new BoxAtlas(boxes, resources, tile_px));
  auto billboards = resources.textured_mesh({}, {});
  if (!billboards) return billboards.error();
  a->billboards_ = *billboards;
  for (uint32_t t = 0; t < a->tiles(); ++t) {
    const int px = a->tiling_.tile_px[t];
    CutTile cut = mesh_of(a->tiling_, t);
    auto mesh = resources.textured_mesh(cut.mesh->vertices, cut.mesh->indices);
    if (!mesh) return mesh.error();
    a->meshes_.push_back(*mesh);
    const std::span<const uint32_t> of_tile = a->tiling_.boxes_of(t);
    for (size_t i = 0; i < of_tile.size(); ++i) {
      a->first_[of_tile[i]] = cut.first[i];
      a->count_[of_tile[i]] = cut.count[i];
    }
    const uint32_t page = a->tiling_.page_of_tile[t];
    auto pixels = std::make_shared<std::vector<uint8_t>>(
        a->tiling_.whole_pages ? std::move(boxes.pages[page])
                               : cut_tile(boxes, a->tiling_, t, boxes.pages[page]));
    a->given_.push_back({a->textures_[t], px, px, 4, pixels->data(), pixels, true});
    // A page's tiles follow each other: let it go after its last.
    if (t + 1 == a->tiles() || a->tiling_.page_of_tile[t + 1] != page)
      boxes.pages[page] = std::vector<uint8_t>();
  }
  boxes.pages.clear();
  a->drawable_.assign(a->tiles(), 1);
  a->tiles_in_ = a->tiles();
  return a;
}

Result<std::unique_ptr<BoxAtlas>> BoxAtlas::create_streamed(const BoxSet& boxes,
                                                            gpu::OwnedResources& resources,
                                                            std::string pack,
                                                            uint64_t upload_bytes_per_frame,
                                                            int tile_px) {
  std::unique_ptr<BoxAtlas> a(new BoxAtlas(boxes, resources, tile_px));
  auto billboards = resources.textured_mesh({}, {});
  if (!billboards) return billboards.error();
  a->billboards_ = *billboards;
  for (uint32_t t = 0; t < a->tiles(); ++t) {
    auto mesh = resources.textured_mesh({}, {});
    if (!mesh) return mesh.error();
    a->meshes_.push_back(*mesh);
  }
  a->upload_bytes_per_frame_ = upload_bytes_per_frame;
  a->warm_up_ = resources.texture();
  a->loader_ = std::make_unique<Loader>(boxes, a->tiling_, std::move(pack));
  Loader* raw = a->loader_.get();
  a->loader_->thread = std::thread([raw] { raw->run(); });
  return a;
}

void BoxAtlas::want(uint32_t box, float priority, bool prefetch) {
  const uint32_t tile = tiling_.tiles.boxes[box].page;
  if (drawable_[tile] || asked_[tile]) return;
  (prefetch ? prefetches_ : wants_).push_back({priority, tile});
}

bool BoxAtlas::end_frame(DrawList& out) {
  if (!given_.empty()) {
    out.uploads.insert(out.uploads.end(), given_.begin(), given_.end());
    given_.clear();
    return true;
  }
  if (!loader_) return false;
  const bool warm_up = bool(warm_up_);
  if (warm_up) {
    // The renderer's first mipmapped upload builds its mipmap pass (on llvmpipe 90 ms of
    // shader compiling): made with the walk's first frame, not with a later one's tile.
    auto texels = std::make_shared<std::vector<uint8_t>>(4 * 4 * 4, 0);
    out.uploads.push_back({warm_up_, 4, 4, 4, texels->data(), texels, true});
    warm_up_ = {};
  }
  // This frame's asks, highest priority first, the prefetches after every want.
  auto by_priority = [](const auto& a, const auto& b) { return a.first > b.first; };
  std::stable_sort(wants_.begin(), wants_.end(), by_priority);
  std::stable_sort(prefetches_.begin(), prefetches_.end(), by_priority);
  std::vector<uint32_t> asks;
  for (const auto* list : {&wants_, &prefetches_})
    for (const auto& [priority, tile] : *list)
      if (!asked_[tile]) {
        asked_[tile] = 1;
        asks.push_back(tile);
      }
  wants_.clear();
  prefetches_.clear();
  std::vector<CutTile> taken;
  {
    std::lock_guard lock(loader_->mutex);
    loader_->queue.insert(loader_->queue.end(), asks.begin(), asks.end());
    // What was cut, in order, up to the frame's bytes (at least one).
    uint64_t bytes = 0;
    const size_t n =
        gpu::taken_in_a_frame(loader_->done, upload_bytes_per_frame_, take_all_, bytes);
    taken.assign(std::make_move_iterator(loader_->done.begin()),
                 std::make_move_iterator(loader_->done.begin() + std::ptrdiff_t(n)));
    loader_->done.erase(loader_->done.begin(), loader_->done.begin() + std::ptrdiff_t(n));
  }
  loader_->wake.notify_all();
  take_all_ = false;
  for (CutTile& cut : taken) {
    const int px = tiling_.tile_px[cut.tile];
    if (!cut.error.empty()) {
      if (failure_.empty()) failure_ = cut.error;
      continue;  // stays asked: never asked again, never drawable
    }
    bytes_read_ += cut.pixels->size();
    const std::span<const uint32_t> of_tile = tiling_.boxes_of(cut.tile);
    for (size_t i = 0; i < of_tile.size(); ++i) {
      first_[of_tile[i]] = cut.first[i];
      count_[of_tile[i]] = cut.count[i];
    }
    out.uploads.push_back({textures_[cut.tile], px, px, 4, cut.pixels->data(), cut.pixels, true});
    out.textured_mesh_uploads.push_back({meshes_[cut.tile], std::move(cut.mesh)});
    drawable_[cut.tile] = 1;
    ++tiles_in_;
  }
  return warm_up;
}

uint64_t BoxAtlas::ready_bytes() const {
  if (!loader_) return 0;
  std::lock_guard lock(loader_->mutex);
  uint64_t bytes = 0;
  gpu::taken_in_a_frame(loader_->done, upload_bytes_per_frame_, take_all_, bytes);
  return bytes;
}

void BoxAtlas::wait_for_loads(std::chrono::steady_clock::time_point until) {
  if (!loader_) return;
  std::unique_lock lock(loader_->mutex);
  auto idle = [&] {
    return !loader_->in_flight && (loader_->queue.empty() || loader_->done.size() >= kReadAhead);
  };
  if (until != std::chrono::steady_clock::time_point::max()) {
    loader_->idle.wait_until(lock, until, idle);  // what is cut then goes up at the frame's pace
    return;
  }
  loader_->idle.wait(lock, idle);
  take_all_ = true;
}

size_t BoxAtlas::add(std::vector<uint32_t>& chosen, DrawList& out) const {
  std::sort(chosen.begin(), chosen.end());
  const size_t first = out.meshes.size();
  for (uint32_t b : chosen) {
    const uint32_t tile = tiling_.tiles.boxes[b].page;
    FF_ASSERT(drawable_[tile], "box %u drawn before its tile %u is in", b, tile);
    const MeshHandle mesh = meshes_[tile];
    if (out.meshes.size() > first && out.meshes.back().mesh == mesh &&
        out.meshes.back().first_index + out.meshes.back().index_count == first_[b])
      out.meshes.back().index_count += count_[b];
    else
      out.meshes.push_back({mesh, first_[b], count_[b], textures_[tile]});
  }
  chosen.clear();
  size_t draws = 0;
  for (size_t b = first; b < out.meshes.size();) {
    size_t e = b;
    while (e < out.meshes.size() && out.meshes[e].mesh == out.meshes[b].mesh) ++e;
    draws += e - b > kMeshRangesPerCall ? 1 : e - b;
    b = e;
  }
  return draws;
}

size_t BoxAtlas::add_billboards(std::vector<uint32_t>& chosen, const glm::vec3& eye,
                                DrawList& out) {
  if (chosen.empty()) return 0;
  std::sort(chosen.begin(), chosen.end(), [&](uint32_t a, uint32_t b) {  // by tile
    const uint32_t ta = tiling_.tiles.boxes[a].page, tb = tiling_.tiles.boxes[b].page;
    return ta != tb ? ta < tb : a < b;
  });
  auto mesh = std::make_shared<TexturedMesh>();
  size_t draws = 0;
  for (size_t i = 0; i < chosen.size();) {
    const uint32_t tile = tiling_.tiles.boxes[chosen[i]].page;
    FF_ASSERT(drawable_[tile], "billboard %u drawn before its tile %u is in", chosen[i], tile);
    const uint32_t first = uint32_t(mesh->indices.size());
    for (; i < chosen.size() && tiling_.tiles.boxes[chosen[i]].page == tile; ++i)
      append_billboard(tiling_.tiles.boxes[chosen[i]], tiling_.tile_px[tile], eye, *mesh);
    const uint32_t count = uint32_t(mesh->indices.size()) - first;
    if (count == 0) continue;
    out.meshes.push_back({billboards_, first, count, textures_[tile]});
    ++draws;
  }
  chosen.clear();
  if (draws > 0) out.textured_mesh_uploads.push_back({billboards_, std::move(mesh)});
  return draws;
}

}  // namespace farfield
