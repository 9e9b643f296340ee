// Objects that repeat one model (Scene::instances): stored once in the .ffscene, read back,
// whole and a chunk at a time, as the scene that was written; a table that lies is refused.
#include "farfield/scene/instances.hpp"

#include <gtest/gtest.h>
#include <xxhash.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>

#include "farfield/core/progress.hpp"
#include "farfield/scene/chunked_scene.hpp"
#include "farfield/scene/field_generator.hpp"
#include "farfield/scene/scene_file.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using test::TempDir;

Scene field_of(const Scene& model, uint64_t count) {
  Progress quiet(true);
  auto field = generate_field(model, {.count = count, .spacing = 12.0}, quiet);
  EXPECT_TRUE(field) << field.error().message;
  return std::move(*field);
}

// A textured quad (after a box row), one copy as it is and two turned, scaled and moved.
Scene turned_copies() {
  Scene s = test::make_textured_scene();
  SceneBuilder b(s);
  const uint32_t quad = uint32_t(s.objects.size() - 1);
  const glm::mat3 turn = glm::mat3(glm::rotate(glm::mat4(1.0f), 1.2f, glm::vec3(0, 1, 0))) * 2.0f;
  b.add_instance("turned", ObjectKind::mesh, quad, turn, {30.0f, 0.0f, 0.0f});
  b.add_instance("moved", ObjectKind::mesh, quad, glm::mat3(1.0f), {0.0f, 0.0f, 40.0f});
  return s;
}

void expect_same_scene(const Scene& read, const Scene& written) {
  EXPECT_TRUE(test::same_bytes(read.objects, written.objects));
  EXPECT_TRUE(test::same_bytes(read.vertices, written.vertices));
  EXPECT_TRUE(test::same_bytes(read.indices, written.indices));
  EXPECT_TRUE(test::same_bytes(read.uvs, written.uvs));
  EXPECT_EQ(read.instances, written.instances);
  EXPECT_EQ(read.names, written.names);
  EXPECT_EQ(scene_fingerprint(read), scene_fingerprint(written));
}

TEST(Instances, AFieldIsStoredOnceAndReadBackAsWritten) {
  TempDir dir;
  const Scene model = test::make_box_row(3);
  const Scene field = field_of(model, 64);
  ASSERT_EQ(field.instances.size(), 63u);
  EXPECT_EQ(validate_scene(field), "");
  for (const Instance& i : field.instances) EXPECT_EQ(i.prototype, 0u);
  // Copy 5 is copy 0 moved along the grid, bit for bit but for the offset.
  const Object &first = field.objects[0], &fifth = field.objects[5];
  EXPECT_EQ(field.vertices[fifth.first_vertex].normal, field.vertices[first.first_vertex].normal);
  EXPECT_NE(field.vertices[fifth.first_vertex].position, field.vertices[first.first_vertex].position);

  ASSERT_TRUE(write_scene(field, dir.file("field.ffscene")));
  Scene flat = field;  // the same geometry without instances: every copy stored
  flat.instances.clear();
  ASSERT_TRUE(write_scene(flat, dir.file("flat.ffscene")));
  const auto stored = std::filesystem::file_size(dir.file("field.ffscene"));
  const auto whole = std::filesystem::file_size(dir.file("flat.ffscene"));
  EXPECT_LT(stored * 4, whole) << stored << " bytes with instances, " << whole << " without";

  auto read = read_scene(dir.file("field.ffscene"));
  ASSERT_TRUE(read) << read.error().message;
  expect_same_scene(*read, field);
  const auto info = test::run_farfield("info " + dir.file("field.ffscene"));
  EXPECT_EQ(info.exit_status, 0);
  EXPECT_NE(info.output.find("instances:   63 objects repeat 1 model"), std::string::npos)
      << info.output;
}

TEST(Instances, TurnedAndScaledCopiesMoveTheirNormalsAndKeepTheirTextureCoordinates) {
  TempDir dir;
  const Scene s = turned_copies();
  ASSERT_EQ(validate_scene(s), "");
  ASSERT_TRUE(s.textured(s.objects[s.instances[0].prototype]));
  const Object &p = s.objects[s.instances[0].prototype], &turned = s.objects[s.instances[0].object];
  const glm::mat3 linear = s.instances[0].linear;
  for (uint32_t v = 0; v < p.vertex_count; ++v) {
    const Vertex &a = s.vertices[p.first_vertex + v], &b = s.vertices[turned.first_vertex + v];
    EXPECT_LT(glm::length(b.position - (linear * a.position + glm::vec3(30, 0, 0))), 1e-4f);
    const glm::vec3 n = glm::normalize(linear * unpack_normal(a.normal));
    EXPECT_LT(glm::length(unpack_normal(b.normal) - n), 0.01f);
    EXPECT_EQ(s.uvs[turned.first_uv + v], s.uvs[p.first_uv + v]);
  }
  ASSERT_TRUE(write_scene(s, dir.file("t.ffscene")));
  auto read = read_scene(dir.file("t.ffscene"));
  ASSERT_TRUE(read) << read.error().message;
  expect_same_scene(*read, s);
}

// Chunks small enough that copies lie in chunks other than their model's.
TEST(Instances, ChunksReadTheirCopiesFromTheModelsChunk) {
  TempDir dir;
  for (const Scene& scene : {field_of(test::make_box_row(3), 20), turned_copies()}) {
    ASSERT_TRUE(test::write_in_chunks(scene, dir.file("c.ffscene"), 1));
    auto disk = ChunkedScene::open(dir.file("c.ffscene"));
    ASSERT_TRUE(disk) << disk.error().message;
    EXPECT_GT(disk->chunks().size(), 2u);
    EXPECT_TRUE(test::same_bytes(disk->index().objects, scene.objects));
    EXPECT_EQ(disk->vertex_count(), scene.vertices.size());
    EXPECT_EQ(disk->index_count(), scene.indices.size());
    EXPECT_EQ(disk->fingerprint(), scene_fingerprint(scene));
    ChunkGeometry g;
    for (size_t c = 0; c < disk->chunks().size(); ++c) {
      const SceneChunk& k = disk->chunks()[c];
      ASSERT_TRUE(disk->read_chunk(c, g)) << c;
      ASSERT_EQ(g.vertices.size(), k.vertex_count);
      EXPECT_EQ(0, std::memcmp(g.vertices.data(), scene.vertices.data() + k.first_vertex,
                               g.vertices.size() * sizeof(Vertex)))
          << "chunk " << c;
      for (uint32_t i = 0; i < k.index_count; ++i)
        ASSERT_EQ(g.indices[i] + k.first_vertex, scene.indices[k.first_index + i]);
      for (uint32_t i = 0; i < k.uv_count; ++i)
        ASSERT_EQ(g.uvs[i], scene.uvs[k.first_uv + i]);
    }
  }
}

// The largest stretch of a linear map is its largest singular value: a rotation's 1, a
// scale's its factor however turned, a sheared map's what stretching sampled directions finds
// (never less, and not more than they show by over a part in a thousand).
TEST(Instances, LargestStretchIsTheLargestSingularValue) {
  const glm::mat3 turn = glm::mat3(glm::rotate(glm::mat4(1.0f), 0.9f, glm::vec3(1, 1, 0)));
  EXPECT_NEAR(largest_stretch(glm::mat3(1.0f)), 1.0, 1e-9);
  EXPECT_NEAR(largest_stretch(turn), 1.0, 1e-6);
  EXPECT_NEAR(largest_stretch(turn * 2.5f), 2.5, 1e-5);
  const glm::mat3 scale(glm::vec3(0.5f, 0, 0), glm::vec3(0, 3.0f, 0), glm::vec3(0, 0, 1.0f));
  EXPECT_NEAR(largest_stretch(turn * scale * glm::transpose(turn)), 3.0, 1e-5);
  glm::mat3 sheared = turn * scale;
  sheared[2][0] = 1.7f;  // column 2, row 0
  double sampled = 0.0;
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j <= 100; ++j) {
      const double a = 6.283185307 * i / 200.0, e = 3.141592654 * j / 100.0;
      const glm::vec3 d(std::sin(e) * std::cos(a), std::cos(e), std::sin(e) * std::sin(a));
      sampled = std::max(sampled, double(glm::length(sheared * d)));
    }
  const double stretch = largest_stretch(sheared);
  EXPECT_GE(stretch, sampled * (1.0 - 1e-6));
  EXPECT_LE(stretch, sampled * 1.001);
}

TEST(Instances, ATableThatLiesIsRefused) {
  const Scene good = turned_copies();
  const uint32_t last = good.instances.back().object;
  auto problem = [&](auto change) {
    Scene s = good;
    change(s);
    return validate_scene(s);
  };
  EXPECT_NE(problem([](Scene& s) { s.instances[0].linear = -s.instances[0].linear; }).find("mirrors"),
            std::string::npos);
  EXPECT_NE(problem([&](Scene& s) { s.instances.back().prototype = last; }).find("not an earlier"),
            std::string::npos);
  EXPECT_NE(problem([&](Scene& s) { s.instances.back().prototype = s.instances[0].object; })
                .find("itself an instance"),
            std::string::npos);
  EXPECT_NE(problem([](Scene& s) { std::swap(s.instances[0], s.instances[1]); })
                .find("increasing object order"),
            std::string::npos);
  EXPECT_NE(problem([&](Scene& s) { s.vertices[s.objects[last].first_vertex].position.y += 1; })
                .find("vertex 0 is not its prototype's moved"),
            std::string::npos);
  // The writer refuses such a scene, and leaves no file.
  TempDir dir;
  Scene bad = good;
  bad.instances[0].offset.x += 1.0f;
  auto written = write_scene(bad, dir.file("bad.ffscene"));
  ASSERT_FALSE(written);
  EXPECT_NE(written.error().message.find("refusing to write an invalid scene"), std::string::npos)
      << written.error().message;
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad.ffscene")));
}

// A file whose instance table was changed, its checksums made to match: the reader checks it.
TEST(Instances, AFileWhoseTableLiesIsRefused) {
  TempDir dir;
  ASSERT_TRUE(write_scene(turned_copies(), dir.file("t.ffscene")));
  std::string file = test::read_file(dir.file("t.ffscene"));
  uint32_t count;
  std::memcpy(&count, file.data() + 40, 4);
  for (uint32_t e = 0; e < count; ++e) {
    char* entry = file.data() + 64 + e * 48;
    if (std::strcmp(entry, "instances") != 0) continue;
    uint64_t offset, bytes;
    std::memcpy(&offset, entry + 16, 8);
    std::memcpy(&bytes, entry + 24, 8);
    Instance first;
    std::memcpy(&first, file.data() + offset, sizeof first);
    first.prototype = first.object;  // an instance of itself
    std::memcpy(file.data() + offset, &first, sizeof first);
    const uint64_t checksum = XXH3_64bits(file.data() + offset, bytes);
    std::memcpy(entry + 32, &checksum, 8);
  }
  test::reseal_scene_header(file);
  auto read = parse_scene(std::as_bytes(std::span(file.data(), file.size())), "t.ffscene");
  ASSERT_FALSE(read);
  EXPECT_NE(read.error().message.find("not an earlier one"), std::string::npos)
      << read.error().message;
  test::write_file(dir.file("lies.ffscene"), file);
  auto disk = ChunkedScene::open(dir.file("lies.ffscene"));
  ASSERT_FALSE(disk);
  EXPECT_NE(disk.error().message.find("not an earlier one"), std::string::npos)
      << disk.error().message;
}

}  // namespace
}  // namespace farfield
