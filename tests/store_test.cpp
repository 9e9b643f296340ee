#include "farfield/store/store.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>

#include "farfield/eval/image_metrics.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/store/bake_record.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using test::TempDir;

std::vector<std::byte> bytes_of(std::string_view text) {
  const auto* p = reinterpret_cast<const std::byte*>(text.data());
  return {p, p + text.size()};
}

std::vector<std::byte> random_bytes(size_t size, uint32_t seed) {
  std::mt19937 random(seed);
  std::vector<std::byte> bytes(size);
  for (auto& b : bytes) b = std::byte(random() & 0xFF);
  return bytes;
}

Image gradient(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = image.pixel(x, y);
      p[0] = uint8_t(x * 255 / w);
      p[1] = uint8_t(y * 255 / h);
      p[2] = uint8_t((x + y) % 64 < 32 ? 60 : 200);
    }
  return image;
}

Store open_or_die(const std::string& path, Store::Mode mode) {
  auto store = Store::open(path, mode);
  if (!store) {
    std::fprintf(stderr, "%s\n", store.error().message.c_str());
    std::abort();
  }
  return std::move(store).value();
}

std::vector<std::string> names(const Result<std::vector<BlobInfo>>& blobs) {
  std::vector<std::string> out;
  if (!blobs) return {"error: " + blobs.error().message};
  for (const BlobInfo& b : *blobs) out.push_back(b.name);
  return out;
}

// Runs SQL on a file through SQLite directly, as another program would.
void run_sql(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* message = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message), SQLITE_OK)
      << (message ? message : "");
  sqlite3_free(message);
  sqlite3_close(db);
}

::testing::AssertionResult refused(const std::string& path, Store::Mode mode,
                                   const std::string& words) {
  auto store = Store::open(path, mode);
  if (store) return ::testing::AssertionFailure() << path << " opened";
  const std::string& m = store.error().message;
  if (m.find(path) == std::string::npos || m.find(words) == std::string::npos)
    return ::testing::AssertionFailure() << "message '" << m << "' lacks the path or '" << words
                                         << "'";
  return ::testing::AssertionSuccess() << m;
}

TEST(Store, BytesRoundTripWithBothCodecs) {
  TempDir dir;
  const std::string path = dir.file("a.ffpack");
  const auto noise = random_bytes(100000, 1);
  const std::vector<std::byte> zeros(1 << 20, std::byte{0});
  {
    Store store = open_or_die(path, Store::Mode::kReadWrite);
    ASSERT_TRUE(store.put("raw/noise", noise, Codec::kNone));
    ASSERT_TRUE(store.put("zstd/zeros", zeros, Codec::kZstd));
    ASSERT_TRUE(store.put("zstd/empty", {}, Codec::kZstd));
    ASSERT_TRUE(store.put("raw/empty", {}, Codec::kNone));
  }
  Store store = open_or_die(path, Store::Mode::kRead);
  EXPECT_EQ(store.get("raw/noise").value(), noise);
  EXPECT_EQ(store.get("zstd/zeros").value(), zeros);
  EXPECT_TRUE(store.get("zstd/empty").value().empty());
  EXPECT_TRUE(store.get("raw/empty").value().empty());
  const auto info = store.info("zstd/zeros").value();
  ASSERT_TRUE(info);
  EXPECT_EQ(info->codec, Codec::kZstd);
  EXPECT_EQ(info->raw_size, zeros.size());
  EXPECT_LT(info->stored_size, 1000u);

  auto missing = store.get("nope");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().message, path + ": no blob 'nope'");
  EXPECT_FALSE(store.contains("nope").value());
  EXPECT_TRUE(store.contains("raw/noise").value());
  EXPECT_FALSE(store.info("nope").value());
}

TEST(Store, ImagesRoundTripAsPngExactlyAndJpegWithinQuality) {
  TempDir dir;
  const std::string path = dir.file("a.ffpack");
  const Image image = gradient(160, 120);
  {
    Store store = open_or_die(path, Store::Mode::kReadWrite);
    ASSERT_TRUE(store.put_image("png", image, ImageCodec::png()));
    ASSERT_TRUE(store.put_image("jpeg", image, ImageCodec::jpeg(85)));
    ASSERT_TRUE(store.put("bytes", bytes_of("hello")));
  }
  Store store = open_or_die(path, Store::Mode::kRead);
  auto png = store.get_image("png");
  ASSERT_TRUE(png) << png.error().message;
  EXPECT_EQ(png->rgb, image.rgb);
  auto jpeg = store.get_image("jpeg");
  ASSERT_TRUE(jpeg) << jpeg.error().message;
  // Quality 85 subsamples chroma 4:2:0, which blurs the hard blue stripes of this image.
  EXPECT_GT(compare_images(image, *jpeg).psnr_db, 28.0);
  EXPECT_EQ(store.info("jpeg").value()->raw_size, image.rgb.size());
  EXPECT_LT(store.info("jpeg").value()->stored_size, image.rgb.size() / 5);

  // Each kind of blob is read with its own call.
  auto wrong = store.get("png");
  ASSERT_FALSE(wrong);
  EXPECT_NE(wrong.error().message.find("'png'"), std::string::npos) << wrong.error().message;
  EXPECT_NE(wrong.error().message.find("get_image"), std::string::npos);
  EXPECT_FALSE(store.get_image("bytes"));
}

TEST(Store, ListsSumsAndErasesByPrefix) {
  TempDir dir;
  Store store = open_or_die(dir.file("a.ffpack"), Store::Mode::kReadWrite);
  for (const char* name : {"octree/nodes", "stratified/cell/2/far", "stratified/cell/10/far",
                           "stratified/cells", "stratifiee", "z\xff\xff", "z\xff"})
    ASSERT_TRUE(store.put(name, bytes_of("0123456789"), Codec::kNone));
  using V = std::vector<std::string>;
  EXPECT_EQ(names(store.list("stratified/cell/")),
            (V{"stratified/cell/10/far", "stratified/cell/2/far"}));
  EXPECT_EQ(names(store.list("stratified/cell")),
            (V{"stratified/cell/10/far", "stratified/cell/2/far", "stratified/cells"}));
  EXPECT_EQ(names(store.list("z\xff")), (V{"z\xff", "z\xff\xff"}));
  EXPECT_EQ(store.list().value().size(), 7u);
  EXPECT_TRUE(store.list("nothing").value().empty());
  EXPECT_EQ(store.total_bytes("stratified/").value(), 30u);
  EXPECT_EQ(store.total_bytes().value(), 70u);

  EXPECT_EQ(store.erase("stratified/").value(), 3u);
  EXPECT_EQ(names(store.list()), (V{"octree/nodes", "stratifiee", "z\xff", "z\xff\xff"}));
  EXPECT_EQ(store.erase("").value(), 4u);
  EXPECT_TRUE(store.list().value().empty());
}

// Compacting gives the file back the room of erased blobs, keeps the rest, and does nothing
// where little is free; a read-only store refuses.
TEST(Store, CompactGivesBackTheRoomOfErasedBlobs) {
  TempDir dir;
  const std::string path = dir.file("a.ffpack");
  Store store = open_or_die(path, Store::Mode::kReadWrite);
  const std::vector<std::byte> kept = random_bytes(1 << 20, 1);
  ASSERT_TRUE(store.put("kept", kept, Codec::kNone));
  ASSERT_TRUE(store.put("work/0", random_bytes(4 << 20, 2), Codec::kNone));
  EXPECT_EQ(store.compact().value(), 0u) << "nothing free yet";
  const uint64_t before = std::filesystem::file_size(path);
  ASSERT_EQ(store.erase("work/").value(), 1u);
  EXPECT_EQ(std::filesystem::file_size(path), before) << "SQLite keeps the freed pages";
  const uint64_t given = store.compact().value();
  EXPECT_GE(given, uint64_t(4) << 20);
  EXPECT_LE(std::filesystem::file_size(path), before - given);
  EXPECT_EQ(store.get("kept").value(), kept);
  EXPECT_TRUE(store.verify());
  Store reader = open_or_die(path, Store::Mode::kRead);
  EXPECT_FALSE(reader.compact());
}

TEST(Store, MetaIsKeptAndListedByPrefix) {
  TempDir dir;
  const std::string path = dir.file("a.ffpack");
  {
    Store store = open_or_die(path, Store::Mode::kReadWrite);
    ASSERT_TRUE(store.set_meta("stratified.alpha_deg", "1.5"));
    ASSERT_TRUE(store.set_meta("stratified.shells", "4"));
    ASSERT_TRUE(store.set_meta("scene.fingerprint", "0123abcd"));
    ASSERT_TRUE(store.set_meta("stratified.shells", "5"));  // replaces
    ASSERT_TRUE(store.set_meta("empty", ""));
  }
  Store store = open_or_die(path, Store::Mode::kRead);
  EXPECT_EQ(store.get_meta("stratified.shells").value(), "5");
  EXPECT_EQ(store.get_meta("empty").value(), "");
  EXPECT_FALSE(store.get_meta("missing").value());
  using P = std::vector<std::pair<std::string, std::string>>;
  EXPECT_EQ(store.list_meta("stratified.").value(),
            (P{{"stratified.alpha_deg", "1.5"}, {"stratified.shells", "5"}}));
  EXPECT_EQ(store.list_meta().value().size(), 4u);
}

// A bake record is used where its format is the one read, or (given) one from an oldest
// format on: a format change that only scenes with instances see leaves plain scenes' packs
// usable (TechniqueDescriptor::plain_scene_format); otherwise the error says to re-bake.
TEST(Store, BakeRecordsOfAnOlderFormatAreUsedOnlyWhereAllowed) {
  TempDir dir;
  const std::string path = dir.file("a.ffpack");
  {
    Store store = open_or_die(path, Store::Mode::kReadWrite);
    ASSERT_TRUE(write_bake_record(store, {"clusters", 7, 0x1234, 1.0, {}}));
  }
  Store store = open_or_die(path, Store::Mode::kRead);
  EXPECT_TRUE(usable_bake(store, "clusters", 7, 0x1234));
  const auto newer = usable_bake(store, "clusters", 8, 0x1234);
  ASSERT_FALSE(newer);
  EXPECT_NE(newer.error().message.find("has format 7 and this farfield reads format 8"),
            std::string::npos)
      << newer.error().message;
  EXPECT_TRUE(usable_bake(store, "clusters", 8, 0x1234, 7));
  EXPECT_FALSE(usable_bake(store, "clusters", 9, 0x1234, 8));
  EXPECT_FALSE(usable_bake(store, "clusters", 6, 0x1234, 5));  // newer than this farfield
  EXPECT_FALSE(usable_bake(store, "clusters", 8, 0x9999, 7));  // another scene
}

TEST(Store, ReadOnlyStoreRefusesWrites) {
  TempDir dir;
  const std::string path = dir.file("a.ffpack");
  { open_or_die(path, Store::Mode::kReadWrite); }
  Store store = open_or_die(path, Store::Mode::kRead);
  auto put = store.put("x", bytes_of("y"));
  ASSERT_FALSE(put);
  EXPECT_NE(put.error().message.find("read-only"), std::string::npos) << put.error().message;
  EXPECT_FALSE(store.set_meta("k", "v"));
  EXPECT_FALSE(store.erase(""));
  EXPECT_FALSE(store.begin());
}

TEST(Store, TransactionCommitsAllOrNothing) {
  TempDir dir;
  const std::string path = dir.file("a.ffpack");
  {
    Store store = open_or_die(path, Store::Mode::kReadWrite);
    {
      auto t = store.begin();
      ASSERT_TRUE(t) << t.error().message;
      ASSERT_TRUE(store.put("cell/0/a", bytes_of("a")));
      ASSERT_TRUE(store.put("cell/0/b", bytes_of("b")));
      ASSERT_TRUE(store.set_meta("done", "0"));
      ASSERT_TRUE(t->commit());
    }
    {
      auto t = store.begin();
      ASSERT_TRUE(t);
      ASSERT_TRUE(store.put("cell/1/a", random_bytes(3 << 20, 2)));  // spills to the file
      ASSERT_TRUE(store.put("cell/0/a", bytes_of("overwritten")));
      ASSERT_TRUE(store.set_meta("done", "1"));
      EXPECT_TRUE(store.contains("cell/1/a").value());  // visible inside the transaction
    }  // not committed: rolled back
    EXPECT_FALSE(store.contains("cell/1/a").value());
  }
  Store store = open_or_die(path, Store::Mode::kRead);
  EXPECT_EQ(names(store.list()), (std::vector<std::string>{"cell/0/a", "cell/0/b"}));
  EXPECT_EQ(store.get("cell/0/a").value(), bytes_of("a"));
  EXPECT_EQ(store.get_meta("done").value(), "0");
  EXPECT_TRUE(store.verify());
}

// A bake in a child process: transaction i writes "cell/i/a", tells the parent 'm' (mid),
// writes "cell/i/b" and meta "done" = i, commits, then tells the parent 'c'. Resumes from the
// names present, as a bake would. At transaction `hold` it stops after 'm' and waits to die.
[[noreturn]] void bake_forever(const std::string& path, int pipe_fd, int hold) {
  auto store = Store::open(path, Store::Mode::kReadWrite);
  if (!store) _exit(2);
  for (int i = 0; i < 100000; ++i) {
    const std::string cell = "cell/" + std::to_string(100000 + i);
    if (store->contains(cell + "/b").value()) continue;
    auto t = store->begin();
    if (!t || !store->put(cell + "/a", random_bytes(1 << 20, i), Codec::kNone)) _exit(3);
    if (::write(pipe_fd, "m", 1) != 1) _exit(4);
    while (i == hold) ::pause();
    if (!store->put(cell + "/b", random_bytes(1 << 19, ~i), Codec::kZstd)) _exit(3);
    if (!store->set_meta("done", std::to_string(i)) || !t->commit()) _exit(3);
    if (::write(pipe_fd, "c", 1) != 1) _exit(4);
  }
  _exit(0);
}

// Reads the child's progress until `commits` commits and one more 'm', then kills it.
int kill_mid_transaction(pid_t child, int pipe_fd, int commits) {
  int seen = 0;
  char c;
  while (::read(pipe_fd, &c, 1) == 1) {
    if (c == 'c') ++seen;
    if (c == 'm' && seen >= commits) break;
  }
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "child status " << status;
  return seen;
}

// Every cell has both blobs intact, and the cells are 0..n-1 with no gap.
int check_prefix(const Store& store) {
  auto blobs = store.list("cell/");
  EXPECT_TRUE(blobs) << blobs.error().message;
  if (!blobs) return -1;
  const int cells = int(blobs->size() / 2);
  EXPECT_EQ(blobs->size() % 2, 0u);
  for (int i = 0; i < cells; ++i) {
    const std::string cell = "cell/" + std::to_string(100000 + i);
    EXPECT_EQ(store.get(cell + "/a").value(), random_bytes(1 << 20, i)) << cell;
    EXPECT_EQ(store.get(cell + "/b").value(), random_bytes(1 << 19, ~i)) << cell;
  }
  EXPECT_EQ(store.get_meta("done").value().value_or("none"), std::to_string(cells - 1));
  return cells;
}

// Run 0 dies exactly between two puts of transaction 8; run 1 resumes it and dies wherever
// the kill lands (a put, the commit, between transactions) after 8 more commits.
TEST(Store, KilledBakeLeavesCommittedPrefixAndResumes) {
  TempDir dir;
  const std::string path = dir.file("bake.ffpack");
  int cells_before = 0;
  for (int run = 0; run < 2; ++run) {
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      ::close(fds[0]);
      bake_forever(path, fds[1], run == 0 ? 8 : -1);
    }
    ::close(fds[1]);
    const int acknowledged = kill_mid_transaction(child, fds[0], 8);
    ::close(fds[0]);

    // Opening for writing rolls the interrupted transaction back.
    Store store = open_or_die(path, Store::Mode::kReadWrite);
    const int cells = check_prefix(store);
    if (run == 0) {
      EXPECT_EQ(cells, 8);
    }
    EXPECT_GE(cells, cells_before + acknowledged) << "run " << run;
    EXPECT_TRUE(store.verify());
    cells_before = cells;
  }
}

TEST(Store, CrashMidTransactionNeedsOneWritableOpen) {
  TempDir dir;
  const std::string path = dir.file("a.ffpack");
  {
    Store store = open_or_die(path, Store::Mode::kReadWrite);
    ASSERT_TRUE(store.put("kept", bytes_of("kept")));
  }
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    auto store = Store::open(path, Store::Mode::kReadWrite);
    auto t = store->begin();
    // Bigger than SQLite's page cache, so pages reach the file before the commit.
    (void)store->put("lost", random_bytes(8 << 20, 3), Codec::kNone);
    (void)store->put("kept", bytes_of("changed"));
    ::raise(SIGKILL);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  ASSERT_TRUE(std::filesystem::exists(path + "-journal"));

  // A read-only open cannot roll back, and says so.
  EXPECT_TRUE(refused(path, Store::Mode::kRead, "interrupted"));
  { open_or_die(path, Store::Mode::kReadWrite); }
  EXPECT_FALSE(std::filesystem::exists(path + "-journal"));
  Store store = open_or_die(path, Store::Mode::kRead);
  EXPECT_EQ(names(store.list()), std::vector<std::string>{"kept"});
  EXPECT_EQ(store.get("kept").value(), bytes_of("kept"));
}

// Finds `pattern` in the file and flips one bit in the middle of it.
void flip_bit_in(const std::string& path, std::string_view pattern) {
  std::string bytes = test::read_file(path);
  const size_t at = bytes.find(pattern);
  ASSERT_NE(at, std::string::npos);
  ASSERT_EQ(bytes.find(pattern, at + 1), std::string::npos);
  bytes[at + pattern.size() / 2] ^= 0x10;
  test::write_file(path, bytes);
}

TEST(Store, FlippedByteInBlobIsDetectedAndNamed) {
  TempDir dir;
  const std::string path = dir.file("a.ffpack");
  std::string marked(50000, 'x');
  marked.replace(30000, 20, "<<FARFIELD MARKER>>!");
  {
    Store store = open_or_die(path, Store::Mode::kReadWrite);
    ASSERT_TRUE(store.put("cell/1", bytes_of("neighbour")));
    ASSERT_TRUE(store.put("cell/7/far", bytes_of(marked), Codec::kNone));
    ASSERT_TRUE(store.put("cell/9", bytes_of("neighbour")));
  }
  flip_bit_in(path, "<<FARFIELD MARKER>>!");
  Store store = open_or_die(path, Store::Mode::kRead);  // blob data is not read on open
  auto get = store.get("cell/7/far");
  ASSERT_FALSE(get);
  EXPECT_EQ(get.error().message, path + ": blob 'cell/7/far' is corrupted (checksum mismatch)");
  EXPECT_TRUE(store.get("cell/1"));
  EXPECT_TRUE(store.get("cell/9"));
  auto verify = store.verify();
  ASSERT_FALSE(verify);
  EXPECT_EQ(verify.error().message, get.error().message);
}

TEST(Store, TamperedColumnsAreDetectedAndNamed) {
  TempDir dir;
  const std::string path = dir.file("a.ffpack");
  {
    Store store = open_or_die(path, Store::Mode::kReadWrite);
    ASSERT_TRUE(store.put("zstd", random_bytes(1000, 5)));
    ASSERT_TRUE(store.put_image("image", gradient(32, 32), ImageCodec::png()));
    ASSERT_TRUE(store.put("raw", bytes_of("raw bytes")));
  }
  run_sql(path,
          "UPDATE blobs SET raw_size = raw_size + 1 WHERE name = 'zstd';"
          "UPDATE blobs SET raw_size = 32 * 33 * 3 WHERE name = 'image';"
          "UPDATE blobs SET codec = 9 WHERE name = 'raw';");
  Store store = open_or_die(path, Store::Mode::kRead);
  for (const char* name : {"zstd", "image", "raw"}) {
    const std::string message = std::string(name) == "image" ? store.get_image(name).error().message
                                                             : store.get(name).error().message;
    EXPECT_NE(message.find(path + ": blob '" + name + "'"), std::string::npos) << message;
  }
  EXPECT_NE(store.get("raw").error().message.find("unknown codec 9"), std::string::npos);
}

TEST(StoreFile, RefusesWhatIsNotAPack) {
  TempDir dir;
  const std::string pack = dir.file("good.ffpack");
  {
    Store store = open_or_die(pack, Store::Mode::kReadWrite);
    for (int i = 0; i < 20; ++i)
      ASSERT_TRUE(store.put("blob/" + std::to_string(i), random_bytes(100000, i), Codec::kNone));
  }
  const std::string good = test::read_file(pack);

  EXPECT_TRUE(refused(dir.file("missing.ffpack"), Store::Mode::kRead, "No such file"));
  EXPECT_TRUE(refused(dir.path().string(), Store::Mode::kRead, "not a regular file"));
  test::write_file(dir.file("empty.ffpack"), "");
  EXPECT_TRUE(refused(dir.file("empty.ffpack"), Store::Mode::kRead, "empty file"));

  const std::string text = dir.file("text.ffpack");
  test::write_file(text, std::string(3000, 'a') + "\nthis is a text file, not a pack\n");
  const std::string noise = dir.file("noise.ffpack");
  const auto random = random_bytes(70000, 9);
  test::write_file(noise, std::string(reinterpret_cast<const char*>(random.data()), random.size()));
  const std::string scene = dir.file("boxes.ffscene");
  ASSERT_TRUE(write_scene(test::make_box_row(3), scene));
  for (const std::string& path : {text, noise, scene}) {
    for (auto mode : {Store::Mode::kRead, Store::Mode::kReadWrite}) {
      const std::string before = test::read_file(path);
      EXPECT_TRUE(refused(path, mode, "not a farfield pack (not an SQLite database)"));
      EXPECT_EQ(test::read_file(path), before) << path << " was modified";
    }
  }

  // Truncated: at half, or within the first page.
  const std::string cut = dir.file("cut.ffpack");
  test::write_file(cut, good.substr(0, good.size() / 2));
  EXPECT_TRUE(refused(cut, Store::Mode::kRead, "corrupted pack"));
  EXPECT_TRUE(refused(cut, Store::Mode::kRead, "truncated: " + std::to_string(good.size() / 2)));
  EXPECT_TRUE(refused(cut, Store::Mode::kReadWrite, "corrupted pack"));
  test::write_file(cut, good.substr(0, 60));
  EXPECT_TRUE(refused(cut, Store::Mode::kRead, "not a farfield pack"));
  EXPECT_TRUE(refused(cut, Store::Mode::kReadWrite, "not a farfield pack"));
}

TEST(StoreFile, RefusesOtherDatabasesAndSchemas) {
  TempDir dir;
  const std::string other = dir.file("other.ffpack");
  run_sql(other, "CREATE TABLE blobs(name TEXT, data BLOB)");
  EXPECT_TRUE(refused(other, Store::Mode::kRead, "application_id 0x00000000"));
  EXPECT_TRUE(refused(other, Store::Mode::kReadWrite, "not a farfield pack"));

  const std::string newer = dir.file("newer.ffpack");
  { open_or_die(newer, Store::Mode::kReadWrite); }
  run_sql(newer, "PRAGMA user_version = 2");
  EXPECT_TRUE(refused(newer, Store::Mode::kRead, "schema version 2 is newer"));

  const std::string extra = dir.file("extra.ffpack");
  { open_or_die(extra, Store::Mode::kReadWrite); }
  run_sql(extra, "CREATE TRIGGER t AFTER INSERT ON blobs BEGIN DELETE FROM meta; END");
  EXPECT_TRUE(refused(extra, Store::Mode::kReadWrite, "not those of schema version 1"));

  const std::string foreign = dir.file("foreign.ffpack");
  run_sql(foreign, "PRAGMA application_id = 1234");
  // An SQLite file with no table yet but another owner's id is not taken over either.
  run_sql(foreign, "CREATE TABLE t(x)");
  EXPECT_TRUE(refused(foreign, Store::Mode::kReadWrite, "application_id 0x000004d2"));
}

TEST(StoreFile, CreatesOnlyWithReadWriteAndReopens) {
  TempDir dir;
  const std::string path = dir.file("new.ffpack");
  EXPECT_FALSE(Store::open(path, Store::Mode::kRead));
  EXPECT_FALSE(std::filesystem::exists(path));
  { open_or_die(path, Store::Mode::kReadWrite); }
  // One self-contained file at rest: no journal beside it.
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"new.ffpack"});
  Store store = open_or_die(path, Store::Mode::kRead);
  EXPECT_TRUE(store.list().value().empty());
  EXPECT_TRUE(store.verify());
  EXPECT_FALSE(Store::open(dir.file("no/such/folder.ffpack"), Store::Mode::kReadWrite));
}

}  // namespace
}  // namespace farfield
