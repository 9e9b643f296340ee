// The clusters bake's kept work (bake_work.hpp): batches read back instead of redone, another
// plan's work erased, damaged batches refused by name.
#include "farfield/techniques/clusters/bake_work.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <numeric>

#include "farfield/store/store.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// Item i: one part of i + 1 triangles' worth of indices over three vertices.
PartList item(uint32_t i) {
  SimplifiedPart p;
  p.mesh.material = i % 3;
  p.error_m = 0.5f * float(i);
  p.mesh.vertices.resize(3);
  p.mesh.vertices[1].position.x = float(i);
  for (uint32_t k = 0; k <= i; ++k) p.mesh.indices.insert(p.mesh.indices.end(), {0, 1, 2});
  return {p};
}

TEST(BakeWork, KeptBatchesAreReadInsteadOfRedone) {
  test::TempDir dir;
  auto store = Store::open(dir.file("p.ffpack"), Store::Mode::kReadWrite);
  ASSERT_TRUE(store);
  Progress quiet(true);
  std::vector<uint32_t> order(50);
  std::iota(order.rbegin(), order.rend(), 0u);  // the last item first
  std::atomic<int> calls{0};
  auto work = [&](uint32_t i) {
    ++calls;
    return item(i);
  };
  auto run = [&](const std::string& plan) {
    auto w = BakeWork::open(&*store, "test", plan);
    EXPECT_TRUE(w);
    return w->run("test", "items", 50, order, 8, 2, quiet, work);
  };
  auto first = run("plan A");
  ASSERT_TRUE(first) << first.error().message;
  EXPECT_EQ(calls.load(), 50);
  for (uint32_t i = 0; i < 50; ++i) {
    ASSERT_EQ((*first)[i].size(), 1u);
    EXPECT_EQ((*first)[i][0].mesh.indices.size(), 3u * (i + 1));
  }
  EXPECT_EQ(store->list("clusters/work/test/0")->size(), 7u);  // ceil(50 / 8) batches

  calls = 0;
  auto again = run("plan A");
  ASSERT_TRUE(again);
  EXPECT_EQ(calls.load(), 0);
  for (uint32_t i = 0; i < 50; ++i) {
    EXPECT_EQ((*again)[i][0].mesh.indices, (*first)[i][0].mesh.indices);
    EXPECT_EQ((*again)[i][0].error_m, (*first)[i][0].error_m);
    EXPECT_EQ((*again)[i][0].mesh.material, (*first)[i][0].mesh.material);
  }
  ASSERT_TRUE(store->erase("clusters/work/test/000002"));  // a batch the kill lost
  calls = 0;
  ASSERT_TRUE(run("plan A"));
  EXPECT_EQ(calls.load(), 8);

  // A damaged batch is named.
  const std::vector<std::byte> junk(10, std::byte{7});
  ASSERT_TRUE(store->put("clusters/work/test/000003", junk));
  auto damaged = run("plan A");
  ASSERT_FALSE(damaged);
  EXPECT_NE(damaged.error().message.find("clusters/work/test/000003"), std::string::npos)
      << damaged.error().message;
  EXPECT_NE(damaged.error().message.find("p.ffpack"), std::string::npos);

  // Another plan starts afresh.
  calls = 0;
  ASSERT_TRUE(run("plan B"));
  EXPECT_EQ(calls.load(), 50);
  // Without a store nothing is kept, and all is done.
  auto none = BakeWork::open(nullptr, "test", "plan B");
  ASSERT_TRUE(none);
  calls = 0;
  ASSERT_TRUE(none->run("test", "items", 50, order, 8, 1, quiet, work));
  EXPECT_EQ(calls.load(), 50);
}

TEST(BakeWork, DecodingRefusesWhatIsNotABatch) {
  const PartList a = item(4), b = item(0);
  const std::vector<std::byte> bytes = encode_parts({&a, &b});
  auto back = decode_parts(bytes, 2, "batch");
  ASSERT_TRUE(back);
  EXPECT_EQ((*back)[0][0].mesh.indices, a[0].mesh.indices);
  EXPECT_FALSE(decode_parts(bytes, 3, "batch"));  // fewer items than asked
  EXPECT_FALSE(decode_parts(bytes, 1, "batch"));  // bytes past the last item
  std::vector<std::byte> truncated(bytes.begin(), bytes.end() - 4);
  auto refused = decode_parts(truncated, 2, "batch X");
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("batch X"), std::string::npos);
  PartList bad = item(1);
  bad[0].mesh.indices[4] = 3;  // past its three vertices
  EXPECT_FALSE(decode_parts(encode_parts({&bad}), 1, "batch"));
}

}  // namespace
}  // namespace farfield
