// Writing a whole file so that readers see the old file or the new one, never a part: a
// temporary file beside the destination, flushed, then renamed over it. On failure the
// temporary file is removed and the message names the destination and the cause.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

#include "farfield/core/result.hpp"

namespace farfield {

// `fill` writes the content into the open file descriptor (with write_all) and returns false
// when a write fails (errno then says why).
Result<void> write_file_atomically(const std::string& path, const std::function<bool(int)>& fill);
Result<void> write_file_atomically(const std::string& path, std::string_view bytes);

// write(2) until all of `data` is written; false on an error (errno set).
bool write_all(int fd, const void* data, size_t size);

}  // namespace farfield
