#include "scene_file_layout.hpp"

#include <xxhash.h>

#include <algorithm>
#include <cstring>
#include <string_view>
#include <vector>

#include "farfield/scene/instances.hpp"

namespace farfield::scene_file {

uint64_t header_checksum(const HeaderV2& h, std::span<const SectionEntryV2> table) {
  XXH3_state_t* state = XXH3_createState();
  XXH3_64bits_reset(state);
  XXH3_64bits_update(state, &h, offsetof(HeaderV2, header_checksum));
  XXH3_64bits_update(state, table.data(), table.size_bytes());
  const uint64_t hash = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  return hash;
}

Error truncated(const std::string& name, uint64_t have, uint64_t want) {
  return make_error(name, ": truncated .ffscene file (", std::to_string(have), " of ",
                    std::to_string(want), " bytes)");
}

Error corrupted(const std::string& name, const std::string& what) {
  return make_error(name, ": corrupted .ffscene file (", what, ")");
}

namespace {

std::string tag_text(const SectionEntryV2& e) {
  return std::string(e.tag, strnlen(e.tag, sizeof e.tag));
}

template <class T>
Result<void> read_array(std::vector<T>& out, const SectionEntryV2& e, const ReadAt& read) {
  out.resize(e.bytes / sizeof(T));
  return e.bytes ? read(out.data(), e.bytes, e.offset) : Result<void>{};
}

}  // namespace

Result<SectionTable> read_section_table(const char* head, uint64_t file_size,
                                        const std::string& name, const ReadAt& read) {
  SectionTable t;
  HeaderV2& h = t.header;
  std::memcpy(&h, head, sizeof h);
  if (h.header_size != sizeof(HeaderV2) || h.section_count > kMaxSections)
    return make_error(name, ": corrupted .ffscene header");
  const uint64_t table_end = sizeof(HeaderV2) + uint64_t(h.section_count) * sizeof(SectionEntryV2);
  if (file_size < table_end) return truncated(name, file_size, table_end);
  t.entries.resize(h.section_count);
  if (auto ok = read(t.entries.data(), t.entries.size() * sizeof(SectionEntryV2), sizeof(HeaderV2));
      !ok)
    return ok.error();
  if (header_checksum(h, t.entries) != h.header_checksum)
    return make_error(name, ": corrupted .ffscene header (checksum mismatch)");
  if (h.file_size != file_size) {
    if (file_size < h.file_size) {
      Error e = truncated(name, file_size, h.file_size);
      // Name what is lost, so that a copy cut short is recognised for what it is.
      for (const SectionEntryV2& s : t.entries)
        if (s.offset + s.bytes > file_size) {
          e.message += ": the " + tag_text(s) + " section and what follows it are missing";
          break;
        }
      return e;
    }
    return make_error(name, ": .ffscene file has ", std::to_string(file_size - h.file_size),
                      " unexpected trailing bytes");
  }

  // Find the known sections; check every one's place in the file.
  for (const SectionEntryV2& e : t.entries) {
    const std::string tag = tag_text(e);
    if (e.offset < table_end || e.offset > file_size || e.bytes > file_size - e.offset ||
        e.bytes > kMaxSectionBytes)
      return corrupted(name, tag + " section out of bounds");
    const auto* known = std::find(std::begin(kTagNames), std::end(kTagNames), tag);
    if (known == std::end(kTagNames)) {
      if (e.flags & kRequired)
        return make_error(name, ": needs a newer farfield (it holds a '", tag,
                          "' section this build does not know)");
      continue;
    }
    const int k = int(known - std::begin(kTagNames));
    if (t.found[k]) return corrupted(name, "two " + tag + " sections");
    if (e.element_size != kTagElementSize[k] || e.bytes % kTagElementSize[k] != 0)
      return corrupted(name, tag + " section of the wrong element size");
    t.found[k] = &e;
  }
  // The room left after the table for more entries is zeros: a flip there is damage too.
  uint64_t first_section = file_size;
  for (const SectionEntryV2& e : t.entries) first_section = std::min(first_section, e.offset);
  if (first_section > table_end && first_section - table_end <= 4096) {
    std::vector<char> gap(first_section - table_end);
    if (auto ok = read(gap.data(), gap.size(), table_end); !ok) return ok.error();
    if (std::any_of(gap.begin(), gap.end(), [](char c) { return c != 0; }))
      return corrupted(name, "bytes after the section table are not zeros");
  }
  for (int k : {kObjects, kMaterials, kVertices, kIndices, kNames})
    if (!t.found[k]) return corrupted(name, std::string("no ") + kTagNames[k] + " section");
  if (t.count(kVertices) > UINT32_MAX || t.count(kIndices) > UINT32_MAX ||
      t.count(kNames) > UINT32_MAX || t.count(kUvs) > UINT32_MAX)
    return corrupted(name, "counts beyond 32-bit ranges");
  const bool any_texture = t.found[kTextures] || t.found[kTextureNames] || t.found[kImages];
  if (any_texture && !(t.found[kTextures] && t.found[kTextureNames] && t.found[kImages]))
    return corrupted(name, "texture sections incomplete");
  const bool any_cell =
      t.found[kCells] || t.found[kCellObjects] || t.found[kPortals] || t.found[kPortalPoints];
  if (any_cell &&
      !(t.found[kCells] && t.found[kCellObjects] && t.found[kPortals] && t.found[kPortalPoints]))
    return corrupted(name, "cell and portal sections incomplete");
  if (t.found[kFingerprint] && t.count(kFingerprint) != 1)
    return corrupted(name, "fingerprint section of another size than one");
  return t;
}

Result<void> read_index_sections(const SectionTable& table, Scene& scene, const std::string& name,
                                 bool verify, const ReadAt& read) {
  const auto& found = table.found;
  std::string texture_names;
  std::vector<TextureEntry> textures;
  std::vector<std::byte> images;
  auto verify_section = [&](int t, const void* data) -> Result<void> {
    if (verify && XXH3_64bits(data, found[t]->bytes) != found[t]->checksum)
      return corrupted(name, std::string(kTagNames[t]) + " section checksum mismatch");
    return {};
  };
  Result<void> ok = read_array(scene.objects, *found[kObjects], read);
  if (ok) ok = verify_section(kObjects, scene.objects.data());
  if (ok) ok = read_array(scene.materials, *found[kMaterials], read);
  if (ok) ok = verify_section(kMaterials, scene.materials.data());
  if (ok) {
    scene.names.resize(found[kNames]->bytes);
    if (found[kNames]->bytes)
      ok = read(scene.names.data(), found[kNames]->bytes, found[kNames]->offset);
  }
  if (ok) ok = verify_section(kNames, scene.names.data());
  if (ok && found[kCells]) {
    ok = read_array(scene.cells, *found[kCells], read);
    if (ok) ok = verify_section(kCells, scene.cells.data());
    if (ok) ok = read_array(scene.cell_objects, *found[kCellObjects], read);
    if (ok) ok = verify_section(kCellObjects, scene.cell_objects.data());
    if (ok) ok = read_array(scene.portals, *found[kPortals], read);
    if (ok) ok = verify_section(kPortals, scene.portals.data());
    if (ok) ok = read_array(scene.portal_points, *found[kPortalPoints], read);
    if (ok) ok = verify_section(kPortalPoints, scene.portal_points.data());
  }
  if (ok && found[kInstances]) {
    ok = read_array(scene.instances, *found[kInstances], read);
    if (ok) ok = verify_section(kInstances, scene.instances.data());
  }
  if (ok && found[kTextures]) {
    ok = read_array(textures, *found[kTextures], read);
    if (ok) ok = verify_section(kTextures, textures.data());
    if (ok) {
      texture_names.resize(found[kTextureNames]->bytes);
      if (!texture_names.empty())
        ok = read(texture_names.data(), texture_names.size(), found[kTextureNames]->offset);
    }
    if (ok) ok = verify_section(kTextureNames, texture_names.data());
    if (ok) ok = read_array(images, *found[kImages], read);
    if (ok) ok = verify_section(kImages, images.data());
  }
  if (!ok) return ok.error();

  for (size_t i = 0; i < textures.size(); ++i) {
    const TextureEntry& e = textures[i];
    if (e.image_offset > images.size() || e.image_bytes > images.size() - e.image_offset ||
        uint64_t(e.name_offset) + e.name_size > texture_names.size())
      return corrupted(name, "texture " + std::to_string(i) + " out of range");
    Texture t;
    t.name = texture_names.substr(e.name_offset, e.name_size);
    t.codec = TextureCodec(e.codec);
    t.width = e.width;
    t.height = e.height;
    t.has_alpha = e.has_alpha != 0;
    t.encoded.assign(images.begin() + ptrdiff_t(e.image_offset),
                     images.begin() + ptrdiff_t(e.image_offset + e.image_bytes));
    scene.textures.push_back(std::move(t));
  }
  const HeaderV2& h = table.header;
  scene.bounds.min = {h.bounds_min[0], h.bounds_min[1], h.bounds_min[2]};
  scene.bounds.max = {h.bounds_max[0], h.bounds_max[1], h.bounds_max[2]};
  return {};
}

Result<std::vector<SceneChunk>> read_chunk_table(const SectionTable& table, const Scene& index,
                                                 const std::string& name, bool verify,
                                                 const ReadAt& read) {
  std::vector<SceneChunk> chunks;
  if (!table.found[kChunks]) return chunks;
  if (auto ok = read_array(chunks, *table.found[kChunks], read); !ok) return ok.error();
  if (verify && XXH3_64bits(chunks.data(), table.found[kChunks]->bytes) !=
                    table.found[kChunks]->checksum)
    return corrupted(name, "chunks section checksum mismatch");
  // Consecutive, without gaps, over everything; each object inside its chunk's ranges.
  uint64_t object = 0, vertex = 0, index_at = 0, uv = 0;
  for (size_t c = 0; c < chunks.size(); ++c) {
    const SceneChunk& k = chunks[c];
    auto bad = [&](const std::string& what) {
      return corrupted(name, "chunk " + std::to_string(c) + " " + what);
    };
    if (k.first_object != object || k.first_vertex != vertex || k.first_index != index_at ||
        k.first_uv != uv)
      return bad("does not start where the one before it ends");
    if (k.object_count == 0) return bad("holds no object");
    if (k.index_count % 3 != 0) return bad("holds part of a triangle");
    object += k.object_count;
    vertex += k.vertex_count;
    index_at += k.index_count;
    uv += k.uv_count;
    if (object > index.objects.size()) return bad("runs past the last object");
    for (uint64_t i = k.first_object; i < object; ++i) {
      const Object& o = index.objects[i];
      if (instance_of(index, uint32_t(i))) continue;  // its ranges are its prototype's
      const bool textured = o.material < index.materials.size() && index.textured(o);
      if (o.first_vertex < k.first_vertex || uint64_t(o.first_vertex) + o.vertex_count > vertex ||
          o.first_index < k.first_index || uint64_t(o.first_index) + o.index_count > index_at ||
          (textured &&
           (o.first_uv < k.first_uv || uint64_t(o.first_uv) + o.vertex_count > uv)))
        return bad("does not hold the geometry of its object " + std::to_string(i));
    }
  }
  if (object != index.objects.size() || vertex != table.count(kVertices) ||
      index_at != table.count(kIndices) || uv != table.count(kUvs))
    return corrupted(name, "chunks do not cover the scene");
  return chunks;
}

}  // namespace farfield::scene_file
