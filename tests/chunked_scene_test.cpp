// The .ffscene's chunks: written in parts (SceneFileWriter, write_city) to the same bytes as a
// whole write, read a chunk at a time (ChunkedScene), damage named by chunk.
#include "farfield/scene/chunked_scene.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <random>

#include "farfield/core/camera_path.hpp"
#include "farfield/core/progress.hpp"
#include "farfield/scene/city_generator.hpp"
#include "farfield/scene/scene_file_writer.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using test::TempDir;

CityOptions small_city(bool textures) {
  CityOptions o;
  o.blocks_x = o.blocks_z = 3;
  o.textures = textures;
  return o;
}

Scene city(bool textures) {
  Progress quiet(true);
  auto scene = generate_city(small_city(textures), quiet);
  EXPECT_TRUE(scene) << scene.error().message;
  return std::move(*scene);
}

// Objects [first, first + count) of `s` as a scene of their own (offsets from its start).
Scene part_of(const Scene& s, uint32_t first, uint32_t count) {
  Scene part;
  part.materials = s.materials;
  part.textures = s.textures;
  const Object& a = s.objects[first];
  const Object& z = s.objects[first + count - 1];
  const uint32_t v0 = a.first_vertex, i0 = a.first_index, n0 = a.name_offset;
  uint32_t u0 = UINT32_MAX, u1 = 0;
  for (uint32_t k = first; k < first + count; ++k)
    if (s.textured(s.objects[k])) {
      u0 = std::min(u0, s.objects[k].first_uv);
      u1 = std::max(u1, s.objects[k].first_uv + s.objects[k].vertex_count);
    }
  if (u0 == UINT32_MAX) u0 = u1 = 0;
  part.vertices.assign(s.vertices.begin() + v0, s.vertices.begin() + z.first_vertex + z.vertex_count);
  part.indices.assign(s.indices.begin() + i0, s.indices.begin() + z.first_index + z.index_count);
  for (uint32_t& index : part.indices) index -= v0;
  part.uvs.assign(s.uvs.begin() + u0, s.uvs.begin() + u1);
  part.names = s.names.substr(n0, z.name_offset + z.name_size - n0);
  for (uint32_t k = first; k < first + count; ++k) {
    Object o = s.objects[k];
    o.first_vertex -= v0;
    o.first_index -= i0;
    o.name_offset -= n0;
    if (s.textured(o)) o.first_uv -= u0;
    part.objects.push_back(o);
  }
  return part;
}

TEST(SceneFileWriter, PartsMakeTheSameFile) {
  TempDir dir;
  for (bool textures : {false, true}) {
    const Scene scene = city(textures);
    ASSERT_EQ(scene.uvs.empty(), !textures);
    ASSERT_TRUE(write_scene(scene, dir.file("whole.ffscene")));
    const std::string whole = test::read_file(dir.file("whole.ffscene"));
    // Random cuts between objects, and the fingerprint read back from the file.
    std::mt19937 rng(textures ? 7 : 3);
    auto writer = SceneFileWriter::create(dir.file("parts.ffscene"),
                                          {scene.vertices.size(), scene.indices.size()});
    ASSERT_TRUE(writer) << writer.error().message;
    for (uint32_t first = 0; first < scene.objects.size();) {
      const uint32_t count = std::min<uint32_t>(1 + rng() % 300, uint32_t(scene.objects.size()) - first);
      ASSERT_TRUE(writer->append(part_of(scene, first, count)));
      first += count;
    }
    auto info = writer->finish(scene);
    ASSERT_TRUE(info) << info.error().message;
    EXPECT_EQ(info->file_bytes, whole.size());
    EXPECT_TRUE(test::read_file(dir.file("parts.ffscene")) == whole) << "textures " << textures;
    // The city written a block at a time.
    Progress quiet(true);
    auto written = write_city(small_city(textures), dir.file("city.ffscene"), quiet);
    ASSERT_TRUE(written) << written.error().message;
    EXPECT_TRUE(test::read_file(dir.file("city.ffscene")) == whole) << "textures " << textures;
    EXPECT_GT(written->chunks, 1u);
  }
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"city.ffscene", "parts.ffscene",
                                                     "whole.ffscene"}));
}

TEST(ChunkedScene, ChunksCoverTheSceneWithinTheirBudget) {
  TempDir dir;
  const Scene scene = city(true);
  constexpr uint32_t kBudget = 5000;
  ASSERT_TRUE(test::write_in_chunks(scene, dir.file("c.ffscene"), kBudget));
  auto chunked = ChunkedScene::open(dir.file("c.ffscene"));
  ASSERT_TRUE(chunked) << chunked.error().message;
  EXPECT_EQ(chunked->fingerprint(), scene_fingerprint(scene));
  EXPECT_EQ(chunked->triangle_count(), scene.triangle_count());
  EXPECT_EQ(chunked->vertex_count(), scene.vertices.size());
  EXPECT_TRUE(chunked->index().vertices.empty() && chunked->index().indices.empty());
  EXPECT_TRUE(test::same_bytes(chunked->index().objects, scene.objects));
  EXPECT_EQ(chunked->index().names, scene.names);
  EXPECT_EQ(chunked->index().textures.size(), scene.textures.size());
  ASSERT_GT(chunked->chunks().size(), scene.triangle_count() / kBudget);
  uint64_t triangles = 0;
  ChunkGeometry g;
  for (size_t c = 0; c < chunked->chunks().size(); ++c) {
    const SceneChunk& k = chunked->chunks()[c];
    if (k.object_count > 1) {
      EXPECT_LE(k.triangle_count(), kBudget) << c;
    }
    triangles += k.triangle_count();
    EXPECT_EQ(chunked->chunk_of(k.first_object), c);
    EXPECT_EQ(chunked->chunk_of(k.first_object + k.object_count - 1), c);
    ASSERT_TRUE(chunked->read_chunk(c, g));
    ASSERT_EQ(g.vertices.size(), k.vertex_count);
    EXPECT_EQ(std::memcmp(g.vertices.data(), scene.vertices.data() + k.first_vertex,
                          k.vertex_count * sizeof(Vertex)),
              0);
    ASSERT_EQ(g.uvs.size(), k.uv_count);
    if (k.uv_count) {
      EXPECT_EQ(std::memcmp(g.uvs.data(), scene.uvs.data() + k.first_uv, k.uv_count * 8), 0);
    }
    ASSERT_EQ(g.indices.size(), k.index_count);
    for (uint32_t i = 0; i < k.index_count; ++i)
      ASSERT_EQ(g.indices[i] + k.first_vertex, scene.indices[k.first_index + i]) << c;
  }
  EXPECT_EQ(triangles, scene.triangle_count());
  // The whole-file reader reads the same scene and knows its chunks.
  SceneFileInfo info;
  auto whole = read_scene(dir.file("c.ffscene"), &info);
  ASSERT_TRUE(whole);
  EXPECT_EQ(info.chunks, chunked->chunks().size());
  EXPECT_EQ(scene_fingerprint(*whole), scene_fingerprint(scene));
}

TEST(ChunkedScene, ObjectsOutOfOrderMakeOneChunk) {
  TempDir dir;
  Scene scene = test::make_box_row(4);
  std::reverse(scene.objects.begin(), scene.objects.end());  // geometry stays where it was
  ASSERT_EQ(validate_scene(scene), "");
  ASSERT_TRUE(test::write_in_chunks(scene, dir.file("r.ffscene"), 1));
  auto chunked = ChunkedScene::open(dir.file("r.ffscene"));
  ASSERT_TRUE(chunked) << chunked.error().message;
  ASSERT_EQ(chunked->chunks().size(), 1u);
  ChunkGeometry g;
  ASSERT_TRUE(chunked->read_chunk(0, g));
  EXPECT_TRUE(test::same_bytes(g.indices, scene.indices));
  EXPECT_EQ(chunked->fingerprint(), scene_fingerprint(scene));
}

TEST(ChunkedScene, NamesATruncatedOrCorruptedChunk) {
  TempDir dir;
  const Scene scene = city(false);
  const std::string path = dir.file("c.ffscene");
  ASSERT_TRUE(test::write_in_chunks(scene, path, 4000));
  const std::string bytes = test::read_file(path);

  // A vertex of chunk 2 damaged: chunk 2 is refused by name, its neighbours still read.
  auto opened = ChunkedScene::open(path);
  ASSERT_TRUE(opened);
  const SceneChunk k = opened->chunks()[2];
  const char* vertex = reinterpret_cast<const char*>(&scene.vertices[k.first_vertex + 1]);
  const size_t at = bytes.find(std::string(vertex, sizeof(Vertex)));
  ASSERT_NE(at, std::string::npos);
  std::string damaged = bytes;
  damaged[at + 4] ^= 0x10;
  test::write_file(dir.file("d.ffscene"), damaged);
  auto d = ChunkedScene::open(dir.file("d.ffscene"));
  ASSERT_TRUE(d) << "the index is intact";
  ChunkGeometry g;
  EXPECT_TRUE(d->read_chunk(1, g));
  EXPECT_TRUE(d->read_chunk(3, g));
  auto read = d->read_chunk(2, g);
  ASSERT_FALSE(read);
  const std::string objects = "chunk 2 (objects " + std::to_string(k.first_object) + " to " +
                              std::to_string(k.first_object + k.object_count - 1);
  EXPECT_NE(read.error().message.find(objects), std::string::npos) << read.error().message;
  EXPECT_NE(read.error().message.find("checksum mismatch"), std::string::npos);
  EXPECT_NE(read.error().message.find(dir.file("d.ffscene")), std::string::npos);

  // The file cut short after it was opened: the chunk read is named as truncated.
  test::write_file(dir.file("t.ffscene"), bytes);
  auto t = ChunkedScene::open(dir.file("t.ffscene"));
  ASSERT_TRUE(t);
  std::filesystem::resize_file(dir.file("t.ffscene"), at);
  const size_t last = t->chunks().size() - 1;
  read = t->read_chunk(last, g);
  ASSERT_FALSE(read);
  EXPECT_NE(read.error().message.find("chunk " + std::to_string(last) + " (objects"),
            std::string::npos)
      << read.error().message;
  EXPECT_NE(read.error().message.find("truncated"), std::string::npos) << read.error().message;
  // And cut short before: refused at opening, naming what is missing.
  auto cut = ChunkedScene::open(dir.file("t.ffscene"));
  ASSERT_FALSE(cut);
  EXPECT_NE(cut.error().message.find("truncated"), std::string::npos) << cut.error().message;
  EXPECT_NE(cut.error().message.find("section and what follows it are missing"),
            std::string::npos)
      << cut.error().message;
}

TEST(ChunkedScene, FilesWrittenBeforeChunksAreReadWhole) {
  const std::string v1 = std::string(FARFIELD_SOURCE_DIR) + "/tests/data/tree_v1.ffscene";
  auto chunked = ChunkedScene::open(v1);
  ASSERT_FALSE(chunked);
  EXPECT_NE(chunked.error().message.find("written before chunks"), std::string::npos)
      << chunked.error().message;
  EXPECT_TRUE(read_scene(v1));
  // info describes it as before, read whole.
  auto info = test::run_farfield("info " + v1);
  EXPECT_EQ(info.exit_status, 0) << info.output;
  EXPECT_NE(info.output.find("load time:"), std::string::npos) << info.output;
  // import rewrites it with chunks, the same scene.
  TempDir dir;
  auto rewritten = test::run_farfield("import " + v1 + " --out " + dir.file("new.ffscene"));
  ASSERT_EQ(rewritten.exit_status, 0) << rewritten.output;
  auto now = ChunkedScene::open(dir.file("new.ffscene"));
  ASSERT_TRUE(now) << now.error().message;
  EXPECT_EQ(now->fingerprint(), 0x894bed053fea1f6eull);
  EXPECT_EQ(now->triangle_count(), 632u);
  // path reads the chunked one without its geometry: the same poses.
  for (const std::string kind : {"orbit", "fly"}) {
    ASSERT_EQ(test::run_farfield("path " + v1 + " --kind " + kind + " --frames 20 --out " +
                                 dir.file("old.json"))
                  .exit_status,
              0);
    ASSERT_EQ(test::run_farfield("path " + dir.file("new.ffscene") + " --kind " + kind +
                                 " --frames 20 --out " + dir.file("new.json"))
                  .exit_status,
              0);
    auto old_path = read_camera_path(dir.file("old.json"));
    auto new_path = read_camera_path(dir.file("new.json"));
    ASSERT_TRUE(old_path && new_path);
    ASSERT_EQ(old_path->frames.size(), new_path->frames.size());
    for (size_t f = 0; f < old_path->frames.size(); ++f)
      EXPECT_EQ(old_path->frames[f].position, new_path->frames[f].position) << kind << f;
    std::filesystem::remove(dir.file("old.json"));
    std::filesystem::remove(dir.file("new.json"));
  }
  auto mixed = test::run_farfield("import " + v1 + " " + v1 + " --out " + dir.file("m.ffscene"));
  EXPECT_EQ(mixed.exit_status, 2) << mixed.output;
  auto scaled =
      test::run_farfield("import " + v1 + " --scale 2 --out " + dir.file("m.ffscene"));
  EXPECT_EQ(scaled.exit_status, 2) << scaled.output;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"new.ffscene"});
}

TEST(SceneFileWriter, RefusesPartsThatDoNotAddUp) {
  TempDir dir;
  const Scene scene = test::make_box_row(3);
  {
    auto writer = SceneFileWriter::create(dir.file("a.ffscene"),
                                          {scene.vertices.size() - 1, scene.indices.size()});
    ASSERT_TRUE(writer);
    auto ok = writer->append(scene);
    ASSERT_FALSE(ok);
    EXPECT_NE(ok.error().message.find("hold more than"), std::string::npos) << ok.error().message;
  }
  {
    auto writer = SceneFileWriter::create(dir.file("a.ffscene"),
                                          {scene.vertices.size() + 8, scene.indices.size()});
    ASSERT_TRUE(writer);
    ASSERT_TRUE(writer->append(scene));
    auto ok = writer->finish(scene);
    ASSERT_FALSE(ok);
    EXPECT_NE(ok.error().message.find("not the"), std::string::npos) << ok.error().message;
  }
  {
    Scene broken = scene;
    broken.indices[0] = 999;
    auto writer = SceneFileWriter::create(dir.file("a.ffscene"),
                                          {scene.vertices.size(), scene.indices.size()});
    ASSERT_TRUE(writer);
    auto ok = writer->append(broken);
    ASSERT_FALSE(ok);
    EXPECT_NE(ok.error().message.find("invalid scene"), std::string::npos) << ok.error().message;
  }
  auto absurd = SceneFileWriter::create(dir.file("a.ffscene"), {uint64_t(1) << 33, 0});
  ASSERT_FALSE(absurd);
  EXPECT_TRUE(dir.entries().empty()) << "nothing half-written is left";
}

TEST(ChunkedSceneCli, InfoLeavesTheGeometryOnDisk) {
  TempDir dir;
  auto generated =
      test::run_farfield("generate city --blocks 3 -q --out " + dir.file("c.ffscene"));
  ASSERT_EQ(generated.exit_status, 0) << generated.output;
  auto info = test::run_farfield("info " + dir.file("c.ffscene"));
  ASSERT_EQ(info.exit_status, 0) << info.output;
  EXPECT_NE(info.output.find("open time:"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("chunks:"), std::string::npos) << info.output;
  const Scene scene = city(false);
  EXPECT_NE(info.output.find("triangles:   " + std::to_string(scene.triangle_count())),
            std::string::npos)
      << info.output;
  // A damaged chunk that info samples is named.
  std::string bytes = test::read_file(dir.file("c.ffscene"));
  const char* vertex = reinterpret_cast<const char*>(&scene.vertices[3]);
  const size_t at = bytes.find(std::string(vertex, sizeof(Vertex)));
  ASSERT_NE(at, std::string::npos);
  bytes[at] ^= 1;
  test::write_file(dir.file("c.ffscene"), bytes);
  info = test::run_farfield("info " + dir.file("c.ffscene"));
  EXPECT_EQ(info.exit_status, 1) << info.output;
  EXPECT_NE(info.output.find("chunk 0 (objects 0 to"), std::string::npos) << info.output;
}

}  // namespace
}  // namespace farfield
