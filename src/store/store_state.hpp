// Private to src/store/: the SQLite connection behind a Store, and helpers for its cached
// statements. store_open.cpp opens and checks a pack; store.cpp reads and writes it.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <span>
#include <string_view>

#include <sqlite3.h>

#include "farfield/store/store.hpp"

namespace farfield::detail {

enum StatementId {
  kPut, kGet, kInfo, kList, kTotal, kErase, kSetMeta, kGetMeta, kListMeta, kEraseMeta,
  kStatementCount
};

// Resets a cached statement when the scope that used it ends, so that it holds no read lock
// and no pointer into the caller's strings.
class Use {
 public:
  explicit Use(sqlite3_stmt* stmt) : stmt_(stmt) {}
  Use(const Use&) = delete;
  ~Use() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  sqlite3_stmt* get() const { return stmt_; }

 private:
  sqlite3_stmt* stmt_;
};

inline void bind_text(sqlite3_stmt* stmt, int index, std::string_view text) {
  // An empty string_view may hold a null pointer, which SQLite would bind as NULL.
  sqlite3_bind_text(stmt, index, text.empty() ? "" : text.data(), int(text.size()), SQLITE_STATIC);
}

// Binds ?1 and ?2 to the range of names that start with `prefix`: [prefix, end), where end
// is prefix with its last byte below 0xFF incremented. With no such byte there is no upper
// bound, and ?2 becomes an empty BLOB, which sorts after every TEXT value in SQLite.
inline void bind_prefix(sqlite3_stmt* stmt, std::string_view prefix, std::string& end) {
  bind_text(stmt, 1, prefix);
  end.assign(prefix);
  while (!end.empty() && uint8_t(end.back()) == 0xFF) end.pop_back();
  if (end.empty()) {
    sqlite3_bind_zeroblob(stmt, 2, 0);
  } else {
    end.back() = char(uint8_t(end.back()) + 1);
    bind_text(stmt, 2, end);
  }
}

inline std::string column_text(sqlite3_stmt* stmt, int column) {
  const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt, column));
  return text ? std::string(text, size_t(sqlite3_column_bytes(stmt, column))) : std::string();
}

inline std::string quoted(std::string_view name) { return "'" + std::string(name) + "'"; }

inline bool is_image(Codec codec) { return codec == Codec::kJpeg || codec == Codec::kPng; }

struct StoreState {
  std::string path;
  Store::Mode mode = Store::Mode::kRead;
  sqlite3* db = nullptr;
  std::array<sqlite3_stmt*, kStatementCount> statements{};
  bool in_transaction = false;

  ~StoreState();

  // The message for an SQLite failure while doing `what` (e.g. "cannot read blob 'x'"):
  // names the file, and says plainly what NOTADB, CORRUPT, BUSY and a hot journal mean.
  Error error(int rc, std::string_view what) const;

  Result<void> exec(const char* sql, std::string_view what) {
    const int rc = sqlite3_exec(db, sql, nullptr, nullptr, nullptr);
    if (rc != SQLITE_OK) return error(rc, what);
    return {};
  }

  // Runs a statement that returns one integer.
  Result<int64_t> query_int(const char* sql, std::string_view what) const {
    sqlite3_stmt* stmt = nullptr;
    int rc = sqlite3_prepare_v2(db, sql, -1, &stmt, nullptr);
    if (rc != SQLITE_OK) return error(rc, what);
    rc = sqlite3_step(stmt);
    const int64_t value = sqlite3_column_int64(stmt, 0);
    sqlite3_finalize(stmt);
    if (rc != SQLITE_ROW) return error(rc == SQLITE_DONE ? SQLITE_CORRUPT : rc, what);
    return value;
  }

  Result<void> writable(std::string_view what) const {
    if (mode == Store::Mode::kRead) return make_error(path, ": ", what, ": pack opened read-only");
    return {};
  }

  Result<void> write_blob(std::string_view name, Codec codec, uint64_t raw_size,
                          std::span<const std::byte> stored);
  // Finds blob `name`, checks its checksum and sizes, and hands (codec, raw size, stored
  // bytes) to `decode` while the bytes are still SQLite's.
  template <class T, class Decode>
  Result<T> read_blob(std::string_view name, Decode&& decode) const;
  Result<BlobInfo> blob_info(sqlite3_stmt* stmt) const;
  Result<void> check_header();
  Result<void> create_schema();
  // The statements of kStatementSql, once the schema is known to be ours.
  Result<void> prepare();
};

}  // namespace farfield::detail
