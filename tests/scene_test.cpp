#include "farfield/scene/scene.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/scene/field_generator.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

TEST(Scene, MedianTriangleEdgeIsTheTypicalLongestEdge) {
  EXPECT_EQ(median_triangle_edge(Scene{}), 0.0f);
  const Scene boxes = test::make_box_row(3);  // unit boxes: every longest edge a face diagonal
  EXPECT_NEAR(median_triangle_edge(boxes), std::sqrt(2.0f), 1e-5f);
  EXPECT_NEAR(median_triangle_edge(boxes, 5), std::sqrt(2.0f), 1e-5f);  // sampled
}

TEST(Scene, NormalsSurvivePackingWithinAQuarterDegree) {
  for (float a = 0.0f; a < 6.28f; a += 0.1f) {
    for (float b = -1.5f; b < 1.5f; b += 0.1f) {
      const glm::vec3 n(std::cos(a) * std::cos(b), std::sin(b), std::sin(a) * std::cos(b));
      const glm::vec3 back = glm::normalize(unpack_normal(pack_normal(n)));
      EXPECT_GT(glm::dot(n, back), std::cos(glm::radians(0.25f))) << a << " " << b;
      EXPECT_EQ(pack_normal(unpack_normal(pack_normal(n))), pack_normal(n));
    }
  }
  EXPECT_EQ(unpack_normal(pack_normal({0, 1, 0})), glm::vec3(0, 1, 0));
  EXPECT_EQ(unpack_normal(pack_normal({0, 0, -1})), glm::vec3(0, 0, -1));
}

TEST(Scene, ColorsPackToBytes) {
  EXPECT_EQ(pack_color({1, 0, 0, 1}), 0xff0000ffu);
  EXPECT_EQ(pack_color({2, -1, 0.5f, 0}), 0x008000ffu);  // clamped
  EXPECT_EQ(unpack_color(0xff0000ffu), glm::vec4(1, 0, 0, 1));
}

TEST(Scene, BuilderKeepsRangesBoundsAndNames) {
  const Scene scene = test::make_box_row(3);
  ASSERT_EQ(scene.objects.size(), 3u);
  EXPECT_EQ(scene.triangle_count(), 36u);
  EXPECT_EQ(scene.materials.size(), 2u);
  EXPECT_EQ(scene.object_name(scene.objects[2]), "box_2");
  EXPECT_EQ(scene.objects[1].first_index, 36u);
  EXPECT_EQ(scene.objects[1].first_vertex, 24u);
  EXPECT_EQ(scene.objects[2].bounds.min, glm::vec3(4, 0, 0));
  EXPECT_EQ(scene.bounds.max, glm::vec3(5, 1, 1));
  EXPECT_EQ(validate_scene(scene), "");
  EXPECT_EQ(scene.byte_size(), 3 * 64 + 2 * 32 + 72 * 20 + 108 * 4 + scene.names.size());
}

// Texture coordinates are kept for textured objects only; the scene validates their ranges.
TEST(Scene, TexturedObjectsAloneHoldTextureCoordinates) {
  Scene scene = test::make_textured_scene();
  ASSERT_EQ(validate_scene(scene), "");
  ASSERT_EQ(scene.objects.size(), 2u);
  EXPECT_FALSE(scene.textured(scene.objects[0]));
  EXPECT_TRUE(scene.textured(scene.objects[1]));
  EXPECT_EQ(scene.uvs.size(), scene.objects[1].vertex_count);
  EXPECT_EQ(scene.objects[1].first_uv, 0u);
  EXPECT_EQ(scene.texture_bytes(), scene.textures[0].encoded.size());
  Scene broken = scene;
  broken.uvs.pop_back();
  EXPECT_NE(validate_scene(broken).find("texture coordinates out of range"), std::string::npos);
  broken = scene;
  broken.materials[scene.objects[1].material].texture = 7;
  EXPECT_NE(validate_scene(broken).find("texture out of range"), std::string::npos);
  broken = scene;
  broken.materials[scene.objects[1].material].alpha_mode = AlphaMode(9);
  EXPECT_NE(validate_scene(broken).find("alpha mode"), std::string::npos);
  broken = scene;
  broken.textures[0].encoded.clear();
  EXPECT_NE(validate_scene(broken).find("empty image"), std::string::npos);
  // A scene whose materials are colours alone hashes them as version 1 did (the 16-byte
  // colours: SceneFile.Version1FilesStillRead); any other material field counts.
  Scene plain = test::make_box_row(2);
  const uint64_t before = scene_fingerprint(plain);
  plain.materials[0].double_sided = 1;  // drawn differently: another fingerprint
  EXPECT_NE(scene_fingerprint(plain), before);
  broken = scene;
  broken.uvs[0].x += 1.0f;
  EXPECT_NE(scene_fingerprint(broken), scene_fingerprint(scene));
}

TEST(Scene, EmptyObjectsAreDropped) {
  Scene scene;
  SceneBuilder b(scene);
  const uint32_t m = b.add_material({});
  b.begin_object("nothing", ObjectKind::mesh, m);
  b.add_vertex({0, 0, 0}, {0, 1, 0}, 0);
  b.end_object();
  EXPECT_TRUE(scene.objects.empty());
  EXPECT_TRUE(scene.vertices.empty());
  EXPECT_TRUE(scene.names.empty());
  EXPECT_TRUE(scene.bounds.empty());
}

TEST(Scene, ValidationNamesTheBrokenInvariant) {
  auto broken = [](auto&& edit) {
    Scene scene = test::make_box_row(2);
    edit(scene);
    return validate_scene(scene);
  };
  EXPECT_NE(broken([](Scene& s) { s.objects[1].material = 9; }).find("material"),
            std::string::npos);
  EXPECT_NE(broken([](Scene& s) { s.objects[0].index_count += 3; }).find("index"),
            std::string::npos);
  EXPECT_NE(broken([](Scene& s) { s.objects[0].name_size = 999; }).find("name"), std::string::npos);
  EXPECT_NE(broken([](Scene& s) { s.objects[0].kind = ObjectKind(200); }).find("kind"),
            std::string::npos);
  EXPECT_NE(broken([](Scene& s) { s.indices[40] = 3; }).find("object's vertex range"),
            std::string::npos);
  EXPECT_NE(broken([](Scene& s) { s.vertices[5].position.y = NAN; }).find("finite"),
            std::string::npos);
}

TEST(FieldGenerator, CopiesStandOnTheGroundOnAGrid) {
  const Scene model = test::make_box_row(2);  // two materials: folded into vertex colours
  Progress quiet(true);
  auto field = generate_field(model, {.count = 5, .spacing = 10.0}, quiet);
  ASSERT_TRUE(field) << field.error().message;
  ASSERT_EQ(field->objects.size(), 5u);
  EXPECT_EQ(validate_scene(*field), "");
  EXPECT_EQ(field->triangle_count(), 5 * model.triangle_count());
  EXPECT_EQ(field->materials.size(), 1u);
  EXPECT_LT(field->materials[0].base_color.a, 1.0f);  // the model has a transparent part
  // 3 to a row: centres at x = -10, 0, 10 and z = -5, 5.
  EXPECT_FLOAT_EQ(field->objects[0].bounds.center().x, -10.0f);
  EXPECT_FLOAT_EQ(field->objects[4].bounds.center().x, 0.0f);
  EXPECT_FLOAT_EQ(field->objects[4].bounds.center().z, 5.0f);
  EXPECT_FLOAT_EQ(field->bounds.min.y, 0.0f);
  EXPECT_EQ(field->object_name(field->objects[3]), "copy_3");
  // The transparent box's colour carries its material's tint.
  const glm::vec4 c = unpack_color(field->vertices[24].color);
  EXPECT_NEAR(c.b, 1.0f, 0.01f);
  EXPECT_NEAR(c.r, 0.5f, 0.01f);
  // make_box_row(2) holds a building and a mesh: its copies are meshes; a model of one kind
  // gives copies of that kind.
  EXPECT_EQ(field->objects[0].kind, ObjectKind::mesh);
  Scene trees = model;
  for (Object& o : trees.objects) o.kind = ObjectKind::tree;
  auto grove = generate_field(trees, {.count = 2, .spacing = 10.0}, quiet);
  ASSERT_TRUE(grove);
  EXPECT_EQ(grove->objects[1].kind, ObjectKind::tree);
}

TEST(FieldGenerator, RejectsBadOptions) {
  const Scene model = test::make_box_row(1);
  Progress quiet(true);
  EXPECT_FALSE(generate_field(model, {.count = 0, .spacing = 1.0}, quiet));
  EXPECT_FALSE(generate_field(model, {.count = 1, .spacing = -1.0}, quiet));
  EXPECT_FALSE(generate_field(model, {.count = 1, .spacing = NAN}, quiet));
  EXPECT_FALSE(generate_field(Scene{}, {.count = 1, .spacing = 1.0}, quiet));
  auto huge = generate_field(model, {.count = 1ull << 40, .spacing = 1.0}, quiet);
  ASSERT_FALSE(huge);
  EXPECT_NE(huge.error().message.find("2^32"), std::string::npos);
}

}  // namespace
}  // namespace farfield
