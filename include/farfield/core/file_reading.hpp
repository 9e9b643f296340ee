// Reading files of any size: a regular file opened with its size, and reads that go on until
// every byte asked for has come (read(2) and pread(2) may return fewer bytes than asked: Linux
// returns at most 2^31 - 4096 a call). Errors name the file and the cause; a file that ends
// before the bytes asked for is "truncated", not an I/O error with no errno.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "farfield/core/result.hpp"

namespace farfield {

// An open regular file, closed on destruction.
class ReadableFile {
 public:
  static Result<ReadableFile> open(const std::string& path);
  ReadableFile(ReadableFile&& other) noexcept;
  ReadableFile& operator=(ReadableFile&&) = delete;
  ~ReadableFile();

  uint64_t size() const { return size_; }
  int fd() const { return fd_; }
  // `size` bytes at `offset` into `data`.
  Result<void> read_at(void* data, uint64_t size, uint64_t offset) const;
  // The whole file.
  Result<std::string> read_all() const;

 private:
  ReadableFile(std::string path, int fd, uint64_t size) : path_(std::move(path)), fd_(fd), size_(size) {}
  std::string path_;
  int fd_ = -1;
  uint64_t size_ = 0;
};

}  // namespace farfield
