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

Result<void> write_file_atomically(const std::string& path, const std::function<bool(int)>& fill) {
  const std::filesystem::path target(path);
  const std::filesystem::path folder = target.parent_path().empty() ? "." : target.parent_path();
  std::string tmp = (folder / ".").string();  // "DIR/." then the hidden name after the dot
  tmp.append(target.filename().string());
  tmp.append(".XXXXXX.tmp");
  const int fd = ::mkstemps(tmp.data(), 4);
  if (fd < 0)
    return make_error(path, ": cannot create a temporary file beside it: ", std::strerror(errno));
  ::fchmod(fd, 0644);
  auto fail = [&](const char* what, int error) -> Result<void> {
    ::unlink(tmp.c_str());
    return make_error(path, ": ", what, ": ", std::strerror(error));
  };
  if (!fill(fd)) {
    const int error = errno;
    ::close(fd);
    return fail("write failed", error);
  }
  const bool synced = ::fsync(fd) == 0;
  const int sync_error = errno;
  if (::close(fd) != 0) return fail("close failed", errno);
  if (!synced) return fail("flush failed", sync_error);
  if (::rename(tmp.c_str(), path.c_str()) != 0)
    return fail("cannot rename the temporary file into place", errno);
  return {};
}

Result<void> write_file_atomically(const std::string& path, std::string_view bytes) {
  return write_file_atomically(path, [&](int fd) { return write_all(fd, bytes.data(), bytes.size()); });
}

}  // namespace farfield
