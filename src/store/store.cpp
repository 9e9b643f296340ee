#include "farfield/store/store.hpp"

#include <algorithm>
#include <bit>

#include <xxhash.h>

#include "farfield/core/assert.hpp"
#include "farfield/core/codec.hpp"
#include "store_state.hpp"

namespace farfield {

namespace detail {

Result<void> StoreState::write_blob(std::string_view name, Codec codec, uint64_t raw_size,
                                    std::span<const std::byte> stored) {
  FF_ASSERT(!name.empty(), "empty blob name");
  const std::string what = "cannot write blob " + quoted(name);
  if (auto ok = writable(what); !ok) return ok.error();
  const int limit = sqlite3_limit(db, SQLITE_LIMIT_LENGTH, -1);
  if (raw_size > kMaxBlobRawBytes || stored.size() >= size_t(limit))
    return make_error(path, ": ", what, ": ", std::to_string(raw_size), " bytes (",
                      std::to_string(stored.size()), " encoded) are over the limit of ",
                      std::to_string(kMaxBlobRawBytes), " (", std::to_string(limit),
                      " encoded); split it");
  Use use(statements[kPut]);
  sqlite3_stmt* stmt = use.get();
  bind_text(stmt, 1, name);
  sqlite3_bind_int(stmt, 2, int(codec));
  sqlite3_bind_int64(stmt, 3, int64_t(raw_size));
  sqlite3_bind_int64(stmt, 4, std::bit_cast<int64_t>(XXH3_64bits(stored.data(), stored.size())));
  sqlite3_bind_blob64(stmt, 5, stored.empty() ? "" : static_cast<const void*>(stored.data()),
                      stored.size(), SQLITE_STATIC);
  const int rc = sqlite3_step(stmt);
  if (rc != SQLITE_DONE) return error(rc, what);
  return {};
}

template <class T, class Decode>
Result<T> StoreState::read_blob(std::string_view name, Decode&& decode) const {
  const std::string what = "cannot read blob " + quoted(name);
  Use use(statements[kGet]);
  sqlite3_stmt* stmt = use.get();
  bind_text(stmt, 1, name);
  const int rc = sqlite3_step(stmt);
  if (rc == SQLITE_DONE) return make_error(path, ": no blob ", quoted(name));
  if (rc != SQLITE_ROW) return error(rc, what);
  const int64_t codec = sqlite3_column_int64(stmt, 0);
  const int64_t raw_size = sqlite3_column_int64(stmt, 1);
  const uint64_t checksum = std::bit_cast<uint64_t>(sqlite3_column_int64(stmt, 2));
  // A zero-length blob comes back as a null pointer.
  const void* data = sqlite3_column_blob(stmt, 3);
  if (!data && sqlite3_errcode(db) == SQLITE_NOMEM) return error(SQLITE_NOMEM, what);
  const std::span<const std::byte> stored(static_cast<const std::byte*>(data),
                                          data ? size_t(sqlite3_column_bytes(stmt, 3)) : 0);
  if (XXH3_64bits(stored.data(), stored.size()) != checksum)
    return make_error(path, ": blob ", quoted(name), " is corrupted (checksum mismatch)");
  // The checksum covers the data only; the other columns must agree with it.
  auto corrupted = [&](const std::string& why) {
    return make_error(path, ": blob ", quoted(name), " is corrupted (", why, ")");
  };
  if (codec < 0 || codec > int64_t(Codec::kPng))
    return corrupted("unknown codec " + std::to_string(codec));
  if (raw_size < 0 || uint64_t(raw_size) > kMaxBlobRawBytes ||
      (Codec(codec) == Codec::kNone && uint64_t(raw_size) != stored.size()))
    return corrupted("size " + std::to_string(raw_size) + " does not fit its data");
  auto decoded = decode(Codec(codec), uint64_t(raw_size), stored);
  if (!decoded)
    return make_error(path, ": blob ", quoted(name), " cannot be decoded (",
                      decoded.error().message, ")");
  return std::move(decoded).value();
}

Result<BlobInfo> StoreState::blob_info(sqlite3_stmt* stmt) const {
  BlobInfo info;
  info.name = column_text(stmt, 0);
  const int64_t codec = sqlite3_column_int64(stmt, 1);
  const int64_t raw_size = sqlite3_column_int64(stmt, 2);
  if (codec < 0 || codec > int64_t(Codec::kPng) || raw_size < 0)
    return make_error(path, ": blob ", quoted(info.name), " is corrupted (codec ",
                      std::to_string(codec), ", size ", std::to_string(raw_size), ")");
  info.codec = Codec(codec);
  info.raw_size = uint64_t(raw_size);
  info.stored_size = uint64_t(sqlite3_column_int64(stmt, 3));
  return info;
}

}  // namespace detail

using namespace detail;  // the statement helpers of store_state.hpp

const char* codec_name(Codec codec) {
  switch (codec) {
    case Codec::kNone:
      return "none";
    case Codec::kZstd:
      return "zstd";
    case Codec::kJpeg:
      return "jpeg";
    case Codec::kPng:
      return "png";
  }
  return "unknown";
}

Store::Store(std::unique_ptr<StoreState> state) : state_(std::move(state)) {}
Store::Store(Store&&) noexcept = default;
Store& Store::operator=(Store&&) noexcept = default;
Store::~Store() {
  FF_ASSERT(!state_ || !state_->in_transaction, "%s: Store closed inside a Transaction",
            state_->path.c_str());
}

const std::string& Store::path() const {
  return state_->path;
}
Store::Mode Store::mode() const {
  return state_->mode;
}

Result<void> Store::put(std::string_view name, std::span<const std::byte> bytes, Codec codec) {
  FF_ASSERT(codec == Codec::kNone || codec == Codec::kZstd, "blob '%.*s': codec %s for bytes",
            int(name.size()), name.data(), codec_name(codec));
  if (codec == Codec::kNone) return state_->write_blob(name, codec, bytes.size(), bytes);
  const Bytes compressed = zstd_compress(bytes);
  return state_->write_blob(name, codec, bytes.size(), compressed);
}

Result<void> Store::put_image(std::string_view name, const Image& image, ImageCodec codec) {
  FF_ASSERT(is_image(codec.codec), "blob '%.*s': codec %s for an image", int(name.size()),
            name.data(), codec_name(codec.codec));
  auto encoded =
      codec.codec == Codec::kJpeg ? encode_jpeg(image, codec.jpeg_quality) : encode_png(image);
  if (!encoded)
    return make_error(state_->path, ": cannot write blob ", quoted(name), ": ",
                      encoded.error().message);
  return state_->write_blob(name, codec.codec, image.rgb.size(), *encoded);
}

Result<std::vector<std::byte>> Store::get(std::string_view name) const {
  using Stored = std::span<const std::byte>;
  return state_->read_blob<Bytes>(
      name, [](Codec codec, uint64_t raw_size, Stored stored) -> Result<Bytes> {
        if (is_image(codec))
          return make_error("it holds a ", codec_name(codec), " image; read it with get_image");
        if (codec == Codec::kZstd) return zstd_decompress(stored, raw_size);
        return Bytes(stored.begin(), stored.end());
      });
}

Result<void> Store::get_into(std::string_view name, std::span<std::byte> bytes) const {
  using Stored = std::span<const std::byte>;
  auto read = state_->read_blob<bool>(
      name, [&](Codec codec, uint64_t raw_size, Stored stored) -> Result<bool> {
        if (is_image(codec))
          return make_error("it holds a ", codec_name(codec), " image; read it with get_image");
        if (raw_size != bytes.size())
          return make_error("it holds ", std::to_string(raw_size), " bytes, expected ",
                            std::to_string(bytes.size()));
        if (codec == Codec::kZstd) {
          if (auto ok = zstd_decompress_into(stored, bytes); !ok) return ok.error();
        } else {
          std::copy(stored.begin(), stored.end(), bytes.begin());
        }
        return true;
      });
  if (!read) return read.error();
  return {};
}

Result<Image> Store::get_image(std::string_view name) const {
  using Stored = std::span<const std::byte>;
  return state_->read_blob<Image>(
      name, [](Codec codec, uint64_t raw_size, Stored stored) -> Result<Image> {
        if (!is_image(codec))
          return make_error("it holds bytes (", codec_name(codec),
                            "), not an image; read it with get");
        // raw_size bounds the decoder's allocation, then must match what it found.
        const uint64_t pixels = std::min(raw_size / 3, kMaxImagePixels);
        auto image =
            codec == Codec::kJpeg ? decode_jpeg(stored, pixels) : decode_png(stored, pixels);
        if (image && image->rgb.size() != raw_size)
          return make_error("image of ", std::to_string(image->rgb.size()), " bytes, expected ",
                            std::to_string(raw_size));
        return image;
      });
}

Result<std::optional<BlobInfo>> Store::info(std::string_view name) const {
  Use use(state_->statements[kInfo]);
  bind_text(use.get(), 1, name);
  const int rc = sqlite3_step(use.get());
  if (rc == SQLITE_DONE) return std::optional<BlobInfo>();
  if (rc != SQLITE_ROW) return state_->error(rc, "cannot read blob " + quoted(name));
  auto info = state_->blob_info(use.get());
  if (!info) return info.error();
  return std::optional<BlobInfo>(std::move(info).value());
}

Result<bool> Store::contains(std::string_view name) const {
  auto found = info(name);
  if (!found) return found.error();
  return found->has_value();
}

Result<std::vector<BlobInfo>> Store::list(std::string_view prefix) const {
  Use use(state_->statements[kList]);
  std::string end;
  bind_prefix(use.get(), prefix, end);
  std::vector<BlobInfo> blobs;
  int rc;
  while ((rc = sqlite3_step(use.get())) == SQLITE_ROW) {
    auto info = state_->blob_info(use.get());
    if (!info) return info.error();
    blobs.push_back(std::move(info).value());
  }
  if (rc != SQLITE_DONE) return state_->error(rc, "cannot list blobs " + quoted(prefix));
  return blobs;
}

Result<uint64_t> Store::total_bytes(std::string_view prefix) const {
  Use use(state_->statements[kTotal]);
  std::string end;
  bind_prefix(use.get(), prefix, end);
  const int rc = sqlite3_step(use.get());
  if (rc != SQLITE_ROW) return state_->error(rc, "cannot sum blobs " + quoted(prefix));
  return uint64_t(sqlite3_column_int64(use.get(), 0));
}

Result<uint64_t> Store::erase(std::string_view prefix) {
  const std::string what = "cannot erase blobs " + quoted(prefix);
  if (auto ok = state_->writable(what); !ok) return ok.error();
  Use use(state_->statements[kErase]);
  std::string end;
  bind_prefix(use.get(), prefix, end);
  const int rc = sqlite3_step(use.get());
  if (rc != SQLITE_DONE) return state_->error(rc, what);
  return uint64_t(sqlite3_changes64(state_->db));
}

Result<uint64_t> Store::compact() {
  const std::string what = "cannot compact";
  if (auto ok = state_->writable(what); !ok) return ok.error();
  auto free_pages = state_->query_int("PRAGMA freelist_count", what);
  if (!free_pages) return free_pages.error();
  auto pages = state_->query_int("PRAGMA page_count", what);
  if (!pages) return pages.error();
  auto page_size = state_->query_int("PRAGMA page_size", what);
  if (!page_size) return page_size.error();
  if (*free_pages == 0 || *free_pages * 10 < *pages) return uint64_t(0);
  if (auto ok = state_->exec("VACUUM", what); !ok) return ok.error();
  return uint64_t(*free_pages) * uint64_t(*page_size);
}

Result<void> Store::set_meta(std::string_view key, std::string_view value) {
  FF_ASSERT(!key.empty(), "empty meta key");
  const std::string what = "cannot write meta " + quoted(key);
  if (auto ok = state_->writable(what); !ok) return ok.error();
  Use use(state_->statements[kSetMeta]);
  bind_text(use.get(), 1, key);
  bind_text(use.get(), 2, value);
  const int rc = sqlite3_step(use.get());
  if (rc != SQLITE_DONE) return state_->error(rc, what);
  return {};
}

Result<void> Store::erase_meta(std::string_view key) {
  const std::string what = "cannot erase meta " + quoted(key);
  if (auto ok = state_->writable(what); !ok) return ok.error();
  Use use(state_->statements[kEraseMeta]);
  bind_text(use.get(), 1, key);
  const int rc = sqlite3_step(use.get());
  if (rc != SQLITE_DONE) return state_->error(rc, what);
  return {};
}

Result<std::optional<std::string>> Store::get_meta(std::string_view key) const {
  Use use(state_->statements[kGetMeta]);
  bind_text(use.get(), 1, key);
  const int rc = sqlite3_step(use.get());
  if (rc == SQLITE_DONE) return std::optional<std::string>();
  if (rc != SQLITE_ROW) return state_->error(rc, "cannot read meta " + quoted(key));
  return std::optional<std::string>(column_text(use.get(), 0));
}

Result<std::vector<std::pair<std::string, std::string>>> Store::list_meta(
    std::string_view prefix) const {
  Use use(state_->statements[kListMeta]);
  std::string end;
  bind_prefix(use.get(), prefix, end);
  std::vector<std::pair<std::string, std::string>> pairs;
  int rc;
  while ((rc = sqlite3_step(use.get())) == SQLITE_ROW)
    pairs.emplace_back(column_text(use.get(), 0), column_text(use.get(), 1));
  if (rc != SQLITE_DONE) return state_->error(rc, "cannot list meta " + quoted(prefix));
  return pairs;
}

Result<Transaction> Store::begin() {
  FF_ASSERT(!state_->in_transaction, "%s: a Transaction is already open", state_->path.c_str());
  if (auto ok = state_->writable("cannot begin a transaction"); !ok) return ok.error();
  // IMMEDIATE takes the write lock now: a second writer waits (busy timeout) or fails here,
  // not at its first put.
  if (auto ok = state_->exec("BEGIN IMMEDIATE", "cannot begin a transaction"); !ok)
    return ok.error();
  state_->in_transaction = true;
  return Transaction(state_.get());
}

Transaction::~Transaction() {
  if (!state_) return;
  if (!sqlite3_get_autocommit(state_->db)) (void)state_->exec("ROLLBACK", "");
  state_->in_transaction = false;
}

Result<void> Transaction::commit() {
  FF_ASSERT(state_, "commit of a finished Transaction");
  auto ok = state_->exec("COMMIT", "cannot commit");
  // SQLite rolls back by itself after some errors (disk full, I/O); then nothing is open.
  if (ok || sqlite3_get_autocommit(state_->db)) {
    state_->in_transaction = false;
    state_ = nullptr;
  }
  return ok;
}

Result<void> Store::verify() const {
  sqlite3_stmt* stmt = nullptr;
  int rc = sqlite3_prepare_v2(state_->db, "PRAGMA quick_check", -1, &stmt, nullptr);
  if (rc != SQLITE_OK) return state_->error(rc, "cannot check the pack");
  rc = sqlite3_step(stmt);
  const std::string first = rc == SQLITE_ROW ? column_text(stmt, 0) : "";
  sqlite3_finalize(stmt);
  if (rc != SQLITE_ROW) return state_->error(rc, "cannot check the pack");
  if (first != "ok") return make_error(state_->path, ": corrupted pack (", first, ")");

  rc = sqlite3_prepare_v2(state_->db, "SELECT name, checksum, data FROM blobs", -1, &stmt, nullptr);
  if (rc != SQLITE_OK) return state_->error(rc, "cannot check the pack");
  Result<void> result;
  while ((rc = sqlite3_step(stmt)) == SQLITE_ROW) {
    const void* data = sqlite3_column_blob(stmt, 2);
    const size_t size = data ? size_t(sqlite3_column_bytes(stmt, 2)) : 0;
    if (XXH3_64bits(data, size) != std::bit_cast<uint64_t>(sqlite3_column_int64(stmt, 1))) {
      result = make_error(state_->path, ": blob ", quoted(column_text(stmt, 0)),
                          " is corrupted (checksum mismatch)");
      break;
    }
  }
  if (result && rc != SQLITE_DONE) result = state_->error(rc, "cannot check the pack");
  sqlite3_finalize(stmt);
  return result;
}

}  // namespace farfield
