// Writing a whole file so that readers see the old file or the new one, never a part: a
// temporary file beside the destination, flushed, then renamed over it. On failure the
// temporary file is removed and the message names the destination and the cause.
#pragma once

#include <string>
#include <string_view>

#include "farfield/core/result.hpp"

namespace farfield {

Result<void> write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace farfield
