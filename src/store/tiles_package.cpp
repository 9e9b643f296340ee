#include "farfield/store/tiles_package.hpp"

#include <sqlite3.h>

#include <cstdio>
#include <filesystem>

namespace farfield {

struct TilesPackageWriter::State {
  std::string path, partial;
  sqlite3* db = nullptr;
  sqlite3_stmt* insert = nullptr;
};

namespace {

Error sqlite_error(const std::string& path, sqlite3* db, const char* doing) {
  return make_error(path, ": ", doing, ": ", db ? sqlite3_errmsg(db) : "out of memory");
}

}  // namespace

Result<TilesPackageWriter> TilesPackageWriter::create(const std::string& path) {
  TilesPackageWriter w;
  w.state_ = new State;
  w.state_->path = path;
  w.state_->partial = path + ".partial";
  std::error_code ignored;
  std::filesystem::remove(w.state_->partial, ignored);
  if (sqlite3_open_v2(w.state_->partial.c_str(), &w.state_->db,
                      SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK)
    return sqlite_error(path, w.state_->db, "cannot create the package");
  const char* schema =
      "PRAGMA journal_mode=OFF; PRAGMA synchronous=OFF; BEGIN;"
      "CREATE TABLE media (key TEXT PRIMARY KEY, content BLOB);";
  if (sqlite3_exec(w.state_->db, schema, nullptr, nullptr, nullptr) != SQLITE_OK)
    return sqlite_error(path, w.state_->db, "cannot make the media table");
  if (sqlite3_prepare_v2(w.state_->db, "INSERT INTO media (key, content) VALUES (?, ?)", -1,
                         &w.state_->insert, nullptr) != SQLITE_OK)
    return sqlite_error(path, w.state_->db, "cannot prepare");
  return w;
}

TilesPackageWriter::TilesPackageWriter(TilesPackageWriter&& other) noexcept
    : state_(other.state_) {
  other.state_ = nullptr;
}

TilesPackageWriter::~TilesPackageWriter() {
  if (!state_) return;
  sqlite3_finalize(state_->insert);
  sqlite3_close(state_->db);
  std::error_code ignored;
  if (!state_->partial.empty()) std::filesystem::remove(state_->partial, ignored);
  delete state_;
}

Result<void> TilesPackageWriter::put(std::string_view key, std::string_view content) {
  sqlite3_stmt* s = state_->insert;
  sqlite3_reset(s);
  sqlite3_bind_text(s, 1, key.data(), int(key.size()), SQLITE_STATIC);
  sqlite3_bind_blob64(s, 2, content.data(), content.size(), SQLITE_STATIC);
  if (sqlite3_step(s) != SQLITE_DONE)
    return sqlite_error(state_->path, state_->db, ("cannot write " + std::string(key)).c_str());
  return {};
}

Result<void> TilesPackageWriter::finish() {
  if (sqlite3_exec(state_->db, "COMMIT;", nullptr, nullptr, nullptr) != SQLITE_OK)
    return sqlite_error(state_->path, state_->db, "cannot commit");
  sqlite3_finalize(state_->insert);
  state_->insert = nullptr;
  if (sqlite3_close(state_->db) != SQLITE_OK)
    return sqlite_error(state_->path, state_->db, "cannot close");
  state_->db = nullptr;
  std::error_code error;
  std::filesystem::rename(state_->partial, state_->path, error);
  if (error) return make_error(state_->path, ": cannot rename the package into place: ",
                               error.message());
  state_->partial.clear();
  return {};
}

Result<std::string> read_tiles_package(const std::string& path, std::string_view key) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    Error e = sqlite_error(path, db, "cannot open the package");
    sqlite3_close(db);
    return e;
  }
  sqlite3_stmt* s = nullptr;
  Result<std::string> out = make_error(path, ": no '", key, "' in the package");
  if (sqlite3_prepare_v2(db, "SELECT content FROM media WHERE key = ?", -1, &s, nullptr) !=
      SQLITE_OK) {
    out = sqlite_error(path, db, "not a 3D Tiles package (no media table)");
  } else {
    sqlite3_bind_text(s, 1, key.data(), int(key.size()), SQLITE_STATIC);
    if (sqlite3_step(s) == SQLITE_ROW)
      out = std::string(static_cast<const char*>(sqlite3_column_blob(s, 0)),
                        size_t(sqlite3_column_bytes(s, 0)));
  }
  sqlite3_finalize(s);
  sqlite3_close(db);
  return out;
}

}  // namespace farfield
