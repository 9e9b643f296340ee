#include "farfield/core/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace farfield {

Result<void> write_file_atomically(const std::string& path, std::string_view bytes) {
  const std::filesystem::path target(path);
  std::string tmp = (target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path())
                        .append(".")
                        .string();  // "DIR/." then the hidden name right after the dot
  tmp.append(target.filename().string());
  tmp.append(".XXXXXX.tmp");
  const int fd = ::mkstemps(tmp.data(), 4);
  if (fd < 0) return make_error(path, ": cannot create a temporary file beside it: ", std::strerror(errno));
  ::fchmod(fd, 0644);
  const char* p = bytes.data();
  size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int e = errno;
      ::close(fd);
      ::unlink(tmp.c_str());
      return make_error(path, ": write failed: ", std::strerror(e));
    }
    p += n;
    left -= static_cast<size_t>(n);
  }
  const bool synced = ::fsync(fd) == 0;
  const int sync_errno = errno;
  if (::close(fd) != 0 || !synced) {
    const int e = synced ? errno : sync_errno;
    ::unlink(tmp.c_str());
    return make_error(path, ": flush failed: ", std::strerror(e));
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    ::unlink(tmp.c_str());
    return make_error(path, ": cannot rename the temporary file into place: ", std::strerror(e));
  }
  return {};
}

}  // namespace farfield
