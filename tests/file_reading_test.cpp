// Files of any size: reads go on past the ~2 GiB a single read(2) returns on Linux, and a file
// that ends early is called truncated.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstring>
#include <vector>

#include "farfield/core/file_reading.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

TEST(FileReading, ReadsMoreThanTwoGibibytesAtOnceFromASparseFile) {
  test::TempDir dir;
  const std::string path = dir.file("sparse.bin");
  const uint64_t size = (uint64_t(5) << 30) / 2;  // 2.5 GiB, all holes but the last bytes
  {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::ftruncate(fd, off_t(size)), 0);
    const char tail[8] = {'f', 'a', 'r', 'f', 'i', 'e', 'l', 'd'};
    ASSERT_EQ(::pwrite(fd, tail, sizeof tail, off_t(size - sizeof tail)), ssize_t(sizeof tail));
    ::close(fd);
  }
  auto file = ReadableFile::open(path);
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_EQ(file->size(), size);
  const uint64_t offset = uint64_t(1) << 28, count = size - offset;  // 2.25 GiB in one call
  std::vector<char> bytes(count);
  ASSERT_TRUE(file->read_at(bytes.data(), count, offset));
  EXPECT_EQ(std::memcmp(bytes.data() + count - 8, "farfield", 8), 0);
  EXPECT_EQ(bytes[0], 0);
  auto past = file->read_at(bytes.data(), 16, size - 8);
  ASSERT_FALSE(past);
  EXPECT_NE(past.error().message.find("truncated"), std::string::npos) << past.error().message;
  EXPECT_NE(past.error().message.find(path), std::string::npos);
}

TEST(FileReading, RefusesMissingFilesAndFolders) {
  test::TempDir dir;
  auto missing = ReadableFile::open(dir.file("nope"));
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("cannot open"), std::string::npos);
  auto folder = ReadableFile::open(dir.path().string());
  ASSERT_FALSE(folder);
  EXPECT_NE(folder.error().message.find("not a regular file"), std::string::npos);
}

}  // namespace
}  // namespace farfield
