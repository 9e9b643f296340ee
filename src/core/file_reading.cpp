#include "farfield/core/file_reading.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

namespace farfield {

namespace {

Error io_error(const std::string& path, const char* what) {
  return make_error(path, ": ", what, ": ", std::strerror(errno));
}

}  // namespace

Result<ReadableFile> ReadableFile::open(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return io_error(path, "cannot open");
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    Error e = io_error(path, "cannot stat");
    ::close(fd);
    return e;
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    return make_error(path, ": not a regular file");
  }
  return ReadableFile(path, fd, uint64_t(st.st_size));
}

ReadableFile::ReadableFile(ReadableFile&& other) noexcept
    : path_(std::move(other.path_)), fd_(std::exchange(other.fd_, -1)), size_(other.size_) {}

ReadableFile::~ReadableFile() {
  if (fd_ >= 0) ::close(fd_);
}

Result<void> ReadableFile::read_at(void* data, uint64_t size, uint64_t offset) const {
  char* p = static_cast<char*>(data);
  while (size > 0) {
    // One call reads at most 1 GiB: Linux caps a read near 2 GiB, and off_t offsets stay exact.
    const size_t ask = size_t(std::min<uint64_t>(size, uint64_t(1) << 30));
    const ssize_t n = ::pread(fd_, p, ask, off_t(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return io_error(path_, "read failed");
    if (n == 0)
      return make_error(path_, ": truncated (it ends at byte ", std::to_string(offset),
                        " of the bytes to read)");
    p += n;
    size -= uint64_t(n);
    offset += uint64_t(n);
  }
  return {};
}

Result<std::string> ReadableFile::read_all() const {
  std::string bytes(size_t(size_), '\0');
  if (auto ok = read_at(bytes.data(), size_, 0); !ok) return ok.error();
  return bytes;
}

}  // namespace farfield
