// Shared by the fuzz targets of technique bakes: a scratch .ffpack (in /dev/shm where there is
// one, so that each input costs little I/O) filled with fuzzed blobs, removed again.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include "farfield/store/store.hpp"

namespace fuzz {

inline std::string scratch_pack(const char* target) {
  const std::filesystem::path dir = std::filesystem::is_directory("/dev/shm")
                                        ? "/dev/shm"
                                        : std::filesystem::temp_directory_path();
  return (dir / (std::string("farfield-") + target + "-" + std::to_string(::getpid()) + ".ffpack"))
      .string();
}

inline void remove_pack(const std::string& path) {
  for (const char* suffix : {"", "-journal", "-wal", "-shm"}) ::unlink((path + suffix).c_str());
}

}  // namespace fuzz
