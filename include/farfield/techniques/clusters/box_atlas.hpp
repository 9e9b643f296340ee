// The textured boxes' images on the GPU (box_set.hpp), in tiles: the bake's atlas pages
// (2048^2) are too coarse a unit to stream (on this machine a new 22 MB mipmapped texture
// costs a frame 80 ms of page faults, and a street walk of the 100M city wants boxes on 18 of
// its 25 pages), so each page's boxes are packed again, in their order (depth first over the
// hierarchy: neighbours together), into tiles of 512^2 (larger for a box whose sides do not
// fit one), each a texture of its own and a mesh of its boxes' sides. Two ways in:
// - given the pages' pixels (the scene in memory), every tile is made now and goes to the
//   renderer with the first frame (by default the tiles are then the pages themselves: with
//   everything resident, 512 tiles' 400 textures cost the 10M street at 33 ms a tenth of its
//   triangles and p99 1.23x the budget against 1.12x, and a copy of the pixels);
// - left in the pack (the scene on disk, issue 16), a tile is cut on a background thread once
//   a frame wants one of its boxes (the nearest first; the page read and decoded once for
//   the tiles asked of it in a row), and taken in with at most `upload_bytes_per_frame` a
//   frame, so that neither the walk's start nor any frame waits for them. A box is drawable
//   once its tile is in a frame's list; until then the walk stands in for it
//   (cluster_stream.hpp). Tiles once in stay for the walk.
// Both ways draw the same pixels for the same tiles (mipmapped by the renderer).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/gpu/device.hpp"
#include "farfield/gpu/draw_list.hpp"
#include "farfield/techniques/clusters/billboards.hpp"
#include "farfield/techniques/clusters/box_set.hpp"

namespace farfield {

// The boxes of `set` packed again into square tiles: `tiles` holds `set`'s boxes on pages that
// are the tiles (boxes[b].page: b's tile, its sides placed there; page_px: the usual tile's
// size; no pixels, no object or node index); tile t is tile_px[t] texels square and holds
// boxes[tile_first[t], tile_first[t + 1]) of `boxes_by_tile`, all of page page_of_tile[t] of `set`.
struct BoxTiling {
  BoxSet tiles;
  bool whole_pages = false;  // the tiles are the pages, each box where the bake put it
  std::vector<int> tile_px;
  std::vector<uint32_t> page_of_tile;
  std::vector<uint32_t> tile_first;
  std::vector<uint32_t> boxes_by_tile;
  std::span<const uint32_t> boxes_of(uint32_t tile) const {
    return std::span(boxes_by_tile)
        .subspan(tile_first[tile], tile_first[tile + 1] - tile_first[tile]);
  }
};
// Each page's boxes in their order into tiles of tile_px; a box too large for one (two 256^2
// sides with their gutters do not sit side by side in 512) into a tile of twice that or more.
// tile_px of 0 or of the pages' size or more, or a box that fits no tile: the pages themselves.
BoxTiling tile_boxes(const BoxSet& set, int tile_px);
// Tile t's pixels (RGBA8, rows from the top) from the pixels of its page.
std::vector<uint8_t> cut_tile(const BoxSet& set, const BoxTiling& tiling, uint32_t tile,
                              std::span<const uint8_t> page);

class BoxAtlas {
 public:
  // Every tile of `boxes` now, tiles of tile_px (tile_boxes; its pages' pixels are let go of).
  static Result<std::unique_ptr<BoxAtlas>> create(BoxSet& boxes, gpu::OwnedResources& resources,
                                                  int tile_px);
  // Tiles cut from the pages in the pack at `pack` (`boxes` loaded without pixels; it
  // outlives the atlas).
  static Result<std::unique_ptr<BoxAtlas>> create_streamed(const BoxSet& boxes,
                                                           gpu::OwnedResources& resources,
                                                           std::string pack,
                                                           uint64_t upload_bytes_per_frame,
                                                           int tile_px);
  ~BoxAtlas();  // stops the loader
  BoxAtlas(const BoxAtlas&) = delete;
  BoxAtlas& operator=(const BoxAtlas&) = delete;

  bool drawable(uint32_t box) const { return drawable_[tiling_.tiles.boxes[box].page] != 0; }
  // Asks for the tile of a box not drawable, this frame (higher priority first; prefetches
  // after every want). A tile asked for is cut once, whatever is asked later.
  void want(uint32_t box, float priority, bool prefetch = false);
  // Puts in the list the tiles the loader finished, up to the frame's bytes (every one after
  // wait_for_loads, or when they were given), and passes the loader this frame's asks.
  // Returns whether the frame pays a one-time cost (the tiles given all went in, or the
  // renderer's mipmap pass was built): a frame that times that, not its drawing.
  bool end_frame(DrawList& out);
  // The bytes end_frame would take in were it called now.
  uint64_t ready_bytes() const;
  void set_upload_bytes_per_frame(uint64_t bytes) { upload_bytes_per_frame_ = bytes; }
  // Waits until every tile asked for is cut: the next end_frame takes them all in. With
  // `until`, at most until then, and the next end_frame takes in what its upload bytes allow.
  void wait_for_loads(
      std::chrono::steady_clock::time_point until = std::chrono::steady_clock::time_point::max());
  // The chosen boxes as draws, neighbours in a tile one draw (`chosen` sorted, then cleared);
  // returns the draws the renderer will count for them.
  size_t add(std::vector<uint32_t>& chosen, DrawList& out) const;
  // The chosen boxes as billboards seen from `eye` (billboards.hpp): one mesh made for the
  // frame, a draw per tile (`chosen` sorted by tile, then cleared); returns the draws.
  size_t add_billboards(std::vector<uint32_t>& chosen, const glm::vec3& eye, DrawList& out);
  // The first page that could not be read, or empty: its tiles are never drawable.
  std::string failure() const { return failure_; }
  uint32_t tiles() const { return uint32_t(tiling_.page_of_tile.size()); }
  uint32_t tiles_in() const { return tiles_in_; }
  uint64_t bytes_read() const { return bytes_read_; }

 private:
  struct Loader;
  BoxAtlas(const BoxSet& boxes, gpu::OwnedResources& resources, int tile_px);

  BoxTiling tiling_;
  std::vector<MeshHandle> meshes_;       // per tile
  MeshHandle billboards_;                // this frame's billboards
  std::vector<TextureHandle> textures_;  // per tile
  std::vector<uint32_t> first_, count_;  // per box: its indices in its tile's mesh
  std::vector<uint8_t> drawable_;        // per tile
  std::vector<uint8_t> asked_;           // per tile: passed to the loader
  std::vector<std::pair<float, uint32_t>> wants_, prefetches_;  // this frame's, by tile
  std::vector<TextureUpload> given_;  // the tiles given, until the first frame
  std::unique_ptr<Loader> loader_;    // tiles left in the pack; else null
  TextureHandle warm_up_;             // uploaded with the first frame (see end_frame)
  uint64_t upload_bytes_per_frame_ = 0;
  bool take_all_ = false;
  uint32_t tiles_in_ = 0;
  uint64_t bytes_read_ = 0;
  std::string failure_;
};

}  // namespace farfield
