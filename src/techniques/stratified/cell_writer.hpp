// The stratified bake's writer thread: encodes and stores baked viewcells in order, one
// transaction each, while the GL thread renders the next ones (paper 000, Sec. 3.1; both
// cores busy). With delta coding (Sec. 3.1.4) it keeps each group's reference viewcell.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "farfield/store/store.hpp"
#include "farfield/techniques/stratified/stratified_pack.hpp"

namespace farfield::stratified {

struct CellJob {
  int shell;
  CellKey key;
  CellRecord record;
};

class CellWriter {
 public:
  // `store` and `params` must outlive the writer; nothing else may use `store` meanwhile.
  CellWriter(Store& store, const BakeParams& params, uint32_t object_count);
  ~CellWriter() { finish(); }

  // Waits while two viewcells are already queued (memory stays bounded).
  void push(CellJob job);
  // Writes what is queued and stops the thread.
  void finish();
  std::string error();  // the first write error, naming the pack; empty if none
  uint64_t written();   // viewcells committed

 private:
  void run();
  Result<void> write(const CellJob& job);
  using References = std::map<std::pair<int, uint64_t>, std::pair<CellKey, CellRecord>>;
  References::iterator remember(const std::pair<int, uint64_t>& group, const CellKey& key,
                                const CellRecord& record);

  Store& store_;
  const BakeParams& params_;
  uint32_t object_count_;
  References references_;  // delta coding: (shell, group) -> its reference viewcell
  std::mutex mutex_;
  std::condition_variable work_, space_;
  std::deque<CellJob> queue_;
  std::string error_;
  uint64_t written_ = 0;
  bool done_ = false;
  std::thread thread_;  // last: starts once the members above exist
};

}  // namespace farfield::stratified
