// A 3D Tiles package (.3dtiles): a tileset and its files in one SQLite database, one row a
// file in the table `media` (key: the file's path relative to the tileset, content: its bytes),
// the layout Cesium's 3D Tiles Package specification (1.0.0) describes and its tools read.
// Written to a temporary file beside the destination and renamed over it when whole.
#pragma once

#include <string>
#include <string_view>

#include "farfield/core/result.hpp"

namespace farfield {

class TilesPackageWriter {
 public:
  // Starts `path`.partial (removing one left by a killed run).
  static Result<TilesPackageWriter> create(const std::string& path);
  TilesPackageWriter(TilesPackageWriter&&) noexcept;
  ~TilesPackageWriter();  // without finish(): the partial file is removed

  Result<void> put(std::string_view key, std::string_view content);
  // Commits and renames the partial file over `path`.
  Result<void> finish();

 private:
  TilesPackageWriter() = default;
  struct State;
  State* state_ = nullptr;
};

// The content stored under `key`, or an error naming the package and key (for tests and tools).
Result<std::string> read_tiles_package(const std::string& path, std::string_view key);

}  // namespace farfield
