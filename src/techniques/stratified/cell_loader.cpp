#include "cell_loader.hpp"

#include <algorithm>

namespace farfield::stratified {

Result<std::unique_ptr<CellLoader>> CellLoader::start(const std::string& pack,
                                                      const BakeParams& params,
                                                      uint32_t object_count, size_t cache_cells) {
  auto store = Store::open(pack, Store::Mode::kRead);
  if (!store) return store.error();
  std::unique_ptr<CellLoader> loader(
      new CellLoader(std::move(*store), params, object_count, cache_cells));
  loader->thread_ = std::thread([l = loader.get()] { l->run(); });
  return loader;
}

CellLoader::CellLoader(Store store, const BakeParams& params, uint32_t object_count,
                       size_t cache_cells)
    : store_(std::move(store)),
      params_(params),
      object_count_(object_count),
      cache_cells_(std::max<size_t>(cache_cells, 2)) {}

CellLoader::~CellLoader() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::shared_ptr<const CellRecord> CellLoader::cached(const CellId& id) {
  for (auto it = cache_.begin(); it != cache_.end(); ++it)
    if (it->first == id) {
      cache_.splice(cache_.begin(), cache_, it);  // most recently used first
      return cache_.front().second;
    }
  return nullptr;
}

void CellLoader::prefetch(const CellId& id) {
  {
    std::lock_guard lock(mutex_);
    if (cached(id) || loading_ == id ||
        std::find(queue_.begin(), queue_.end(), id) != queue_.end() ||
        std::find(failed_.begin(), failed_.end(), id) != failed_.end())
      return;
    queue_.push_back(id);
    // Requests further ahead than the cache holds would evict what is needed sooner.
    while (queue_.size() > cache_cells_ / 2) queue_.pop_front();
  }
  wake_.notify_one();
}

std::shared_ptr<const CellRecord> CellLoader::get(const CellId& id, bool* stalled) {
  std::unique_lock lock(mutex_);
  for (;;) {
    if (auto record = cached(id)) return record;
    if (stop_ || std::find(failed_.begin(), failed_.end(), id) != failed_.end()) return nullptr;
    if (stalled) *stalled = true;
    if (loading_ != id) {
      std::erase(queue_, id);
      queue_.push_front(id);
      wake_.notify_one();
    }
    loaded_.wait(lock, [&] {
      return stop_ ||
             (loading_ != id && std::find(queue_.begin(), queue_.end(), id) == queue_.end());
    });
  }
}

std::shared_ptr<const CellRecord> CellLoader::peek(const CellId& id) {
  std::lock_guard lock(mutex_);
  return cached(id);
}

std::string CellLoader::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

uint64_t CellLoader::loads() const {
  std::lock_guard lock(mutex_);
  return loads_;
}

void CellLoader::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return;
    const CellId id = queue_.front();
    queue_.pop_front();
    loading_ = id;
    lock.unlock();
    auto record = read_cell(store_, id.shell, id.key, params_, object_count_);
    lock.lock();
    loading_.reset();
    if (record) {
      ++loads_;
      cache_.emplace_front(id, std::make_shared<const CellRecord>(std::move(*record)));
      while (cache_.size() > cache_cells_) cache_.pop_back();
    } else {
      failed_.push_back(id);
      if (error_.empty()) error_ = record.error().message;
    }
    loaded_.notify_all();
  }
}

}  // namespace farfield::stratified
