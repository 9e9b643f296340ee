#include "farfield/scene/scene_file.hpp"

#include <gtest/gtest.h>
#include <xxhash.h>

#include <cstring>

#include "test_util.hpp"

namespace farfield {
namespace {

using test::same_bytes;

using test::TempDir;

TEST(SceneFile, RoundTripKeepsEverything) {
  TempDir dir;
  const Scene scene = test::make_box_row(7);
  ASSERT_EQ(validate_scene(scene), "");
  ASSERT_TRUE(write_scene(scene, dir.file("row.ffscene")));
  SceneFileInfo info;
  auto read = read_scene(dir.file("row.ffscene"), &info);
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(info.version, kSceneFileVersion);
  EXPECT_EQ(info.file_bytes, std::filesystem::file_size(dir.file("row.ffscene")));
  EXPECT_TRUE(same_bytes(read->objects, scene.objects));
  EXPECT_TRUE(same_bytes(read->materials, scene.materials));
  EXPECT_TRUE(same_bytes(read->vertices, scene.vertices));
  EXPECT_TRUE(same_bytes(read->indices, scene.indices));
  EXPECT_EQ(read->names, scene.names);
  EXPECT_EQ(read->bounds.min, scene.bounds.min);
  EXPECT_EQ(read->bounds.max, scene.bounds.max);
  EXPECT_EQ(read->object_name(read->objects[3]), "box_3");
  // Only the destination is left: the temporary file was renamed into place.
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"row.ffscene"});
}

TEST(SceneFile, TexturesAndTextureCoordinatesRoundTrip) {
  TempDir dir;
  const Scene scene = test::make_textured_scene(AlphaMode::mask);
  ASSERT_TRUE(write_scene(scene, dir.file("t.ffscene")));
  auto read = read_scene(dir.file("t.ffscene"));
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_TRUE(same_bytes(read->objects, scene.objects));
  EXPECT_TRUE(same_bytes(read->materials, scene.materials));
  EXPECT_TRUE(same_bytes(read->uvs, scene.uvs));
  ASSERT_EQ(read->textures.size(), 1u);
  EXPECT_EQ(read->textures[0].name, "checker.png");
  EXPECT_EQ(read->textures[0].width, 4u);
  EXPECT_EQ(read->textures[0].codec, TextureCodec::png);
  EXPECT_EQ(read->textures[0].encoded, scene.textures[0].encoded);
  EXPECT_EQ(scene_fingerprint(*read), scene_fingerprint(scene));
  // Every truncation of a textured file is refused too.
  const std::string bytes = test::read_file(dir.file("t.ffscene"));
  for (size_t size = 0; size < bytes.size(); size += 11)
    EXPECT_FALSE(parse_scene(std::as_bytes(std::span(bytes.data(), size)), "f")) << size;
}

// A version 1 file (written by farfield before textures, kept in tests/data) still reads, to
// the same scene fingerprint as then, so its bakes stay usable; written again it is version 2.
TEST(SceneFile, Version1FilesStillRead) {
  TempDir dir;
  SceneFileInfo info;
  auto v1 = read_scene(std::string(FARFIELD_SOURCE_DIR) + "/tests/data/tree_v1.ffscene", &info);
  ASSERT_TRUE(v1) << v1.error().message;
  EXPECT_EQ(info.version, 1u);
  EXPECT_EQ(v1->triangle_count(), 632u);
  EXPECT_EQ(scene_fingerprint(*v1), 0x894bed053fea1f6eull);
  ASSERT_TRUE(write_scene(*v1, dir.file("v2.ffscene")));
  auto v2 = read_scene(dir.file("v2.ffscene"), &info);
  ASSERT_TRUE(v2);
  EXPECT_EQ(info.version, kSceneFileVersion);
  EXPECT_EQ(scene_fingerprint(*v2), 0x894bed053fea1f6eull);
}

// The file with one more section after the table: a later version's addition.
std::string with_extra_section(const std::string& file, const char* tag, uint32_t flags) {
  uint32_t count;
  std::memcpy(&count, file.data() + 40, 4);
  const size_t old_start = (64 + count * 48 + 63) / 64 * 64;
  const size_t new_start = (64 + (count + 1) * 48 + 63) / 64 * 64;
  std::string out = file.substr(0, 64 + count * 48);
  std::string entry(48, '\0');
  std::memcpy(entry.data(), tag, std::strlen(tag));
  const uint64_t offset = file.size() - old_start + new_start, size = 8, element = 1;
  const std::string payload = "12345678";
  const uint64_t checksum = XXH3_64bits(payload.data(), payload.size());
  std::memcpy(entry.data() + 16, &offset, 8);
  std::memcpy(entry.data() + 24, &size, 8);
  std::memcpy(entry.data() + 32, &checksum, 8);
  std::memcpy(entry.data() + 40, &element, 4);
  std::memcpy(entry.data() + 44, &flags, 4);
  out += entry;
  out.resize(new_start, '\0');
  out += file.substr(old_start);
  out += payload + std::string(56, '\0');
  for (uint32_t i = 0; i < count; ++i) {  // the old sections moved by the table's growth
    uint64_t at;
    std::memcpy(&at, out.data() + 64 + i * 48 + 16, 8);
    at += new_start - old_start;
    std::memcpy(out.data() + 64 + i * 48 + 16, &at, 8);
  }
  ++count;
  std::memcpy(out.data() + 40, &count, 4);
  const uint64_t file_size = out.size();
  std::memcpy(out.data() + 48, &file_size, 8);
  test::reseal_scene_header(out);
  return out;
}

// Version 2 (before cells) has version 3's layout without the cell sections: still read, to the
// same fingerprint.
TEST(SceneFile, Version2FilesStillRead) {
  TempDir dir;
  const Scene scene = test::make_textured_scene();
  ASSERT_TRUE(write_scene(scene, dir.file("t.ffscene")));
  std::string file = test::read_file(dir.file("t.ffscene"));
  const uint32_t version = 2;
  std::memcpy(file.data() + 8, &version, 4);
  uint32_t count;
  std::memcpy(&count, file.data() + 40, 4);
  test::reseal_scene_header(file);
  SceneFileInfo info;
  auto read = parse_scene(std::as_bytes(std::span(file.data(), file.size())), "v2", true, &info);
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(info.version, 2u);
  EXPECT_EQ(scene_fingerprint(*read), scene_fingerprint(scene));
}

TEST(SceneFile, UnknownSectionsAreSkippedUnlessRequired) {
  TempDir dir;
  const Scene scene = test::make_textured_scene();
  ASSERT_TRUE(write_scene(scene, dir.file("t.ffscene")));
  const std::string file = test::read_file(dir.file("t.ffscene"));
  const std::string optional = with_extra_section(file, "wormholes", 0);
  auto read = parse_scene(std::as_bytes(std::span(optional.data(), optional.size())), "f");
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(scene_fingerprint(*read), scene_fingerprint(scene));
  const std::string required = with_extra_section(file, "wormholes", 1);
  read = parse_scene(std::as_bytes(std::span(required.data(), required.size())), "f");
  ASSERT_FALSE(read);
  EXPECT_NE(read.error().message.find("needs a newer farfield"), std::string::npos)
      << read.error().message;
  EXPECT_NE(read.error().message.find("wormholes"), std::string::npos);
}

TEST(SceneFile, SameSceneGivesSameBytes) {
  TempDir dir;
  ASSERT_TRUE(write_scene(test::make_box_row(3), dir.file("a.ffscene")));
  ASSERT_TRUE(write_scene(test::make_box_row(3), dir.file("b.ffscene")));
  EXPECT_EQ(test::read_file(dir.file("a.ffscene")), test::read_file(dir.file("b.ffscene")));
}

TEST(SceneFile, EveryTruncationIsRefused) {
  TempDir dir;
  ASSERT_TRUE(write_scene(test::make_box_row(2), dir.file("full.ffscene")));
  const std::string bytes = test::read_file(dir.file("full.ffscene"));
  for (size_t size = 0; size < bytes.size(); size += 7) {
    const std::string path = dir.file("cut.ffscene");
    test::write_file(path, bytes.substr(0, size));
    auto read = read_scene(path);
    ASSERT_FALSE(read) << "accepted a file cut to " << size << " bytes";
    EXPECT_NE(read.error().message.find(path), std::string::npos);
    if (size >= 8) {
      EXPECT_NE(read.error().message.find("truncated"), std::string::npos) << size;
    }
  }
}

TEST(SceneFile, EveryBitFlipIsRefused) {
  TempDir dir;
  ASSERT_TRUE(write_scene(test::make_box_row(2), dir.file("full.ffscene")));
  const std::string bytes = test::read_file(dir.file("full.ffscene"));
  const Scene original = test::make_box_row(2);
  size_t accepted = 0;
  for (size_t byte = 0; byte < bytes.size(); byte += 3) {
    std::string flipped = bytes;
    flipped[byte] = static_cast<char>(flipped[byte] ^ (1 << (byte % 8)));
    auto parsed = parse_scene(std::as_bytes(std::span(flipped.data(), flipped.size())), "f");
    if (parsed) {
      // Only padding between sections is outside the checksums: a flip there must leave the
      // scene exactly as written, or the reader took damaged data.
      ++accepted;
      EXPECT_TRUE(test::same_bytes(parsed->objects, original.objects) &&
                  test::same_bytes(parsed->materials, original.materials) &&
                  test::same_bytes(parsed->vertices, original.vertices) &&
                  test::same_bytes(parsed->indices, original.indices) &&
                  parsed->names == original.names)
          << "a flip of byte " << byte << " was read as a different scene";
      continue;
    }
    EXPECT_TRUE(parsed.error().message.find("corrupted") != std::string::npos ||
                parsed.error().message.find("not a .ffscene") != std::string::npos ||
                parsed.error().message.find("version") != std::string::npos ||
                parsed.error().message.find("truncated") != std::string::npos)
        << parsed.error().message;
  }
  EXPECT_LT(accepted, bytes.size() / 3 / 4) << "most of the file is outside the checksums";
  // A flip in the vertex data is named as a checksum mismatch of that section.
  std::string flipped = bytes;
  auto read = parse_scene(std::as_bytes(std::span(flipped.data(), flipped.size())), "f");
  ASSERT_TRUE(read);
  flipped[flipped.size() - 64 - 50] ^= 1;  // inside a section near the end, not padding
  read = parse_scene(std::as_bytes(std::span(flipped.data(), flipped.size())), "f");
  ASSERT_FALSE(read);
  EXPECT_NE(read.error().message.find("checksum mismatch"), std::string::npos)
      << read.error().message;
}

TEST(SceneFile, MissingEmptyAndForeignFilesAreRefused) {
  TempDir dir;
  auto missing = read_scene(dir.file("nope.ffscene"));
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("nope.ffscene"), std::string::npos);
  test::write_file(dir.file("empty.ffscene"), "");
  auto empty = read_scene(dir.file("empty.ffscene"));
  ASSERT_FALSE(empty);
  EXPECT_NE(empty.error().message.find("empty"), std::string::npos);
  test::write_file(dir.file("text.ffscene"), std::string(300, 'x'));
  auto text = read_scene(dir.file("text.ffscene"));
  ASSERT_FALSE(text);
  EXPECT_NE(text.error().message.find("not a .ffscene file"), std::string::npos);
  auto folder = read_scene(dir.path().string());
  ASSERT_FALSE(folder);
}

TEST(SceneFile, StructureIsCheckedBehindTheChecksums) {
  TempDir dir;
  ASSERT_TRUE(write_scene(test::make_box_row(2), dir.file("full.ffscene")));
  std::string bytes = test::read_file(dir.file("full.ffscene"));
  // The section table starts at byte 64, 48 bytes an entry: {tag[16], offset, bytes,
  // checksum, element size, flags}; the indices are the second section.
  uint64_t index_offset;
  std::memcpy(&index_offset, bytes.data() + 64 + 1 * 48 + 16, sizeof(index_offset));
  ASSERT_EQ(std::string(bytes.data() + 64 + 1 * 48), "indices");
  const uint32_t far_away = 1000;
  std::memcpy(bytes.data() + index_offset, &far_away, sizeof(far_away));
  const auto span = std::as_bytes(std::span(bytes.data(), bytes.size()));
  auto checked = parse_scene(span, "f", true);
  ASSERT_FALSE(checked);
  EXPECT_NE(checked.error().message.find("indices section checksum"), std::string::npos);
  auto unchecked = parse_scene(span, "f", false);
  ASSERT_FALSE(unchecked);
  EXPECT_NE(unchecked.error().message.find("invalid .ffscene contents"), std::string::npos)
      << unchecked.error().message;
}

TEST(SceneFile, InvalidSceneIsNotWritten) {
  TempDir dir;
  Scene scene = test::make_box_row(2);
  scene.indices[0] = 1000;
  EXPECT_NE(validate_scene(scene), "");
  EXPECT_FALSE(write_scene(scene, dir.file("bad.ffscene")));
  EXPECT_TRUE(dir.entries().empty());
}

TEST(SceneFile, FailedWriteLeavesNothing) {
  TempDir dir;
  auto ok = write_scene(test::make_box_row(1), dir.file("no/such/folder/x.ffscene"));
  ASSERT_FALSE(ok);
  EXPECT_NE(ok.error().message.find("x.ffscene"), std::string::npos);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(SceneFile, WriteReplacesAnExistingFileAtomically) {
  TempDir dir;
  const std::string path = dir.file("s.ffscene");
  ASSERT_TRUE(write_scene(test::make_box_row(1), path));
  ASSERT_TRUE(write_scene(test::make_box_row(4), path));
  auto read = read_scene(path);
  ASSERT_TRUE(read);
  EXPECT_EQ(read->objects.size(), 4u);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"s.ffscene"});
}

}  // namespace
}  // namespace farfield
