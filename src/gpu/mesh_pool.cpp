#include "farfield/gpu/mesh_pool.hpp"

#include <algorithm>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "farfield/core/assert.hpp"
#include "farfield/core/parallel.hpp"

namespace farfield::gpu {

namespace {

constexpr uint64_t kNoFrame = UINT64_MAX;

struct Slot {
  MeshHandle mesh;
  uint64_t key = 0;
  uint64_t bytes = 0;
  uint64_t wanted = kNoFrame;  // the last frame that wanted it; kNoFrame: empty
};

struct Loaded {
  uint64_t key;
  Result<std::shared_ptr<const SceneMeshData>> data;
  uint64_t bytes() const { return data ? (*data)->byte_size() : 0; }
};

}  // namespace

struct MeshPool::State {
  State(Device& d, const MeshPoolOptions& o, Loader l)
      : device(d), options(o), loader(std::move(l)) {}
  Device& device;
  MeshPoolOptions options;
  Loader loader;
  std::vector<Slot> slots;
  std::unordered_map<uint64_t, uint32_t> resident;  // key -> slot
  std::unordered_set<uint64_t> failed;
  std::string failure;
  uint64_t frame = 0;
  std::vector<std::pair<float, uint64_t>> misses;  // this frame's, with their priorities
  std::vector<std::pair<float, uint64_t>> ahead;   // this frame's prefetches, likewise
  MeshPoolCounters counters;

  // Shared with the loader thread.
  std::mutex mutex;
  std::condition_variable wake, idle;
  std::vector<uint64_t> queue;  // highest priority last
  std::optional<uint64_t> in_flight;
  std::vector<Loaded> done;
  uint64_t done_bytes = 0;
  bool take_all = false;  // the next end_frame takes in all that is done (wait_for_loads)
  bool stop = false;
  std::thread thread;

  uint64_t read_ahead() const { return std::max<uint64_t>(options.budget_bytes / 16, 1); }

  void run() {
    run_below_other_threads();  // reading and decoding pages must not lengthen frames
    std::unique_lock lock(mutex);
    for (;;) {
      wake.wait(lock, [&] { return stop || (!queue.empty() && done_bytes < read_ahead()); });
      if (stop) return;
      const uint64_t key = queue.back();
      queue.pop_back();
      in_flight = key;
      lock.unlock();
      Loaded item{key, loader(key)};
      lock.lock();
      in_flight.reset();
      done_bytes += item.bytes();
      done.push_back(std::move(item));
      idle.notify_all();
    }
  }

  // A free slot, emptying the least recently wanted ones not wanted this frame until `bytes`
  // more fit the budget; none when they cannot.
  std::optional<uint32_t> make_room(uint64_t bytes) {
    if (bytes > options.budget_bytes) return std::nullopt;
    std::optional<uint32_t> free_slot;
    for (;;) {
      if (!free_slot)
        for (uint32_t i = 0; i < slots.size() && !free_slot; ++i)
          if (slots[i].wanted == kNoFrame) free_slot = i;
      if (free_slot && counters.resident_bytes + bytes <= options.budget_bytes) return free_slot;
      std::optional<uint32_t> oldest;
      for (uint32_t i = 0; i < slots.size(); ++i)
        if (slots[i].wanted != kNoFrame && slots[i].wanted < frame &&
            (!oldest || slots[i].wanted < slots[*oldest].wanted))
          oldest = i;
      if (!oldest) return std::nullopt;
      Slot& s = slots[*oldest];
      resident.erase(s.key);
      counters.resident_bytes -= s.bytes;
      --counters.resident_items;
      ++counters.evictions;
      s.wanted = kNoFrame;
      s.bytes = 0;
      // Its mesh keeps the old buffers until the slot's next upload replaces them.
    }
  }
};

MeshPool::MeshPool(std::unique_ptr<State> state) : s_(std::move(state)) {}

Result<std::unique_ptr<MeshPool>> MeshPool::create(Device& device, const MeshPoolOptions& options,
                                                   Loader loader) {
  FF_ASSERT(options.meshes > 0 && loader, "a mesh pool of %u meshes", options.meshes);
  auto s = std::make_unique<State>(device, options, std::move(loader));
  s->slots.resize(options.meshes);
  for (Slot& slot : s->slots) {
    auto mesh = device.create_scene_mesh({}, {}, {});
    if (!mesh) {
      for (Slot& made : s->slots)
        if (made.mesh) device.free(made.mesh);
      return mesh.error();
    }
    slot.mesh = *mesh;
  }
  State* raw = s.get();
  s->thread = std::thread([raw] { raw->run(); });
  return std::unique_ptr<MeshPool>(new MeshPool(std::move(s)));
}

MeshPool::~MeshPool() {
  {
    std::lock_guard lock(s_->mutex);
    s_->stop = true;
  }
  s_->wake.notify_all();
  s_->thread.join();
  for (Slot& slot : s_->slots) s_->device.free(slot.mesh);
}

std::optional<MeshHandle> MeshPool::want(uint64_t key, float priority) {
  State& s = *s_;
  if (auto it = s.resident.find(key); it != s.resident.end()) {
    ++s.counters.hits;
    s.slots[it->second].wanted = s.frame;
    return s.slots[it->second].mesh;
  }
  ++s.counters.misses;
  if (!s.failed.contains(key)) s.misses.push_back({priority, key});
  return std::nullopt;
}

void MeshPool::prefetch(uint64_t key, float priority) {
  State& s = *s_;
  if (s.resident.contains(key) || s.failed.contains(key)) return;
  ++s.counters.prefetches;
  s.ahead.push_back({priority, key});
}

std::optional<MeshHandle> MeshPool::peek(uint64_t key) {
  State& s = *s_;
  auto it = s.resident.find(key);
  if (it == s.resident.end()) return std::nullopt;
  s.slots[it->second].wanted = s.frame;
  return s.slots[it->second].mesh;
}

uint64_t MeshPool::end_frame(DrawList& out) {
  State& s = *s_;
  std::vector<Loaded> done;
  // Highest priority last (the loader takes from the back), the prefetches after every want;
  // one entry a key.
  auto by_priority = [](const auto& a, const auto& b) { return a.first > b.first; };
  std::stable_sort(s.misses.begin(), s.misses.end(), by_priority);
  std::stable_sort(s.ahead.begin(), s.ahead.end(), by_priority);
  std::unordered_set<uint64_t> asked;
  std::vector<uint64_t> queue;
  for (const auto* asks : {&s.misses, &s.ahead})
    for (const auto& [priority, key] : *asks)
      if (asked.insert(key).second) queue.push_back(key);
  const uint64_t missed = s.misses.size();
  s.misses.clear();
  s.ahead.clear();
  {
    std::lock_guard lock(s.mutex);
    // What was loaded, in the order it was, up to the frame's upload bytes.
    uint64_t taken = 0;
    const size_t n = taken_in_a_frame(s.done, s.options.upload_bytes_per_frame, s.take_all, taken);
    done.assign(std::make_move_iterator(s.done.begin()),
                std::make_move_iterator(s.done.begin() + std::ptrdiff_t(n)));
    s.done.erase(s.done.begin(), s.done.begin() + std::ptrdiff_t(n));
    s.done_bytes -= taken;
    s.take_all = false;
    auto loaded = [](const std::vector<Loaded>& items, uint64_t key) {
      return std::any_of(items.begin(), items.end(), [&](const Loaded& d) { return d.key == key; });
    };
    std::erase_if(queue, [&](uint64_t key) {
      return (s.in_flight && *s.in_flight == key) || loaded(done, key) || loaded(s.done, key);
    });
    std::reverse(queue.begin(), queue.end());
    s.queue = std::move(queue);
  }
  s.wake.notify_all();
  for (Loaded& item : done) {
    if (!item.data) {
      s.failed.insert(item.key);
      if (s.failure.empty()) s.failure = item.data.error().message;
      continue;
    }
    const uint64_t bytes = item.bytes();
    std::shared_ptr<const SceneMeshData> data = std::move(*item.data);
    ++s.counters.loads;
    s.counters.bytes_read += bytes;
    if (s.resident.contains(item.key)) continue;
    const std::optional<uint32_t> slot = s.make_room(bytes);
    if (!slot) continue;  // the frame wants more than the budget: asked for again if wanted
    Slot& to = s.slots[*slot];
    to.key = item.key;
    to.bytes = bytes;
    to.wanted = s.frame;
    s.resident[item.key] = *slot;
    s.counters.resident_bytes += bytes;
    ++s.counters.resident_items;
    s.counters.peak_resident_bytes =
        std::max(s.counters.peak_resident_bytes, s.counters.resident_bytes);
    out.mesh_uploads.push_back({to.mesh, std::move(data)});
  }
  ++s.frame;
  return missed;
}

void MeshPool::set_upload_bytes_per_frame(uint64_t bytes) {
  std::lock_guard lock(s_->mutex);
  s_->options.upload_bytes_per_frame = bytes;
}

uint64_t MeshPool::ready_bytes() const {
  State& s = *s_;
  std::lock_guard lock(s.mutex);
  uint64_t taken = 0;
  taken_in_a_frame(s.done, s.options.upload_bytes_per_frame, s.take_all, taken);
  return taken;
}

void MeshPool::wait_for_loads(std::chrono::steady_clock::time_point until) {
  State& s = *s_;
  std::unique_lock lock(s.mutex);
  auto idle = [&] { return !s.in_flight && (s.queue.empty() || s.done_bytes >= s.read_ahead()); };
  if (until != std::chrono::steady_clock::time_point::max()) {
    s.idle.wait_until(lock, until, idle);  // what is done then goes up at the frame's pace
    return;
  }
  s.idle.wait(lock, idle);
  s.take_all = true;
}

const MeshPoolCounters& MeshPool::counters() const {
  return s_->counters;
}

std::string MeshPool::failure() const {
  return s_->failure;
}

}  // namespace farfield::gpu
