#include "farfield/techniques/stratified/stratified_pack.hpp"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <sstream>

namespace farfield::stratified {

namespace {

std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

// The `done` record: which sides exist, and the reference viewcell of delta coding.
struct DoneRecord {
  uint8_t faces = 0;  // bit F: side F has a far field
  std::optional<CellKey> reference;
};

std::vector<std::byte> encode_done(const DoneRecord& d) {
  std::vector<std::byte> out(2 + (d.reference ? 12 : 0));
  out[0] = std::byte(d.faces);
  out[1] = std::byte(d.reference ? 1 : 0);
  if (d.reference) std::memcpy(out.data() + 2, d.reference->at.data(), 12);
  return out;
}

Result<DoneRecord> decode_done(const std::vector<std::byte>& bytes, const std::string& what) {
  DoneRecord d;
  if (bytes.size() < 2 || (bytes[1] != std::byte(0) && bytes[1] != std::byte(1)) ||
      bytes.size() != (bytes[1] == std::byte(1) ? 14u : 2u) || uint8_t(bytes[0]) >= 64)
    return make_error(what, " is not a viewcell record");
  d.faces = uint8_t(bytes[0]);
  if (bytes[1] == std::byte(1)) {
    CellKey k;
    std::memcpy(k.at.data(), bytes.data() + 2, 12);
    d.reference = k;
  }
  return d;
}

Image rgb_of(const FaceImage& face) {
  Image image(face.width, face.height);
  const size_t n = size_t(face.width) * face.height;
  for (size_t i = 0; i < n; ++i)
    std::memcpy(&image.rgb[3 * i], &face.pixels[face.channels * i], 3);
  return image;
}

}  // namespace

std::string to_text(const BakeParams& p) {
  std::string t = "scene=" + std::to_string(p.scene) + "\nalpha=" + number(p.alpha_deg) +
                  "\nregion=";
  for (int i = 0; i < 3; ++i) t += number(p.region.min[i]) + ",";
  for (int i = 0; i < 3; ++i) t += number(p.region.max[i]) + (i < 2 ? "," : "");
  t += "\nshells=";
  for (size_t i = 0; i < p.shells.size(); ++i)
    t += (i ? ";" : "") + number(p.shells[i].box) + ":" + number(p.shells[i].viewcell);
  t += "\nresolution=" + std::to_string(p.resolution) + "\ncodec=" + codec_name(p.codec.codec) +
       "\nquality=" + std::to_string(p.codec.codec == Codec::kJpeg ? p.codec.jpeg_quality : 0) +
       "\ndelta=" + (p.delta ? "1" : "0") + "\n";
  return t;
}

Result<BakeParams> parse_params(const std::string& text) {
  std::map<std::string, std::string> kv;
  std::stringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const size_t eq = line.find('=');
    if (eq == std::string::npos) return make_error("stratified parameters: bad line '", line, "'");
    kv[line.substr(0, eq)] = line.substr(eq + 1);
  }
  for (const char* key : {"scene", "alpha", "region", "shells", "resolution", "codec", "quality",
                          "delta"})
    if (!kv.count(key)) return make_error("stratified parameters: '", key, "' is missing");
  auto bad = [&](const char* key) {
    return make_error("stratified parameters: '", key, "' is malformed ('", kv[key], "')");
  };
  BakeParams p;
  char* end = nullptr;
  p.scene = std::strtoull(kv["scene"].c_str(), &end, 10);
  if (*end) return bad("scene");
  p.alpha_deg = std::strtod(kv["alpha"].c_str(), &end);
  if (*end || !(p.alpha_deg > 0 && p.alpha_deg < 90)) return bad("alpha");
  double r[6];
  if (std::sscanf(kv["region"].c_str(), "%lf,%lf,%lf,%lf,%lf,%lf", &r[0], &r[1], &r[2], &r[3],
                  &r[4], &r[5]) != 6)
    return bad("region");
  p.region = {{float(r[0]), float(r[1]), float(r[2])}, {float(r[3]), float(r[4]), float(r[5])}};
  if (p.region.empty()) return bad("region");
  std::stringstream shells(kv["shells"]);
  std::string shell;
  while (std::getline(shells, shell, ';')) {
    ShellParams s;
    if (std::sscanf(shell.c_str(), "%lf:%lf", &s.box, &s.viewcell) != 2 || !(s.viewcell > 0) ||
        !(s.box >= s.viewcell) || !std::isfinite(s.box))
      return bad("shells");
    p.shells.push_back(s);
  }
  if (p.shells.empty() || p.shells.size() > 16) return bad("shells");
  p.resolution = int(std::strtol(kv["resolution"].c_str(), &end, 10));
  if (*end || p.resolution < 8 || p.resolution > 4096) return bad("resolution");
  const long quality = std::strtol(kv["quality"].c_str(), &end, 10);
  if (kv["codec"] == "jpeg" && quality >= 1 && quality <= 100)
    p.codec = ImageCodec::jpeg(int(quality));
  else if (kv["codec"] == "png")
    p.codec = ImageCodec::png();
  else
    return bad("codec");
  if (kv["delta"] != "0" && kv["delta"] != "1") return bad("delta");
  p.delta = kv["delta"] == "1";
  return p;
}

std::string cell_prefix(int shell, const CellKey& key) {
  return "stratified/s" + std::to_string(shell) + "/" + key.name() + "/";
}

Result<void> write_cell(Store& store, int shell, const CellKey& key, const CellRecord& record,
                        const BakeParams& params, const CellRecord* reference,
                        const std::optional<CellKey>& reference_key) {
  const std::string prefix = cell_prefix(shell, key);
  auto transaction = store.begin();
  if (!transaction) return transaction.error();
  if (shell == 0)
    if (auto ok = store.put(prefix + "near", std::as_bytes(std::span(record.near))); !ok) return ok;
  DoneRecord done;
  done.reference = reference ? reference_key : std::nullopt;
  for (int f = 0; f < kFaces; ++f) {
    const FaceImage& face = record.faces[f];
    if (face.channels == 0) continue;
    done.faces |= uint8_t(1u << f);
    Image image = rgb_of(face);
    if (reference) {
      // paper 000, Sec. 3.1.4: neighbouring viewcells see nearly the same far field; store
      // the byte-wise difference (mod 256), which PNG compresses well and restores exactly.
      const FaceImage& ref = reference->faces[f];
      if (ref.channels == 0 || ref.width != face.width || ref.height != face.height)
        return make_error("delta coding: the reference viewcell has no side ", std::to_string(f));
      const size_t n = size_t(face.width) * face.height;
      for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c)
          image.rgb[3 * i + c] = uint8_t(image.rgb[3 * i + c] - ref.pixels[ref.channels * i + c]);
    }
    const std::string name = prefix + "face" + std::to_string(f);
    // A residual is mostly zeros: zstd's long matches take it smaller than PNG's filters.
    if (auto ok = reference ? store.put(name, std::as_bytes(std::span(image.rgb)), Codec::kZstd)
                            : store.put_image(name, image, params.codec);
        !ok)
      return ok;
    if (face.channels == 4) {
      std::vector<uint8_t> mask(size_t(face.width) * face.height);
      for (size_t i = 0; i < mask.size(); ++i) mask[i] = face.pixels[4 * i + 3];
      if (auto ok = store.put(prefix + "mask" + std::to_string(f), std::as_bytes(std::span(mask)));
          !ok)
        return ok;
    }
  }
  if (auto ok = store.put(prefix + "done", encode_done(done)); !ok) return ok;
  return transaction->commit();
}

namespace {

Result<CellRecord> read_cell_at(const Store& store, int shell, const CellKey& key,
                                const BakeParams& params, uint32_t object_count, int depth) {
  const std::string prefix = cell_prefix(shell, key);
  auto done_bytes = store.get(prefix + "done");
  if (!done_bytes) return done_bytes.error();
  auto done = decode_done(*done_bytes, store.path() + ": blob '" + prefix + "done'");
  if (!done) return done.error();
  CellRecord record;
  if (shell == 0) {
    auto near = store.get(prefix + "near");
    if (!near) return near.error();
    if (near->size() % 4) return make_error(store.path(), ": blob '", prefix, "near' is malformed");
    record.near.resize(near->size() / 4);
    if (!near->empty()) std::memcpy(record.near.data(), near->data(), near->size());
    for (size_t i = 0; i < record.near.size(); ++i)
      if (record.near[i] >= object_count || (i && record.near[i] <= record.near[i - 1]))
        return make_error(store.path(), ": blob '", prefix,
                          "near' names objects the scene does not have");
  }
  std::optional<CellRecord> reference;
  if (done->reference) {
    if (depth > 0 || !params.delta)
      return make_error(store.path(), ": viewcell ", prefix, " refers to another delta-coded one");
    auto ref = read_cell_at(store, shell, *done->reference, params, object_count, depth + 1);
    if (!ref) return ref.error();
    reference = std::move(*ref);
    record.reference = done->reference;
  }
  for (int f = 0; f < kFaces; ++f) {
    if (!(done->faces >> f & 1)) continue;
    const std::string name = prefix + "face" + std::to_string(f);
    Result<Image> image = Image{};
    if (reference) {
      auto bytes = store.get(name);
      if (!bytes) return bytes.error();
      const size_t n = size_t(params.resolution) * size_t(params.resolution) * 3;
      if (bytes->size() != n)
        return make_error(store.path(), ": blob '", name, "' is not a ", std::to_string(params.resolution),
                          " pixel square residual");
      image->width = image->height = params.resolution;
      image->rgb.resize(n);
      std::memcpy(image->rgb.data(), bytes->data(), n);
    } else {
      image = store.get_image(name);
      if (!image) return image.error();
    }
    if (image->width != params.resolution || image->height != params.resolution)
      return make_error(store.path(), ": blob '", name, "' is ", std::to_string(image->width), "x",
                        std::to_string(image->height), ", not the bake's ",
                        std::to_string(params.resolution), " pixels square");
    auto mask_info = store.info(prefix + "mask" + std::to_string(f));
    if (!mask_info) return mask_info.error();
    std::vector<std::byte> mask;
    if (*mask_info) {
      auto m = store.get(prefix + "mask" + std::to_string(f));
      if (!m) return m.error();
      if (m->size() != size_t(image->width) * image->height)
        return make_error(store.path(), ": blob '", prefix, "mask", std::to_string(f),
                          "' does not match its side's size");
      mask = std::move(*m);
    }
    FaceImage& face = record.faces[f];
    face.width = image->width;
    face.height = image->height;
    face.channels = mask.empty() ? 3 : 4;
    const size_t n = size_t(face.width) * face.height;
    face.pixels.resize(n * face.channels);
    const FaceImage* ref = reference ? &reference->faces[f] : nullptr;
    if (ref && (ref->channels == 0 || ref->width != face.width))
      return make_error(store.path(), ": blob '", name, "' refers to a missing side");
    for (size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c)
        face.pixels[face.channels * i + c] =
            uint8_t(image->rgb[3 * i + c] + (ref ? ref->pixels[ref->channels * i + c] : 0));
      if (face.channels == 4) face.pixels[4 * i + 3] = uint8_t(mask[i]);
    }
  }
  return record;
}

}  // namespace

Result<CellRecord> read_cell(const Store& store, int shell, const CellKey& key,
                             const BakeParams& params, uint32_t object_count) {
  return read_cell_at(store, shell, key, params, object_count, 0);
}

Result<std::vector<CellKey>> baked_cells(const Store& store, int shell) {
  auto blobs = store.list("stratified/s" + std::to_string(shell) + "/");
  if (!blobs) return blobs.error();
  std::vector<CellKey> cells;
  for (const BlobInfo& b : *blobs) {
    CellKey k;
    char tail[8] = {};
    int s = -1;
    if (std::sscanf(b.name.c_str(), "stratified/s%d/%7u_%7u_%7u/%7s", &s, &k.at[0], &k.at[1],
                    &k.at[2], tail) == 5 &&
        std::strcmp(tail, "done") == 0)
      cells.push_back(k);
  }
  return cells;
}

}  // namespace farfield::stratified
