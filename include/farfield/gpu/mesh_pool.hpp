// A bounded pool of scene meshes that streamed geometry goes through (issue 16: a walk of a
// scene larger than memory). Items (a scene's chunks; later a hierarchy's representations),
// named by 64-bit keys, are loaded on demand on a background thread by the caller's loader,
// and kept on the GPU while their bytes fit the budget; the least recently wanted go first.
//
// Each frame, on the thread that selects: want() every item the frame would draw (it answers
// with the item's mesh where it is resident: a frame never waits for the disk), then
// end_frame(), which asks the loader for the missing ones, highest priority first, then for
// those prefetched (what was not wanted or prefetched this frame is no longer asked for), takes in
// what it has loaded, evicting the least recently wanted items not wanted this frame to make room,
// and puts their uploads in the frame's DrawList (the renderer replaces a pool mesh's buffers with
// them before it draws), up to MeshPoolOptions::upload_bytes_per_frame; the rest wait for the next
// frames. An item taken in is drawn from the next frame on. A pool mesh is a scene mesh of the
// device, made once when the pool is made (on the GL thread): the walk makes no GL object.
//
// Memory: the budget bounds the meshes' bytes (on llvmpipe the GPU buffers are in system
// memory); the loaded data waits in memory only until its upload is drawn, and the loader
// stops reading ahead past a sixteenth of the budget.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/gpu/device.hpp"
#include "farfield/gpu/draw_list.hpp"

namespace farfield::gpu {

struct MeshPoolOptions {
  uint64_t budget_bytes = uint64_t(1) << 30;
  uint32_t meshes = 1024;  // the most items resident at once
  // Loaded bytes taken in by one end_frame, at most (at least one item; 0: no bound): each is
  // a copy into the GPU's buffers that the frame pays for, outside any selection's estimate
  // (on llvmpipe 64 MB taken in at once cost a 100M-city frame 50 ms more than predicted).
  uint64_t upload_bytes_per_frame = uint64_t(4) << 20;
};

// How many of `items` (loaded, in order; each with a bytes()) one frame takes in: up to `cap`
// bytes and at least one; all where `take_all` or `cap` is 0. `bytes`: theirs. The rule of the
// pool's end_frame, and of others that stream into a frame's uploads (the boxes' tiles).
template <class Item>
size_t taken_in_a_frame(const std::vector<Item>& items, uint64_t cap, bool take_all,
                        uint64_t& bytes) {
  bytes = 0;
  size_t n = 0;
  for (; n < items.size(); ++n) {
    if (n > 0 && !take_all && cap != 0 && bytes + items[n].bytes() > cap) break;
    bytes += items[n].bytes();
  }
  return n;
}

// Counters since the pool was made.
struct MeshPoolCounters {
  uint64_t hits = 0;        // wants answered with a resident mesh
  uint64_t misses = 0;      // wants of an item not resident
  uint64_t prefetches = 0;  // prefetches of an item not resident
  uint64_t bytes_read = 0;  // bytes the loader delivered
  uint64_t loads = 0, evictions = 0;
  uint64_t resident_bytes = 0, resident_items = 0;
  uint64_t peak_resident_bytes = 0;
};

class MeshPool {
 public:
  // Reads an item on the loader thread: its geometry, or an error that names it.
  using Loader = std::function<Result<std::shared_ptr<const SceneMeshData>>(uint64_t key)>;

  static Result<std::unique_ptr<MeshPool>> create(Device& device, const MeshPoolOptions& options,
                                                  Loader loader);
  ~MeshPool();  // stops the loader, frees the meshes
  MeshPool(const MeshPool&) = delete;
  MeshPool& operator=(const MeshPool&) = delete;

  // The item's mesh when resident; else it is asked for at end_frame with this priority
  // (higher first). Wanting a resident item keeps it from eviction this frame.
  std::optional<MeshHandle> want(uint64_t key, float priority);
  // Asks for an item the caller expects to want soon (the walk's predicted motion): where it
  // is not resident it is asked for at end_frame after every want of the frame, by this
  // priority; it counts as neither a hit nor a miss and keeps nothing from eviction.
  void prefetch(uint64_t key, float priority);
  // The item's mesh when resident (kept from eviction this frame, as by want), without
  // counting a hit or asking for it: a stand-in looked for where a wanted item is missing.
  std::optional<MeshHandle> peek(uint64_t key);
  // See above. Returns how many wants of this frame were missed.
  uint64_t end_frame(DrawList& out);
  // From the next end_frame on (the caller's share of a frame's time; see the option).
  void set_upload_bytes_per_frame(uint64_t bytes);
  // The bytes end_frame would take in were it called now (what the loader has done, up to
  // the frame's upload bytes): a frame's uploads, foreseen before it selects.
  uint64_t ready_bytes() const;
  // Waits until the loader has nothing left to load (tests, references): the next end_frame
  // takes in everything done that fits, however many bytes. With `until`, waits at most until
  // then, and the next end_frame takes in what the frame's upload bytes allow, as usual.
  void wait_for_loads(
      std::chrono::steady_clock::time_point until = std::chrono::steady_clock::time_point::max());

  const MeshPoolCounters& counters() const;
  // The first load that failed (its loader's message), or empty: such an item is never asked
  // for again, and the caller should report it.
  std::string failure() const;

 private:
  struct State;
  explicit MeshPool(std::unique_ptr<State> state);
  std::unique_ptr<State> s_;
};

}  // namespace farfield::gpu
