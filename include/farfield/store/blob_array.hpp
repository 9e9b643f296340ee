// Arrays of plain records as store blobs: their bytes as written, and read back refusing a
// blob that is not whole records (naming the store and the blob).
#pragma once

#include <cstring>
#include <span>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

template <class T>
std::span<const std::byte> bytes_of(const std::vector<T>& v) {
  return std::as_bytes(std::span(v));
}

template <class T>
Result<std::vector<T>> read_array(const Store& store, const char* name) {
  auto bytes = store.get(name);
  if (!bytes) return bytes.error();
  if (bytes->size() % sizeof(T) != 0)
    return make_error(store.path(), ": blob '", name, "' has a size that is not whole records");
  std::vector<T> out(bytes->size() / sizeof(T));
  if (!out.empty()) std::memcpy(out.data(), bytes->data(), bytes->size());
  return out;
}

}  // namespace farfield
