// Loads baked viewcells from the pack on a background thread (paper 000, Sec. 3.2.1: prefetch
// from the viewpoint's velocity so that a crossing finds its textures ready). The thread has
// its own Store connection; decoded viewcells wait in a small cache, most recently used kept.
#pragma once

#include <condition_variable>
#include <deque>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "farfield/store/store.hpp"
#include "farfield/techniques/stratified/stratified_pack.hpp"

namespace farfield::stratified {

struct CellId {
  int shell;
  CellKey key;
  bool operator==(const CellId&) const = default;
};

class CellLoader {
 public:
  // Opens `pack` read-only for the thread; fails naming the pack.
  static Result<std::unique_ptr<CellLoader>> start(const std::string& pack,
                                                   const BakeParams& params,
                                                   uint32_t object_count, size_t cache_cells);
  ~CellLoader();

  // Asks for a viewcell in the background (ignored when cached or queued).
  void prefetch(const CellId& id);
  // The viewcell now: from the cache, or loaded at the front of the queue while the caller
  // waits (a stall). Null when it failed to load; error() then says why.
  std::shared_ptr<const CellRecord> get(const CellId& id, bool* stalled = nullptr);
  // The viewcell if it is in the cache now; never waits.
  std::shared_ptr<const CellRecord> peek(const CellId& id);
  // The first load error (a corrupted blob, ...), naming the pack and the blob; empty if none.
  std::string error() const;
  uint64_t loads() const;

 private:
  CellLoader(Store store, const BakeParams& params, uint32_t object_count, size_t cache_cells);
  void run();
  std::shared_ptr<const CellRecord> cached(const CellId& id);  // under mutex_

  Store store_;
  BakeParams params_;
  uint32_t object_count_;
  size_t cache_cells_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, loaded_;
  std::deque<CellId> queue_;
  std::optional<CellId> loading_;
  std::list<std::pair<CellId, std::shared_ptr<const CellRecord>>> cache_;  // front: newest
  std::list<CellId> failed_;
  std::string error_;
  uint64_t loads_ = 0;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace farfield::stratified
