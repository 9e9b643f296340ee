#include "store_state.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace farfield {

namespace {

// The schema of version 1. open() compares a pack's schema with these texts verbatim, so a
// file with extra tables, triggers or views (which could run arbitrary SQL on every read) is
// refused. STRICT makes SQLite enforce the column types on write.
constexpr const char* kCreateMeta =
    "CREATE TABLE meta(key TEXT PRIMARY KEY NOT NULL, value TEXT NOT NULL) STRICT";
constexpr const char* kCreateBlobs =
    "CREATE TABLE blobs(name TEXT PRIMARY KEY NOT NULL, codec INTEGER NOT NULL, "
    "raw_size INTEGER NOT NULL, checksum INTEGER NOT NULL, data BLOB NOT NULL) STRICT";

// 16 KiB pages: measured on 1000 blobs of 20..200 KB, reads take half the time of 4 KiB
// pages for 2.6% of space (the last page of each blob is half empty on average; 64 KiB pages
// read no faster and waste 11%).
constexpr int kPageSize = 16384;

constexpr std::array<const char*, detail::kStatementCount> kStatementSql = {
    "INSERT OR REPLACE INTO blobs(name, codec, raw_size, checksum, data) VALUES(?1,?2,?3,?4,?5)",
    "SELECT codec, raw_size, checksum, data FROM blobs WHERE name = ?1",
    // length() of a blob reads the record header only, not the blob's overflow pages.
    "SELECT name, codec, raw_size, length(data) FROM blobs WHERE name = ?1",
    "SELECT name, codec, raw_size, length(data) FROM blobs WHERE name >= ?1 AND name < ?2 "
    "ORDER BY name",
    "SELECT coalesce(sum(length(data)), 0) FROM blobs WHERE name >= ?1 AND name < ?2",
    "DELETE FROM blobs WHERE name >= ?1 AND name < ?2",
    "INSERT OR REPLACE INTO meta(key, value) VALUES(?1, ?2)",
    "SELECT value FROM meta WHERE key = ?1",
    "SELECT key, value FROM meta WHERE key >= ?1 AND key < ?2 ORDER BY key",
    "DELETE FROM meta WHERE key = ?1",
};

// When SQLite finds a database shorter than its header says, says by how much: the header's
// page count is valid when its "version-valid-for" number equals the change counter.
std::string truncation_note(const std::string& path) {
  uint8_t header[100] = {};
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";
  struct stat st {};
  const bool read = ::fstat(fd, &st) == 0 && ::pread(fd, header, sizeof(header), 0) == 100;
  ::close(fd);
  if (!read) return "";
  auto be32 = [&](int at) {
    return uint32_t(header[at]) << 24 | uint32_t(header[at + 1]) << 16 |
           uint32_t(header[at + 2]) << 8 | header[at + 3];
  };
  const uint32_t page_size = header[16] << 8 | header[17];
  const uint64_t expected = uint64_t(page_size == 1 ? 65536 : page_size) * be32(28);
  if (be32(24) != be32(92) || expected <= uint64_t(st.st_size)) return "";
  return "; truncated: " + std::to_string(st.st_size) + " of " + std::to_string(expected) +
         " bytes";
}

}  // namespace

namespace detail {

StoreState::~StoreState() {
  for (sqlite3_stmt* stmt : statements) sqlite3_finalize(stmt);
  sqlite3_close_v2(db);  // rolls back an open transaction
}

Error StoreState::error(int rc, std::string_view what) const {
  const char* detail = db ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
  switch (rc & 0xFF) {
    case SQLITE_NOTADB:
      return make_error(path, ": not a farfield pack (not an SQLite database)");
    case SQLITE_CORRUPT:
      return make_error(path, ": corrupted pack (", what, ": ", detail, truncation_note(path),
                        ")");
    case SQLITE_BUSY:
      return make_error(path, ": ", what, ": the pack is locked by another writer (waited ",
                        std::to_string(kBusyTimeoutMs / 1000), " s)");
    case SQLITE_READONLY:
      if (rc == SQLITE_READONLY_ROLLBACK)
        return make_error(path, ": a write to this pack was interrupted; open it for writing "
                                "once (e.g. resume the bake) to roll that write back");
      break;
  }
  return make_error(path, ": ", what, ": ", detail);
}

// Reading the header is the first read of the file: SQLite refuses here what is not a
// database (NOTADB) and a database shorter than its header says (CORRUPT).
Result<void> StoreState::check_header() {
  auto application_id = query_int("PRAGMA application_id", "cannot read the header");
  if (!application_id) return application_id.error();
  if (uint32_t(*application_id) != kStoreApplicationId) {
    char hex[16];
    std::snprintf(hex, sizeof(hex), "0x%08x", unsigned(uint32_t(*application_id)));
    return make_error(path, ": not a farfield pack (an SQLite database with application_id ",
                      hex, ")");
  }
  auto version = query_int("PRAGMA user_version", "cannot read the header");
  if (!version) return version.error();
  if (*version > kStoreSchemaVersion)
    return make_error(path, ": pack schema version ", std::to_string(*version),
                      " is newer than this build reads (", std::to_string(kStoreSchemaVersion),
                      "); update farfield");
  if (*version < kStoreSchemaVersion)
    return make_error(path, ": unknown pack schema version ", std::to_string(*version));

  // Exactly our tables and their primary-key indexes, in name order.
  const std::array<std::array<const char*, 3>, 4> expected = {{
      {"table", "blobs", kCreateBlobs},
      {"table", "meta", kCreateMeta},
      {"index", "sqlite_autoindex_blobs_1", ""},
      {"index", "sqlite_autoindex_meta_1", ""},
  }};
  sqlite3_stmt* stmt = nullptr;
  int rc = sqlite3_prepare_v2(db, "SELECT type, name, coalesce(sql, '') FROM sqlite_schema "
                              "ORDER BY name", -1, &stmt, nullptr);
  if (rc != SQLITE_OK) return error(rc, "cannot read the schema");
  size_t rows = 0;
  bool same = true;
  while ((rc = sqlite3_step(stmt)) == SQLITE_ROW) {
    for (int c = 0; c < 3 && rows < expected.size(); ++c)
      same = same && column_text(stmt, c) == expected[rows][c];
    ++rows;
  }
  sqlite3_finalize(stmt);
  if (rc != SQLITE_DONE) return error(rc, "cannot read the schema");
  if (!same || rows != expected.size())
    return make_error(path, ": corrupted pack (its tables are not those of schema version ",
                      std::to_string(kStoreSchemaVersion), ")");
  return {};
}

Result<void> StoreState::create_schema() {
  // page_size applies while the database has no page yet; the rest is one transaction, so a
  // crash leaves an empty file (which the next open creates again) or a complete schema.
  if (auto ok = exec(("PRAGMA page_size = " + std::to_string(kPageSize)).c_str(),
                     "cannot create the pack");
      !ok)
    return ok;
  if (auto ok = exec("BEGIN IMMEDIATE", "cannot create the pack"); !ok) return ok;
  // Another process may have created it between our stat() and the lock.
  auto tables = query_int("SELECT count(*) FROM sqlite_schema", "cannot create the pack");
  if (!tables) return tables.error();
  if (*tables != 0) {
    (void)exec("ROLLBACK", "");
    return check_header();
  }
  const std::string sql = "PRAGMA application_id = " + std::to_string(kStoreApplicationId) +
                          "; PRAGMA user_version = " + std::to_string(kStoreSchemaVersion) +
                          "; " + kCreateMeta + "; " + kCreateBlobs + "; COMMIT";
  if (auto ok = exec(sql.c_str(), "cannot create the pack"); !ok) {
    (void)exec("ROLLBACK", "");
    return ok;
  }
  return {};
}

Result<void> StoreState::prepare() {
  for (int i = 0; i < kStatementCount; ++i) {
    const int rc = sqlite3_prepare_v3(db, kStatementSql[i], -1, SQLITE_PREPARE_PERSISTENT,
                                      &statements[i], nullptr);
    if (rc != SQLITE_OK) return error(rc, "cannot read the schema");
  }
  return {};
}

}  // namespace detail

Result<Store> Store::open(const std::string& path, Mode mode) {
  struct stat st {};
  const bool exists = ::stat(path.c_str(), &st) == 0;
  if (!exists && (errno != ENOENT || mode == Mode::kRead))
    return make_error(path, ": cannot open: ", std::strerror(errno));
  if (exists && !S_ISREG(st.st_mode)) return make_error(path, ": not a regular file");
  const bool fresh = !exists || st.st_size == 0;
  if (fresh && mode == Mode::kRead) return make_error(path, ": not a farfield pack (empty file)");

  auto state = std::make_unique<detail::StoreState>();
  state->path = path;
  state->mode = mode;
  // NOMUTEX: a Store is used by one thread at a time (see the header), so SQLite's own
  // per-connection mutex would only cost.
  const int flags = (mode == Mode::kRead ? SQLITE_OPEN_READONLY
                                         : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE) |
                    SQLITE_OPEN_NOMUTEX | SQLITE_OPEN_EXRESCODE;
  int rc = sqlite3_open_v2(path.c_str(), &state->db, flags, nullptr);
  if (rc != SQLITE_OK) return state->error(rc, "cannot open");
  if (mode == Mode::kReadWrite && sqlite3_db_readonly(state->db, "main") == 1)
    return make_error(path, ": cannot open for writing (the file is read-only)");
  sqlite3_busy_timeout(state->db, kBusyTimeoutMs);
  // A pack is data, not code: no schema-defined functions, no writes to sqlite_schema, and
  // each page's cells are bounds-checked as they are read (catches damage earlier, ~free).
  sqlite3_db_config(state->db, SQLITE_DBCONFIG_DEFENSIVE, 1, nullptr);
  sqlite3_db_config(state->db, SQLITE_DBCONFIG_TRUSTED_SCHEMA, 0, nullptr);
  if (auto ok = state->exec("PRAGMA cell_size_check = ON", "cannot open"); !ok) return ok.error();

  if (auto ok = fresh ? state->create_schema() : state->check_header(); !ok) return ok.error();
  if (mode == Mode::kReadWrite) {
    // Rollback journal, synced in full: see docs/ffpack.md, "Transactions".
    if (auto ok = state->exec("PRAGMA journal_mode = DELETE; PRAGMA synchronous = FULL",
                              "cannot open for writing");
        !ok)
      return ok.error();
  }
  if (auto ok = state->prepare(); !ok) return ok.error();
  return Store(std::move(state));
}

}  // namespace farfield
