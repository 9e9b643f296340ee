#include "farfield/core/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace farfield {

bool write_all(int fd, const void* data, size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<size_t>(n);
  }
  return true;
}

bool write_all_at(int fd, const void* data, size_t size, uint64_t offset) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::pwrite(fd, p, size, off_t(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    offset += uint64_t(n);
    size -= static_cast<size_t>(n);
  }
  return true;
}

Result<AtomicFile> AtomicFile::create(const std::string& path) {
  const std::filesystem::path target(path);
  const std::filesystem::path folder = target.parent_path().empty() ? "." : target.parent_path();
  std::string tmp = (folder / ".").string();  // "DIR/." then the hidden name after the dot
  tmp.append(target.filename().string());
  tmp.append(".XXXXXX.tmp");
  const int fd = ::mkstemps(tmp.data(), 4);
  if (fd < 0)
    return make_error(path, ": cannot create a temporary file beside it: ", std::strerror(errno));
  ::fchmod(fd, 0644);
  return AtomicFile(path, std::move(tmp), fd);
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : path_(std::move(other.path_)), temporary_(std::move(other.temporary_)), fd_(other.fd_) {
  other.fd_ = -1;
  other.temporary_.clear();
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!temporary_.empty()) ::unlink(temporary_.c_str());
}

Error AtomicFile::failure(const char* what) const {
  return make_error(path_, ": ", what, ": ", std::strerror(errno));
}

Result<void> AtomicFile::commit() {
  const bool synced = ::fsync(fd_) == 0;
  const int sync_error = errno;
  const bool closed = ::close(fd_) == 0;
  fd_ = -1;
  if (!closed) return failure("close failed");
  errno = sync_error;
  if (!synced) return failure("flush failed");
  if (::rename(temporary_.c_str(), path_.c_str()) != 0)
    return failure("cannot rename the temporary file into place");
  temporary_.clear();
  return {};
}

Result<void> write_file_atomically(const std::string& path, const std::function<bool(int)>& fill) {
  auto file = AtomicFile::create(path);
  if (!file) return file.error();
  if (!fill(file->fd())) return file->failure("write failed");
  return file->commit();
}

Result<void> write_file_atomically(const std::string& path, std::string_view bytes) {
  return write_file_atomically(path, [&](int fd) { return write_all(fd, bytes.data(), bytes.size()); });
}

}  // namespace farfield
