#include "cell_writer.hpp"

#include <optional>

namespace farfield::stratified {

CellWriter::CellWriter(Store& store, const BakeParams& params, uint32_t object_count)
    : store_(store), params_(params), object_count_(object_count), thread_([this] { run(); }) {}

void CellWriter::push(CellJob job) {
  std::unique_lock lock(mutex_);
  space_.wait(lock, [&] { return queue_.size() < 2 || !error_.empty(); });
  queue_.push_back(std::move(job));
  work_.notify_one();
}

void CellWriter::finish() {
  {
    std::lock_guard lock(mutex_);
    done_ = true;
  }
  work_.notify_one();
  if (thread_.joinable()) thread_.join();
}

std::string CellWriter::error() {
  std::lock_guard lock(mutex_);
  return error_;
}

uint64_t CellWriter::written() {
  std::lock_guard lock(mutex_);
  return written_;
}

void CellWriter::run() {
  for (;;) {
    CellJob job;
    {
      std::unique_lock lock(mutex_);
      work_.wait(lock, [&] { return done_ || !queue_.empty(); });
      if (queue_.empty() || !error_.empty()) return;
      job = std::move(queue_.front());
      queue_.pop_front();
    }
    space_.notify_one();
    auto ok = write(job);
    std::lock_guard lock(mutex_);
    if (!ok) {
      error_ = ok.error().message;
      space_.notify_all();
      return;
    }
    ++written_;
  }
}

// Delta coding (Sec. 3.1.4) groups 2 x 2 x 2 neighbouring viewcells: the first one baked is
// stored whole and the others as differences to it.
Result<void> CellWriter::write(const CellJob& job) {
  if (!params_.delta)
    return write_cell(store_, job.shell, job.key, job.record, params_, nullptr, std::nullopt);
  const CellKey group{{job.key.at[0] & ~1u, job.key.at[1] & ~1u, job.key.at[2] & ~1u}};
  const auto id = std::pair{job.shell, group.packed()};
  auto it = references_.find(id);
  if (it == references_.end()) {
    // A resumed bake may already hold the group's reference.
    std::optional<std::pair<CellKey, CellRecord>> found;
    for (uint32_t i = 0; i < 8 && !found; ++i) {
      const CellKey k{{group.at[0] + (i & 1), group.at[1] + (i >> 1 & 1), group.at[2] + (i >> 2)}};
      auto has = store_.contains(cell_prefix(job.shell, k) + "done");
      if (!has) return has.error();
      if (!*has) continue;
      auto r = read_cell(store_, job.shell, k, params_, object_count_);
      if (!r) return r.error();
      if (!r->reference) found.emplace(k, std::move(*r));
    }
    if (!found) {
      if (auto ok =
              write_cell(store_, job.shell, job.key, job.record, params_, nullptr, std::nullopt);
          !ok)
        return ok;
      remember(id, job.key, job.record);
      return {};
    }
    it = remember(id, found->first, found->second);
  }
  return write_cell(store_, job.shell, job.key, job.record, params_, &it->second.second,
                    it->second.first);
}

CellWriter::References::iterator CellWriter::remember(const std::pair<int, uint64_t>& group,
                                                      const CellKey& key,
                                                      const CellRecord& record) {
  if (references_.size() >= 16) references_.clear();  // kd order keeps groups together
  return references_.insert_or_assign(group, std::pair{key, record}).first;
}

}  // namespace farfield::stratified
