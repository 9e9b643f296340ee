#include "farfield/scene/city_generator.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <map>
#include <set>
#include <string>

#include "test_util.hpp"

namespace farfield {
namespace {

using test::same_bytes;

Scene generate(const CityOptions& options) {
  Progress quiet(true);
  auto scene = generate_city(options, quiet);
  EXPECT_TRUE(scene) << scene.error().message;
  return scene ? std::move(scene).value() : Scene{};
}

// The default city, generated once for the tests that only read it.
const Scene& default_city() {
  static const Scene city = generate(CityOptions{});
  return city;
}

CityOptions small_city(uint32_t blocks) {
  CityOptions o;
  o.blocks_x = o.blocks_z = blocks;
  return o;
}

std::string_view block_of(std::string_view name) {  // "block_3_4/tree_2" -> "block_3_4"
  const size_t slash = name.find('/');
  return slash == std::string_view::npos ? std::string_view{} : name.substr(0, slash);
}

// name -> (kind, vertices) of every object of the scene whose name starts with `prefix`.
std::map<std::string, std::pair<ObjectKind, std::vector<Vertex>>> objects_named(
    const Scene& s, std::string_view prefix) {
  std::map<std::string, std::pair<ObjectKind, std::vector<Vertex>>> out;
  for (const Object& o : s.objects) {
    const std::string_view name = s.object_name(o);
    if (!name.starts_with(prefix)) continue;
    out[std::string(name)] = {o.kind,
                              {s.vertices.begin() + o.first_vertex,
                               s.vertices.begin() + o.first_vertex + o.vertex_count}};
  }
  return out;
}

TEST(CityGenerator, SameSeedAndOptionsGiveTheSameScene) {
  const CityOptions options = small_city(3);
  const Scene a = generate(options), b = generate(options);
  ASSERT_GT(a.triangle_count(), 0u);
  EXPECT_TRUE(same_bytes(a.vertices, b.vertices));
  EXPECT_TRUE(same_bytes(a.indices, b.indices));
  EXPECT_TRUE(same_bytes(a.objects, b.objects));
  EXPECT_TRUE(same_bytes(a.materials, b.materials));
  EXPECT_EQ(a.names, b.names);
}

// --textures adds textures and texture coordinates and changes no vertex or index: the same
// city, so that textured and untextured runs compare on the same geometry.
TEST(CityGenerator, TexturesKeepTheGeometry) {
  CityOptions o = small_city(2);
  const Scene plain = generate(o);
  o.textures = true;
  const Scene textured = generate(o);
  EXPECT_TRUE(same_bytes(textured.vertices, plain.vertices));
  EXPECT_EQ(textured.indices, plain.indices);
  EXPECT_EQ(textured.names, plain.names);
  EXPECT_EQ(validate_scene(textured), "");
  ASSERT_EQ(textured.textures.size(), 3u);
  EXPECT_TRUE(plain.textures.empty() && plain.uvs.empty());
  size_t by_kind[size_t(ObjectKind::count_)] = {};
  for (const Object& obj : textured.objects)
    if (textured.textured(obj)) ++by_kind[size_t(obj.kind)];
  EXPECT_GT(by_kind[size_t(ObjectKind::building)], 0u);
  EXPECT_GT(by_kind[size_t(ObjectKind::street)], 0u);
  EXPECT_GT(by_kind[size_t(ObjectKind::ground)], 0u);
  EXPECT_EQ(by_kind[size_t(ObjectKind::tree)], 0u);
  for (const Object& obj : textured.objects) {  // glass stays untextured
    if (textured.materials[obj.material].transparent()) {
      EXPECT_FALSE(textured.textured(obj));
    }
  }
  // The textures are the same bytes whatever the seed.
  o.seed = 99;
  const Scene other = generate(o);
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(other.textures[i].encoded, textured.textures[i].encoded);
}

TEST(CityGenerator, DifferentSeedsGiveDifferentCities) {
  CityOptions options = small_city(2);
  const Scene a = generate(options);
  options.seed = 2;
  const Scene b = generate(options);
  EXPECT_FALSE(same_bytes(a.vertices, b.vertices));
}

TEST(CityGenerator, DefaultCityIsAboutOneKilometreWithOverAMillionTriangles) {
  const Scene& s = default_city();
  EXPECT_EQ(validate_scene(s), "");
  EXPECT_GE(s.triangle_count(), 1'000'000u);
  EXPECT_LE(s.triangle_count(), 2'500'000u);
  EXPECT_NEAR(s.bounds.size().x, 1000.0f, 100.0f);
  EXPECT_NEAR(s.bounds.size().z, 1000.0f, 100.0f);
  EXPECT_GE(s.bounds.min.y, 0.0f);
  EXPECT_LE(s.bounds.max.y, CityOptions{}.max_height);
  EXPECT_LT(s.vertices.size(), uint64_t(UINT32_MAX));
}

TEST(CityGenerator, DefaultCityHasEveryKindAsItsOwnObjects) {
  const Scene& s = default_city();
  std::map<ObjectKind, size_t> count;
  std::set<std::string_view> names;
  for (const Object& o : s.objects) {
    ++count[o.kind];
    EXPECT_TRUE(names.insert(s.object_name(o)).second) << "duplicate " << s.object_name(o);
    if (o.kind == ObjectKind::tree) {
      EXPECT_GE(o.triangle_count(), 50u);
      EXPECT_LE(o.triangle_count(), 150u);
    }
    if (o.kind == ObjectKind::park) {
      EXPECT_EQ(o.triangle_count(), 16u);  // one L-shaped strip
    }
  }
  for (ObjectKind kind :
       {ObjectKind::building, ObjectKind::tree, ObjectKind::fountain, ObjectKind::park,
        ObjectKind::street, ObjectKind::curb, ObjectKind::ground}) {
    EXPECT_GT(count[kind], 0u) << object_kind_name(kind);
  }
  EXPECT_EQ(count[ObjectKind::ground], 64u);  // one per block
  EXPECT_EQ(count[ObjectKind::curb], 4u * 64u);
  EXPECT_EQ(count[ObjectKind::street], 9u * 9u + 2u * 8u * 9u);  // crossings and stretches
  EXPECT_GT(count[ObjectKind::building], 64u * 5u);
  EXPECT_TRUE(names.contains("block_3_4/ground"));
  EXPECT_TRUE(names.contains("street_x_2_5"));
  EXPECT_TRUE(names.contains("crossing_8_8"));
}

TEST(CityGenerator, DefaultCityHasParkBlocksAndSemiTransparentBuildings) {
  const Scene& s = default_city();
  // Per block: buildings, park strips and fountains.
  std::map<std::string_view, std::array<int, 3>> blocks;
  size_t glass = 0, opaque = 0;
  for (const Object& o : s.objects) {
    auto& b = blocks[block_of(s.object_name(o))];
    const Material& m = s.materials[o.material];
    if (o.kind == ObjectKind::building) {
      ++b[0];
      (m.transparent() ? glass : opaque) += 1;
      EXPECT_EQ(m.base_color, m.transparent() ? glm::vec4(1, 1, 1, 0.5f) : glm::vec4(1));
    } else {
      EXPECT_FALSE(m.transparent()) << "only buildings are see-through";
    }
    if (o.kind == ObjectKind::park) ++b[1];
    if (o.kind == ObjectKind::fountain) ++b[2];
  }
  int park_blocks = 0;
  for (const auto& [block, n] : blocks) park_blocks += n[0] == 0 && n[1] == 4 && n[2] == 1;
  EXPECT_GT(park_blocks, 0);
  EXPECT_GT(glass, 0u);
  EXPECT_GT(opaque, glass);
}

// Flat faces and round sides both face out: a triangle's winding agrees with its normals.
TEST(CityGenerator, FrontFacesAreCounterClockwiseSeenFromTheirNormals) {
  CityOptions options = small_city(3);
  options.park_block_fraction = 0.4;  // some of everything
  const Scene s = generate(options);
  ASSERT_EQ(validate_scene(s), "");
  size_t wrong = 0;
  for (size_t i = 0; i < s.indices.size(); i += 3) {
    const Vertex& a = s.vertices[s.indices[i]];
    const Vertex& b = s.vertices[s.indices[i + 1]];
    const Vertex& c = s.vertices[s.indices[i + 2]];
    const glm::vec3 face = glm::cross(b.position - a.position, c.position - a.position);
    const glm::vec3 normal =
        unpack_normal(a.normal) + unpack_normal(b.normal) + unpack_normal(c.normal);
    wrong += glm::dot(face, normal) <= 0.0f;
  }
  EXPECT_EQ(wrong, 0u);
}

TEST(CityGenerator, TargetTrianglesGrowsTheGrid) {
  CityOptions options;
  options.target_triangles = 3'000'000;
  const Scene s = generate(options);
  EXPECT_EQ(validate_scene(s), "");
  EXPECT_GE(s.triangle_count(), options.target_triangles);
  EXPECT_LT(s.triangle_count(), 2 * options.target_triangles);
  size_t blocks = 0;
  for (const Object& o : s.objects) blocks += o.kind == ObjectKind::ground;
  const size_t n = static_cast<size_t>(std::lround(std::sqrt(double(blocks))));
  EXPECT_EQ(n * n, blocks);  // square
  EXPECT_GT(n, 8u);
  EXPECT_NEAR(s.bounds.size().x, s.bounds.size().z, 1.0f);
}

TEST(CityGenerator, GrowingTheGridKeepsTheBlocksThatWereThere) {
  const Scene small = generate(small_city(2)), large = generate(small_city(3));
  for (const char* block : {"block_0_0/", "block_1_1/"}) {
    const auto before = objects_named(small, block), after = objects_named(large, block);
    ASSERT_GT(before.size(), 5u) << block;
    ASSERT_EQ(before.size(), after.size()) << block;
    for (const auto& [name, object] : before) {
      ASSERT_TRUE(after.contains(name)) << name;
      EXPECT_EQ(object.first, after.at(name).first) << name;
      EXPECT_TRUE(same_bytes(object.second, after.at(name).second)) << name;
    }
  }
}

TEST(CityGenerator, RejectsBadOptionsNamingThem) {
  auto message = [](auto change) {
    CityOptions o;
    change(o);
    auto ok = validate_city_options(o);
    return ok ? std::string("accepted") : ok.error().message;
  };
  EXPECT_EQ(message([](CityOptions& o) { o.block_length = -3; }),
            "--block-length must be > 0 (got -3)");
  EXPECT_NE(message([](CityOptions& o) { o.block_width = NAN; }).find("--block-width"),
            std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.max_height = INFINITY; }).find("--max-height"),
            std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.max_height = 0; }).find("--max-height"),
            std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.rows = 0; }).find("--rows"), std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.columns = 0; }).find("--columns"), std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.blocks_x = 0; }).find("--blocks-x"), std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.blocks_z = 200000; }).find("--blocks-z"),
            std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.street_width = 0; }).find("--street-width"),
            std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.curb_width = 60; }).find("--curb-width"),
            std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.curb_height = -1; }).find("--curb-height"),
            std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.tree_distance = 0; }).find("--tree-distance"),
            std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.park_block_fraction = 1.5; }).find("--park-blocks"),
            std::string::npos);
  EXPECT_NE(message([](CityOptions& o) { o.tree_block_fraction = -0.1; }).find("--tree-blocks"),
            std::string::npos);
  EXPECT_NE(message([](CityOptions& o) {
              o.target_triangles = 3'000'000'000;
            }).find("--target-triangles"),
            std::string::npos);
  EXPECT_EQ(message([](CityOptions&) {}), "accepted");

  // generate_city checks them too, and refuses a city too large for a scene.
  Progress quiet(true);
  CityOptions bad;
  bad.rows = 0;
  EXPECT_FALSE(generate_city(bad, quiet));
  auto huge = generate_city(small_city(100000), quiet);
  ASSERT_FALSE(huge);
  EXPECT_NE(huge.error().message.find("2^32"), std::string::npos) << huge.error().message;
}

TEST(CityGenerator, OddOptionsStillGiveAValidCity) {
  CityOptions o = small_city(2);
  o.rows = o.columns = 20;  // paper 000, Fig. A-2: a dense model
  o.max_height = 3;         // lower than a floor and a half
  o.park_block_fraction = 1.0;
  o.tree_block_fraction = 1.0;
  o.tree_distance = 1.0;
  o.blocks_x = 3;
  const Scene s = generate(o);
  EXPECT_EQ(validate_scene(s), "");
  EXPECT_GT(s.triangle_count(), 0u);
  EXPECT_LE(s.bounds.max.y, 12.0f);  // trees stand over the low buildings
  o.park_block_fraction = 0.0;
  o.block_length = o.block_width = 7;  // no room for lots
  o.curb_width = 3;
  EXPECT_EQ(validate_scene(generate(o)), "");
}

}  // namespace
}  // namespace farfield
