// The bounded pool streamed geometry goes through (gpu/mesh_pool.hpp), on a device without a
// GPU: loads by priority, the budget held by evicting the least recently wanted, failures kept.
#include "farfield/gpu/mesh_pool.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <thread>

namespace farfield::gpu {
namespace {

// An item of `vertices` vertices (20 bytes each) and one triangle.
std::shared_ptr<const SceneMeshData> item(size_t vertices) {
  auto data = std::make_shared<SceneMeshData>();
  data->vertices.resize(vertices);
  data->indices = {0, 1, 2};
  return data;
}

struct Recorder {
  std::mutex mutex;
  std::vector<uint64_t> order;
  MeshPool::Loader loader(size_t vertices) {
    return [this, vertices](uint64_t key) -> Result<std::shared_ptr<const SceneMeshData>> {
      std::lock_guard lock(mutex);
      order.push_back(key);
      if (key == 99) return make_error("item 99: unreadable");
      return item(vertices);
    };
  }
};

// Wants `keys` until all are resident (or `rounds` pass); returns the uploads made.
size_t want_until_resident(MeshPool& pool, const std::vector<uint64_t>& keys, int rounds = 20) {
  size_t uploads = 0;
  for (int r = 0; r < rounds; ++r) {
    size_t resident = 0;
    for (uint64_t k : keys) resident += pool.want(k, float(k)).has_value();
    DrawList list;
    pool.end_frame(list);
    uploads += list.mesh_uploads.size();
    if (resident == keys.size()) return uploads;
    pool.wait_for_loads();
  }
  return uploads;
}

TEST(MeshPool, HoldsItsBudgetEvictingTheLeastRecentlyWanted) {
  MemoryDevice device;
  Recorder recorder;
  const uint64_t item_bytes = item(50)->byte_size();  // 1012 bytes
  auto pool = MeshPool::create(device, {4 * item_bytes + 10, 16}, recorder.loader(50));
  ASSERT_TRUE(pool) << pool.error().message;
  EXPECT_EQ(device.live_meshes(), 16u);
  MeshPool& p = **pool;
  EXPECT_EQ(want_until_resident(p, {1, 2}), 2u);
  EXPECT_EQ(want_until_resident(p, {2, 3}), 1u);
  EXPECT_EQ(p.counters().resident_items, 3u);
  EXPECT_EQ(want_until_resident(p, {4}), 1u);
  // A fifth item does not fit: the least recently wanted (1, last wanted before 2 and 3)
  // goes.
  EXPECT_EQ(want_until_resident(p, {5}), 1u);
  EXPECT_EQ(p.counters().evictions, 1u);
  EXPECT_FALSE(p.want(1, 0).has_value()) << "item 1 was wanted longest ago";
  EXPECT_TRUE(p.want(2, 0).has_value());
  EXPECT_LE(p.counters().peak_resident_bytes, 4 * item_bytes + 10);
  EXPECT_EQ(p.counters().bytes_read, 5 * item_bytes);
  DrawList list;
  p.end_frame(list);
}

TEST(MeshPool, LoadsTheHighestPriorityFirstAndKeepsFailures) {
  MemoryDevice device;
  Recorder recorder;
  auto pool = MeshPool::create(device, {1 << 20, 64}, recorder.loader(10));
  ASSERT_TRUE(pool);
  MeshPool& p = **pool;
  for (uint64_t k : {3, 9, 1, 7}) EXPECT_FALSE(p.want(k, float(k)).has_value());
  DrawList list;
  EXPECT_EQ(p.end_frame(list), 4u);
  p.wait_for_loads();
  {
    std::lock_guard lock(recorder.mutex);
    ASSERT_EQ(recorder.order.size(), 4u);
    // The loader may have taken the first before the others were queued behind it: after the
    // first, highest priority first.
    EXPECT_EQ(std::vector<uint64_t>(recorder.order.begin(), recorder.order.end()),
              (std::vector<uint64_t>{9, 7, 3, 1}));
  }
  // The four loaded are taken in; 99 fails.
  EXPECT_EQ(want_until_resident(p, {99, 9}, 3), 4u);
  EXPECT_NE(p.failure().find("item 99: unreadable"), std::string::npos) << p.failure();
  const size_t loads = recorder.order.size();
  want_until_resident(p, {99}, 3);
  EXPECT_EQ(recorder.order.size(), loads) << "a failed item is not asked for again";
}

TEST(MeshPool, WhatNoLongerWantedIsNotLoaded) {
  MemoryDevice device;
  Recorder recorder;
  // A read-ahead of one item: the loader stops after the first until end_frame takes it.
  const uint64_t item_bytes = item(10)->byte_size();
  auto pool = MeshPool::create(device, {16 * item_bytes - 1, 64}, recorder.loader(10));
  ASSERT_TRUE(pool);
  MeshPool& p = **pool;
  for (uint64_t k = 1; k <= 5; ++k) p.want(k, float(k));
  DrawList list;
  p.end_frame(list);
  p.wait_for_loads();
  // The next frame wants other items: 1 to 4 are no longer asked for.
  for (uint64_t k = 11; k <= 12; ++k) p.want(k, float(k));
  p.end_frame(list);
  p.wait_for_loads();
  p.end_frame(list);
  p.wait_for_loads();
  std::lock_guard lock(recorder.mutex);
  for (uint64_t k : recorder.order) EXPECT_TRUE(k == 5 || k == 11 || k == 12) << k;
}

// A frame takes in at most its upload bytes of what was loaded (at least one item), the rest
// in the next frames; after wait_for_loads, everything.
TEST(MeshPool, TakesInAFramesUploadBytesAtMost) {
  MemoryDevice device;
  Recorder recorder;
  const uint64_t item_bytes = item(10)->byte_size();
  MeshPoolOptions options{1 << 20, 64, 2 * item_bytes + 1};
  auto pool = MeshPool::create(device, options, recorder.loader(10));
  ASSERT_TRUE(pool);
  MeshPool& p = **pool;
  auto want_all = [&] {
    for (uint64_t k = 1; k <= 5; ++k) p.want(k, float(k));
  };
  want_all();
  DrawList list;
  p.end_frame(list);
  // Wait for the loader to finish, without taking everything in at the next frame.
  for (int i = 0; i < 1000; ++i) {
    {
      std::lock_guard lock(recorder.mutex);
      if (recorder.order.size() == 5) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  std::vector<size_t> taken;
  for (int frame = 0; frame < 3; ++frame) {
    want_all();
    list.clear();
    p.end_frame(list);
    taken.push_back(list.mesh_uploads.size());
  }
  EXPECT_EQ(taken, (std::vector<size_t>{2, 2, 1}));

  // One item over the bound is still taken in, alone; after wait_for_loads, all at once.
  MeshPoolOptions tight{1 << 20, 64, 1};
  auto second = MeshPool::create(device, tight, recorder.loader(10));
  ASSERT_TRUE(second);
  for (uint64_t k = 21; k <= 24; ++k) (*second)->want(k, float(k));
  list.clear();
  (*second)->end_frame(list);
  (*second)->wait_for_loads();
  list.clear();
  (*second)->end_frame(list);
  EXPECT_EQ(list.mesh_uploads.size(), 4u);
}

}  // namespace
}  // namespace farfield::gpu
