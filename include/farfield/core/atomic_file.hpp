// Writing a whole file so that readers see the old file or the new one, never a part: a
// temporary file beside the destination, flushed, then renamed over it. On failure the
// temporary file is removed and the message names the destination and the cause.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "farfield/core/result.hpp"

namespace farfield {

// A file written in place of `path` in several steps: created as a temporary file beside it,
// renamed over it by commit() once flushed; removed if never committed (destroyed, or
// commit failed).
class AtomicFile {
 public:
  static Result<AtomicFile> create(const std::string& path);
  AtomicFile(AtomicFile&& other) noexcept;
  AtomicFile& operator=(AtomicFile&&) = delete;
  ~AtomicFile();
  int fd() const { return fd_; }
  const std::string& path() const { return path_; }
  // An error naming the destination, `what` failed and errno's cause.
  Error failure(const char* what) const;
  // Flushes, closes and renames the file into place.
  Result<void> commit();

 private:
  AtomicFile(std::string path, std::string temporary, int fd)
      : path_(std::move(path)), temporary_(std::move(temporary)), fd_(fd) {}
  std::string path_, temporary_;
  int fd_ = -1;
};

// `fill` writes the content into the open file descriptor (with write_all) and returns false
// when a write fails (errno then says why).
Result<void> write_file_atomically(const std::string& path, const std::function<bool(int)>& fill);
Result<void> write_file_atomically(const std::string& path, std::string_view bytes);

// write(2) until all of `data` is written; false on an error (errno set).
bool write_all(int fd, const void* data, size_t size);
// pwrite(2) until all of `data` is written at `offset`; false on an error (errno set).
bool write_all_at(int fd, const void* data, size_t size, uint64_t offset);

}  // namespace farfield
