#include "farfield/scene/landscape_generator.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <glm/geometric.hpp>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "farfield/scene/scene_file.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using test::same_bytes;

Scene generate(const LandscapeOptions& options) {
  Progress quiet(true);
  auto scene = generate_landscape(options, quiet);
  EXPECT_TRUE(scene) << scene.error().message;
  return scene ? std::move(scene).value() : Scene{};
}

// 200 m, 32 x 32 cells in 4 x 4 tiles, 12 trees: small enough to test in a few milliseconds.
LandscapeOptions small_landscape() {
  LandscapeOptions o;
  o.size = 200.0;
  o.resolution = 32;
  o.tile_cells = 8;
  o.relief = 30.0;
  o.trees = 12;
  return o;
}

// Height of the terrain's triangles at (x, z), found without the generator's help.
std::optional<float> terrain_height(const Scene& s, float x, float z) {
  for (const Object& o : s.objects) {
    if (o.kind != ObjectKind::terrain || x < o.bounds.min.x || x > o.bounds.max.x ||
        z < o.bounds.min.z || z > o.bounds.max.z)
      continue;
    for (uint32_t i = o.first_index; i < o.first_index + o.index_count; i += 3) {
      const glm::vec3 a = s.vertices[s.indices[i]].position,
                      b = s.vertices[s.indices[i + 1]].position,
                      c = s.vertices[s.indices[i + 2]].position;
      // Barycentric coordinates in the XZ plane.
      const float d = (b.z - c.z) * (a.x - c.x) + (c.x - b.x) * (a.z - c.z);
      const float u = ((b.z - c.z) * (x - c.x) + (c.x - b.x) * (z - c.z)) / d;
      const float v = ((c.z - a.z) * (x - c.x) + (a.x - c.x) * (z - c.z)) / d;
      const float eps = 1e-5f;
      if (u >= -eps && v >= -eps && u + v <= 1.0f + eps)
        return u * a.y + v * b.y + (1 - u - v) * c.y;
    }
  }
  return std::nullopt;
}

TEST(LandscapeGenerator, SameOptionsGiveTheSameLandscape) {
  const Scene a = generate(small_landscape()), b = generate(small_landscape());
  ASSERT_GT(a.triangle_count(), 0u);
  EXPECT_TRUE(same_bytes(a.vertices, b.vertices));
  EXPECT_TRUE(same_bytes(a.indices, b.indices));
  EXPECT_TRUE(same_bytes(a.objects, b.objects));
  EXPECT_EQ(a.names, b.names);
  LandscapeOptions other = small_landscape();
  other.seed = 9;
  EXPECT_FALSE(same_bytes(a.vertices, generate(other).vertices));
}

TEST(LandscapeGenerator, TilesAndTreesAreObjects) {
  const LandscapeOptions o = small_landscape();
  const Scene s = generate(o);
  EXPECT_EQ(validate_scene(s), "");
  std::map<ObjectKind, size_t> count;
  std::set<std::string_view> names;
  for (const Object& obj : s.objects) {
    ++count[obj.kind];
    EXPECT_TRUE(names.insert(s.object_name(obj)).second) << s.object_name(obj);
    if (obj.kind == ObjectKind::terrain) {
      EXPECT_EQ(obj.triangle_count(), 8u * 8u * 2u);
    } else {
      EXPECT_GT(obj.triangle_count(), 1000u);
    }
  }
  EXPECT_EQ(count[ObjectKind::terrain], 16u);
  EXPECT_EQ(count[ObjectKind::tree], 12u);
  EXPECT_EQ(s.objects.size(), 28u);
  EXPECT_TRUE(names.contains("terrain_3_2"));
  EXPECT_TRUE(names.contains("tree_11"));
  Bounds3 ground;
  for (const Object& obj : s.objects) {
    if (obj.kind == ObjectKind::terrain) ground.expand(obj.bounds);
  }
  EXPECT_NEAR(ground.min.x, -100.0f, 1e-3f);
  EXPECT_NEAR(ground.max.z, 100.0f, 1e-3f);

  // A tile size that does not divide the grid leaves smaller tiles at the far edges.
  LandscapeOptions odd = o;
  odd.tile_cells = 10;
  odd.trees = 0;
  const Scene t = generate(odd);
  EXPECT_EQ(t.objects.size(), 16u);
  EXPECT_EQ(t.triangle_count(), 32u * 32u * 2u);
}

TEST(LandscapeGenerator, GroundSpansTheReliefFacesUpAndTilesMeet) {
  LandscapeOptions o = small_landscape();
  o.trees = 0;
  const Scene s = generate(o);
  EXPECT_NEAR(s.bounds.min.y, 0.0f, 1e-4f);
  EXPECT_NEAR(s.bounds.max.y, o.relief, 1e-3f);
  for (size_t i = 0; i < s.indices.size(); i += 3) {
    const Vertex &a = s.vertices[s.indices[i]], &b = s.vertices[s.indices[i + 1]],
                 &c = s.vertices[s.indices[i + 2]];
    const glm::vec3 face = glm::cross(b.position - a.position, c.position - a.position);
    ASSERT_GT(face.y, 0.0f) << "triangle " << i / 3;
    ASSERT_GT(glm::dot(face, unpack_normal(a.normal)), 0.0f) << "triangle " << i / 3;
  }
  // Every grid point appears with one height and one normal, whichever tiles hold it.
  std::map<std::pair<float, float>, std::pair<float, uint32_t>> points;
  for (const Vertex& v : s.vertices) {
    auto [it, fresh] = points.try_emplace({v.position.x, v.position.z}, v.position.y, v.normal);
    if (!fresh) {
      EXPECT_EQ(it->second.first, v.position.y);
      EXPECT_EQ(it->second.second, v.normal);
    }
  }
  EXPECT_EQ(points.size(), 33u * 33u);

  o.relief = 0.0;  // flat
  const Scene flat = generate(o);
  EXPECT_EQ(flat.bounds.size().y, 0.0f);
}

TEST(LandscapeGenerator, ColoursGoFromGrassToRock) {
  LandscapeOptions o = small_landscape();
  o.trees = 0;
  o.relief = 120.0;  // steep enough for rock
  const Scene s = generate(o);
  size_t grass = 0, rock = 0;
  for (const Vertex& v : s.vertices) {
    const glm::vec4 c = unpack_color(v.color);
    grass += c.g > 1.3f * c.b && c.g > c.r;
    rock += c.g < 1.15f * c.b;
  }
  EXPECT_GT(grass, s.vertices.size() / 4);
  EXPECT_GT(rock, 0u);
}

// Trunks stand on the ground: the lowest point of a tree (its trunk's base) is at most a little
// under the triangles below it, never above them.
TEST(LandscapeGenerator, TreesStandOnTheTerrain) {
  LandscapeOptions o = small_landscape();
  o.relief = 40.0;
  o.trees = 20;
  const Scene s = generate(o);
  size_t trees = 0;
  for (const Object& obj : s.objects) {
    if (obj.kind != ObjectKind::tree) continue;
    ++trees;
    const Vertex* lowest = &s.vertices[obj.first_vertex];
    for (uint32_t k = 0; k < obj.vertex_count; ++k) {
      const Vertex& v = s.vertices[obj.first_vertex + k];
      if (v.position.y < lowest->position.y) lowest = &v;
    }
    const auto ground = terrain_height(s, lowest->position.x, lowest->position.z);
    ASSERT_TRUE(ground) << s.object_name(obj);
    EXPECT_LE(lowest->position.y, *ground + 1e-3f) << s.object_name(obj);
    EXPECT_GE(lowest->position.y, *ground - 0.5f) << s.object_name(obj);
    EXPECT_GT(obj.bounds.size().y, 6.0f) << s.object_name(obj);
  }
  EXPECT_EQ(trees, 20u);
}

TEST(LandscapeGenerator, RejectsBadOptionsNamingThem) {
  auto message = [](auto change) {
    LandscapeOptions o;
    change(o);
    auto ok = validate_landscape_options(o);
    return ok ? std::string("accepted") : ok.error().message;
  };
  EXPECT_EQ(message([](LandscapeOptions& o) { o.size = 0; }),
            "--size must be in (0, 1e+06] (got 0)");
  EXPECT_NE(message([](LandscapeOptions& o) { o.size = NAN; }).find("--size"), std::string::npos);
  EXPECT_NE(message([](LandscapeOptions& o) { o.resolution = 0; }).find("--resolution"),
            std::string::npos);
  EXPECT_NE(message([](LandscapeOptions& o) { o.resolution = 10000; }).find("--resolution"),
            std::string::npos);
  EXPECT_NE(message([](LandscapeOptions& o) { o.tile_cells = 0; }).find("--tile"),
            std::string::npos);
  EXPECT_NE(message([](LandscapeOptions& o) { o.relief = -1; }).find("--relief"),
            std::string::npos);
  EXPECT_NE(message([](LandscapeOptions& o) { o.trees = 100000; }).find("--trees"),
            std::string::npos);
  EXPECT_EQ(message([](LandscapeOptions&) {}), "accepted");
  Progress quiet(true);
  LandscapeOptions bad;
  bad.resolution = 0;
  EXPECT_FALSE(generate_landscape(bad, quiet));
}

TEST(LandscapeGenerator, CommandLineWritesALandscape) {
  test::TempDir dir;
  auto r = test::run_farfield(
      "generate landscape --out l.ffscene --size 200 --resolution 32 --tile 8 --relief 30 "
      "--trees 12 -q",
      dir.path().string());
  ASSERT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("wrote l.ffscene: "), std::string::npos) << r.output;
  auto scene = read_scene(dir.file("l.ffscene"));
  ASSERT_TRUE(scene) << scene.error().message;
  EXPECT_TRUE(same_bytes(scene->vertices, generate(small_landscape()).vertices));

  r = test::run_farfield("generate landscape --out bad.ffscene --relief -5", dir.path().string());
  EXPECT_EQ(r.exit_status, 1) << r.output;
  EXPECT_NE(r.output.find("--relief"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad.ffscene")));
}

}  // namespace
}  // namespace farfield
