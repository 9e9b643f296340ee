#include "farfield/core/image.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <png.h>

#include "farfield/core/assert.hpp"

namespace farfield {

namespace {

Error io_error(const std::string& path, const char* what) {
  return make_error(path, ": ", what, ": ", std::strerror(errno));
}

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

// Writes `bytes` to a temporary file beside `path`, then renames it into place, so that a
// reader never sees half a file and a failure leaves nothing behind.
Result<void> write_file_atomically(const std::string& path, const std::vector<uint8_t>& bytes) {
  const std::filesystem::path target(path);
  const std::filesystem::path folder = target.parent_path().empty() ? "." : target.parent_path();
  std::string tmp = (folder / ".").string();
  tmp.append(target.filename().string());
  tmp.append(".XXXXXX.tmp");
  const int fd = ::mkstemps(tmp.data(), 4);
  if (fd < 0) return io_error(path, "cannot create a temporary file beside it");
  ::fchmod(fd, 0644);
  auto fail = [&](const char* what) -> Result<void> {
    Error e = io_error(path, what);
    ::close(fd);
    ::unlink(tmp.c_str());
    return e;
  };
  if (!write_all(fd, bytes.data(), bytes.size())) return fail("write failed");
  if (::fsync(fd) != 0) return fail("flush failed");
  if (::close(fd) != 0) {
    Error e = io_error(path, "close failed");
    ::unlink(tmp.c_str());
    return e;
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    Error e = io_error(path, "cannot rename the temporary file into place");
    ::unlink(tmp.c_str());
    return e;
  }
  return {};
}

}  // namespace

// libpng's simplified API keeps its setjmp error handling inside libpng, so no longjmp
// crosses C++ frames; its errors come back in png_image::message.
Result<void> write_png(const Image& image, const std::string& path) {
  FF_ASSERT(image.width > 0 && image.height > 0 &&
                image.rgb.size() == size_t(image.width) * size_t(image.height) * 3,
            "image %dx%d holds %zu bytes", image.width, image.height, image.rgb.size());
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.width);
  png.height = png_uint_32(image.height);
  png.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  if (!png_image_write_get_memory_size(png, size, 0, image.rgb.data(), 0, nullptr))
    return make_error(path, ": cannot encode PNG: ", png.message);
  std::vector<uint8_t> bytes(size);
  if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, image.rgb.data(), 0, nullptr))
    return make_error(path, ": cannot encode PNG: ", png.message);
  bytes.resize(size);
  return write_file_atomically(path, bytes);
}

Result<Image> read_png(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return io_error(path, "cannot open");
  const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(file),
                                   std::istreambuf_iterator<char>()};
  if (file.bad()) return io_error(path, "read failed");

  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()))
    return make_error(path, ": not a readable PNG file: ", png.message);
  png.format = PNG_FORMAT_RGB;  // libpng converts grey, palette, 16-bit and drops alpha
  if (png.width == 0 || png.height == 0 || png.width > 1u << 15 || png.height > 1u << 15) {
    png_image_free(&png);
    return make_error(path, ": PNG of ", std::to_string(png.width), "x", std::to_string(png.height),
                      " pixels is outside 1..32768 per side");
  }
  Image image(int(png.width), int(png.height));
  if (!png_image_finish_read(&png, nullptr, image.rgb.data(), 0, nullptr))
    return make_error(path, ": corrupted PNG file: ", png.message);
  return image;
}

}  // namespace farfield
