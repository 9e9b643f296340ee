#include "farfield/techniques/clusters/bake_work.hpp"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>

#include "farfield/core/mpi_world.hpp"
#include "farfield/core/parallel.hpp"
#include "farfield/core/text.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

namespace {

constexpr const char* kWork = "clusters/work/";

template <class T>
void append(std::vector<std::byte>& out, const T* data, size_t count) {
  const auto* p = reinterpret_cast<const std::byte*>(data);
  out.insert(out.end(), p, p + count * sizeof(T));
}

// Reads from a batch's bytes, failing (not reading past the end) once they run out.
class Reader {
 public:
  explicit Reader(std::span<const std::byte> bytes) : bytes_(bytes) {}
  template <class T>
  bool read(T* out, size_t count) {
    if (count > (bytes_.size() - at_) / sizeof(T)) return false;
    if (count > 0) std::memcpy(out, bytes_.data() + at_, count * sizeof(T));
    at_ += count * sizeof(T);
    return true;
  }
  bool done() const { return at_ == bytes_.size(); }

 private:
  std::span<const std::byte> bytes_;
  size_t at_ = 0;
};

}  // namespace

PartSizes sizes_of(const std::vector<PartList>& items) {
  PartSizes sizes;
  for (const PartList& item : items)
    for (const SimplifiedPart& p : item) {
      sizes.vertices += p.mesh.vertices.size();
      sizes.indices += p.mesh.indices.size();
    }
  return sizes;
}

// Per item: its part count, then per part: material, error, sloppy, vertex and index counts,
// whether it has texture coordinates, then its vertices, texture coordinates and indices.
std::vector<std::byte> encode_parts(const std::vector<const PartList*>& items) {
  std::vector<std::byte> out;
  for (const PartList* item : items) {
    const uint32_t parts = uint32_t(item->size());
    append(out, &parts, 1);
    for (const SimplifiedPart& p : *item) {
      const uint32_t header[5] = {p.mesh.material, uint32_t(p.sloppy),
                                  uint32_t(p.mesh.vertices.size()), uint32_t(p.mesh.indices.size()),
                                  uint32_t(!p.mesh.uvs.empty())};
      append(out, header, 5);
      append(out, &p.error_m, 1);
      append(out, p.mesh.vertices.data(), p.mesh.vertices.size());
      append(out, p.mesh.uvs.data(), p.mesh.uvs.size());
      append(out, p.mesh.indices.data(), p.mesh.indices.size());
    }
  }
  return out;
}

Result<std::vector<PartList>> decode_parts(std::span<const std::byte> bytes, size_t items,
                                           const std::string& what) {
  auto bad = [&](const char* why) { return make_error(what, " is damaged (", why, ")"); };
  Reader in(bytes);
  std::vector<PartList> out(items);
  for (PartList& item : out) {
    uint32_t parts = 0;
    if (!in.read(&parts, 1)) return bad("it ends early");
    if (parts > bytes.size()) return bad("a part count past its size");
    item.resize(parts);
    for (SimplifiedPart& p : item) {
      uint32_t header[5];
      if (!in.read(header, 5) || !in.read(&p.error_m, 1)) return bad("it ends early");
      if (!(p.error_m >= 0.0f)) return bad("an error that is not a distance");
      const uint32_t vertices = header[2], indices = header[3];
      if (header[1] > 1 || header[4] > 1 || indices % 3 != 0) return bad("a part's header");
      if (vertices > bytes.size() / sizeof(Vertex) || indices > bytes.size() / 4)
        return bad("counts past its size");
      p.mesh.material = header[0];
      p.sloppy = header[1] != 0;
      p.mesh.vertices.resize(vertices);
      p.mesh.uvs.resize(header[4] ? vertices : 0);
      p.mesh.indices.resize(indices);
      if (!in.read(p.mesh.vertices.data(), vertices) ||
          !in.read(p.mesh.uvs.data(), p.mesh.uvs.size()) ||
          !in.read(p.mesh.indices.data(), indices))
        return bad("it ends early");
      for (uint32_t i : p.mesh.indices)
        if (i >= vertices) return bad("an index past its vertices");
    }
  }
  if (!in.done()) return bad("bytes past its last item");
  return out;
}

Result<BakeWork> BakeWork::open(Store* store, const std::string& task, const std::string& plan,
                                const BakeShards* shards) {
  const std::string prefix = std::string(kWork) + task + "/";
  if (!store) return BakeWork(nullptr, prefix, nullptr);
  if (shards && shards->size <= 1) shards = nullptr;
  const std::string plan_name = prefix + "plan";
  auto kept = store->contains(plan_name);
  if (!kept) return kept.error();
  if (*kept) {
    auto bytes = store->get(plan_name);
    if (!bytes) return bytes.error();
    const std::string text(reinterpret_cast<const char*>(bytes->data()), bytes->size());
    if (text == plan) return BakeWork(store, prefix, shards);
  }
  // Another bake's work, or none: start afresh.
  auto transaction = store->begin();
  if (!transaction) return transaction.error();
  if (auto erased = store->erase(prefix); !erased) return erased.error();
  if (auto ok = store->put(plan_name, std::as_bytes(std::span(plan.data(), plan.size()))); !ok)
    return ok.error();
  if (auto ok = transaction->commit(); !ok) return ok.error();
  return BakeWork(store, prefix, shards);
}

Result<std::vector<PartList>> BakeWork::run(const std::string& label, const std::string& noun,
                                            size_t count, const std::vector<uint32_t>& order,
                                            size_t batch, int threads, Progress& progress,
                                            const std::function<PartList(uint32_t)>& work,
                                            size_t rank0_batches) {
  std::vector<PartList> results(count);
  const size_t batches = (count + batch - 1) / batch;
  // Batches already kept are read; the positions (into `order`) of the others' items are done.
  std::vector<size_t> todo;
  std::unique_ptr<std::atomic<uint32_t>[]> left(new std::atomic<uint32_t>[batches]);
  std::vector<bool> saved(batches, false);
  size_t kept_items = 0;  // read from the store
  for (size_t b = 0; b < batches; ++b) {
    const size_t first = b * batch, end = std::min(count, first + batch);
    left[b].store(uint32_t(end - first));
    if (store_) {
      const std::string name = formatted("%s%06zu", prefix_.c_str(), b);
      auto kept = store_->contains(name);
      if (!kept) return kept.error();
      if (*kept) {
        auto bytes = store_->get(name);
        if (!bytes) return bytes.error();
        auto items = decode_parts(*bytes, end - first,
                                  store_->path() + ": clusters bake work '" + name + "'");
        if (!items) return items.error();
        for (size_t k = first; k < end; ++k) results[order[k]] = std::move((*items)[k - first]);
        saved[b] = true;
        kept_items += end - first;
        continue;
      }
    }
    if (shards_ && !(b < rank0_batches ? shards_->rank == 0 : shards_->mine(b)))
      continue;  // another rank's
    for (size_t k = first; k < end; ++k) todo.push_back(k);
  }
  if (kept_items > 0)
    std::fprintf(stderr, "clusters: %s%zu of %zu %s already kept in the %s; continuing\n",
                 shards_ ? formatted("rank %d: ", shards_->rank).c_str() : "", kept_items, count,
                 noun.c_str(), shards_ && shards_->rank != 0 ? "shard" : "pack");
  std::optional<Error> failed;
  auto save_finished = [&]() -> bool {
    if (!store_) return true;
    for (size_t b = 0; b < batches; ++b) {
      if (saved[b] || left[b].load() != 0) continue;
      const size_t first = b * batch, end = std::min(count, first + batch);
      std::vector<const PartList*> items;
      for (size_t k = first; k < end; ++k) items.push_back(&results[order[k]]);
      const std::vector<std::byte> bytes = encode_parts(items);
      if (auto ok = store_->put(formatted("%s%06zu", prefix_.c_str(), b), bytes); !ok) {
        failed = ok.error();
        return false;
      }
      saved[b] = true;
    }
    return true;
  };
  parallel_for(
      todo.size(), threads, progress, label,
      [&](size_t i) {
        const size_t k = todo[i];
        results[order[k]] = work(order[k]);
        left[k / batch].fetch_sub(1);
      },
      save_finished);
  if (failed) return *failed;
  if (shards_) {
    MpiWorld::get().barrier();  // every rank has kept its share
    if (shards_->rank == 0)
      if (auto ok = take_in_shards(batches, batch, count, order, saved, results); !ok)
        return ok.error();
  }
  return results;
}

// Rank 0: the batches not in the pack, from the shard of the rank that made them, copied into
// the pack (one transaction a shard) so that a run after this one finds them there.
Result<void> BakeWork::take_in_shards(size_t batches, size_t batch, size_t count,
                                      const std::vector<uint32_t>& order,
                                      std::vector<bool>& saved, std::vector<PartList>& results) {
  for (int r = 1; r < shards_->size; ++r) {
    const std::string path = shards_->shard(r);
    std::optional<Store> shard;
    auto transaction = store_->begin();
    if (!transaction) return transaction.error();
    for (size_t b = r; b < batches; b += size_t(shards_->size)) {
      if (saved[b]) continue;
      if (!shard) {
        auto opened = Store::open(path, Store::Mode::kRead);
        if (!opened) return make_error("rank ", std::to_string(r), "'s share: ", opened.error().message);
        shard.emplace(std::move(*opened));
      }
      const std::string name = formatted("%s%06zu", prefix_.c_str(), b);
      auto bytes = shard->get(name);
      if (!bytes)
        return make_error("rank ", std::to_string(r), "'s share: ", bytes.error().message);
      const size_t first = b * batch, end = std::min(count, first + batch);
      auto items = decode_parts(*bytes, end - first, path + ": clusters bake work '" + name + "'");
      if (!items) return items.error();
      if (auto ok = store_->put(name, *bytes); !ok) return ok;
      for (size_t k = first; k < end; ++k) results[order[k]] = std::move((*items)[k - first]);
      saved[b] = true;
    }
    if (auto ok = transaction->commit(); !ok) return ok;
  }
  return {};
}

Result<void> BakeWork::erase() {
  if (!store_) return {};
  auto erased = store_->erase(prefix_);
  if (!erased) return erased.error();
  return {};
}

}  // namespace farfield
