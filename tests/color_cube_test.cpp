// Colour-cube compositing, averaging and leaf baking (paper 002, Sec. 4.1), on hand-made cubes.
#include <gtest/gtest.h>

#include "farfield/core/assert.hpp"
#include "farfield/gpu/lighting.hpp"
#include "farfield/scene/texture_image.hpp"
#include "farfield/techniques/colorcube/color_cube.hpp"
#include "farfield/techniques/colorcube/leaf_baker.hpp"

namespace farfield {
namespace {

constexpr float kEps = 1e-5f;

void expect_near(const glm::vec3& a, const glm::vec3& b, float eps = kEps) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

TEST(ColorCube, ModifiedOverKeepsOpaqueSurfacesOpaque) {
  const FaceColor red{{1, 0, 0}, 0.5f}, blue{{0, 0, 1}, 0.5f};
  const FaceColor c = composite(red, blue);
  EXPECT_NEAR(c.coverage, 1.0f, kEps);  // plain over would give 0.75
  expect_near(c.rgb, {0.5f, 0, 0.5f});
  // An opaque front hides the back entirely.
  const FaceColor hidden = composite({{0, 1, 0}, 1.0f}, blue);
  EXPECT_NEAR(hidden.coverage, 1.0f, kEps);
  expect_near(hidden.rgb, {0, 1, 0});
  // Coverage adds up to one at most; the back shows only in the front's gaps.
  const FaceColor partial = composite({{1, 1, 1}, 0.25f}, {{0, 0, 0}, 1.0f});
  EXPECT_NEAR(partial.coverage, 1.0f, kEps);
  expect_near(partial.rgb, {0.25f, 0.25f, 0.25f});
  // Empty over empty stays empty.
  EXPECT_EQ(composite({}, {}).coverage, 0.0f);
}

TEST(ColorCube, AverageIsWeightedByCoverage) {
  const FaceColor faces[] = {{{1, 0, 0}, 1.0f}, {{0, 0, 1}, 0.5f}, {}, {}};
  const FaceColor a = average(faces);
  EXPECT_NEAR(a.coverage, 1.5f / 4.0f, kEps);
  expect_near(a.rgb, {1.0f / 1.5f, 0, 0.5f / 1.5f});
  EXPECT_EQ(average(std::span<const FaceColor>{}).coverage, 0.0f);
}

TEST(ColorCube, CombineCompositesAlongTheFaceAxisThenAverages) {
  std::array<ColorCube, 8> children{};
  // Child 1 (upper X, lower Y and Z) is red on every face; child 0 (lower X) is blue.
  for (auto& f : children[1].faces) f = {{1, 0, 0}, 1.0f};
  for (auto& f : children[0].faces) f = {{0, 0, 1}, 1.0f};
  const ColorCube parent = combine(children);
  // From +X the red child is in front of the blue one: one column of four, red, covered.
  expect_near(parent.faces[0].rgb, {1, 0, 0});
  EXPECT_NEAR(parent.faces[0].coverage, 0.25f, kEps);
  // From -X the blue child is in front.
  expect_near(parent.faces[1].rgb, {0, 0, 1});
  // From +Y both are seen side by side, in two columns: the average of red and blue.
  expect_near(parent.faces[2].rgb, {0.5f, 0, 0.5f});
  EXPECT_NEAR(parent.faces[2].coverage, 0.5f, kEps);
}

// A unit cube cell at the origin and quads in it.
struct LeafScene {
  Scene scene;
  SceneBuilder builder{scene};
  uint32_t material = builder.add_material(Material{});

  // A quad on the plane x = `x`, facing +X, over y in [y0, y1], z in [0, 1].
  void quad_facing_x(float x, float y0, float y1, const glm::vec3& rgb) {
    builder.begin_object("q", ObjectKind::mesh, material);
    const uint32_t color = pack_color(glm::vec4(rgb, 1.0f));
    const glm::vec3 n(1, 0, 0);
    builder.add_vertex({x, y0, 0}, n, color);
    builder.add_vertex({x, y1, 0}, n, color);
    builder.add_vertex({x, y1, 1}, n, color);
    builder.add_vertex({x, y0, 1}, n, color);
    builder.add_triangle(0, 1, 2);  // counter-clockwise seen from +X
    builder.add_triangle(0, 2, 3);
    builder.end_object();
  }
  std::vector<uint32_t> all_triangles() const {
    std::vector<uint32_t> t(scene.triangle_count());
    for (uint32_t i = 0; i < t.size(); ++i) t[i] = i;
    return t;
  }
};

Bounds3 unit_cell() {
  Bounds3 b;
  b.min = glm::vec3(0.0f);
  b.max = glm::vec3(1.0f);
  return b;
}

TEST(LeafBaker, FaceIsTheAverageOfItsRenderedPixels) {
  LeafScene s;
  // With 4 x 4 pixels, red covers rows y in [0, 0.5): 8 pixels; green [0.5, 0.75): 4 pixels.
  s.quad_facing_x(0.5f, 0.0f, 0.5f, {1, 0, 0});
  s.quad_facing_x(0.5f, 0.5f, 0.75f, {0, 1, 0});
  const auto materials = triangle_materials(s.scene);
  const auto triangles = s.all_triangles();
  const glm::vec3 red = gpu::shade({1, 0, 0}, {1, 0, 0}), green = gpu::shade({1, 0, 0}, {0, 1, 0});
  for (CoverageMode mode : {CoverageMode::binary, CoverageMode::fraction}) {
    const auto cubes = bake_leaf(s.scene, materials, triangles, unit_cell(),
                                 {.oversampling = 4, .coverage = mode});
    ASSERT_EQ(cubes.size(), 1u);
    const FaceColor& f = cubes[0].faces[0];  // seen from +X
    expect_near(f.rgb, (8.0f * red + 4.0f * green) / 12.0f, 1e-4f);
    EXPECT_NEAR(f.coverage, mode == CoverageMode::binary ? 1.0f : 12.0f / 16.0f, kEps);
    // From -X the quads show their backs: culled, so the face is transparent.
    EXPECT_EQ(cubes[0].faces[1].coverage, 0.0f);
  }
}

TEST(LeafBaker, APolygonSeenEdgeOnGivesATransparentFace) {
  LeafScene s;
  s.quad_facing_x(0.5f, 0.0f, 1.0f, {1, 1, 1});
  const auto cubes = bake_leaf(s.scene, triangle_materials(s.scene), s.all_triangles(), unit_cell(),
                               {.oversampling = 5});
  EXPECT_EQ(cubes[0].faces[0].coverage, 1.0f);
  for (int face : {2, 3, 4, 5}) EXPECT_EQ(cubes[0].faces[face].coverage, 0.0f) << face;
}

TEST(LeafBaker, ClustersGiveEachSlabItsOwnColour) {
  LeafScene s;
  // Two parallel quads one behind the other; with 2 x 2 x 2 cubes each lands in its slab.
  s.quad_facing_x(0.75f, 0.0f, 1.0f, {1, 0, 0});
  s.quad_facing_x(0.25f, 0.0f, 1.0f, {0, 0, 1});
  const auto cubes = bake_leaf(s.scene, triangle_materials(s.scene), s.all_triangles(), unit_cell(),
                               {.oversampling = 2, .cluster = 2});
  ASSERT_EQ(cubes.size(), 8u);
  const glm::vec3 red = gpu::shade({1, 0, 0}, {1, 0, 0}), blue = gpu::shade({1, 0, 0}, {0, 0, 1});
  for (int y = 0; y < 2; ++y) {
    for (int z = 0; z < 2; ++z) {
      // Cube x = 1 holds the red quad, x = 0 the blue one hidden behind it from +X.
      expect_near(cubes[1 + 2 * (y + 2 * z)].faces[0].rgb, red, 1e-4f);
      expect_near(cubes[0 + 2 * (y + 2 * z)].faces[0].rgb, blue, 1e-4f);
    }
  }
  // The parent made from one cluster's cubes is red from +X: red in front.
  std::array<ColorCube, 8> children;
  for (int i = 0; i < 8; ++i) children[i] = cubes[i];
  expect_near(combine(children).faces[0].rgb, red, 1e-4f);
}

}  // namespace
}  // namespace farfield

namespace farfield {
namespace {

// A textured quad facing +Z over the unit cell's z = 0.5 plane, its texture left half red and
// right half blue (2 x 1 texels; mask cuts the blue half out when its alpha is 0).
Scene textured_leaf_scene(AlphaMode mode, uint8_t blue_alpha) {
  Scene scene;
  SceneBuilder b(scene);
  RgbaImage texels(2, 1);
  texels.texel(0, 0)[0] = 255;
  texels.texel(0, 0)[3] = 255;
  texels.texel(1, 0)[2] = 255;
  texels.texel(1, 0)[3] = blue_alpha;
  auto texture = texture_from_texels("halves.png", texels);
  FF_ASSERT(texture.ok(), "halves.png");
  const uint32_t t = b.add_texture(std::move(*texture));
  const uint32_t m = b.add_material(Material{.texture = t, .alpha_mode = mode});
  b.begin_object("quad", ObjectKind::mesh, m);
  const glm::vec3 n(0, 0, 1);
  b.add_vertex({0, 0, 0.5f}, n, 0xffffffffu, {0, 1});
  b.add_vertex({1, 0, 0.5f}, n, 0xffffffffu, {1, 1});
  b.add_vertex({1, 1, 0.5f}, n, 0xffffffffu, {1, 0});
  b.add_vertex({0, 1, 0.5f}, n, 0xffffffffu, {0, 0});
  b.add_triangle(0, 1, 2);
  b.add_triangle(0, 2, 3);
  b.end_object();
  return scene;
}

// The +Z face (index 4) of the cube of column (x, y) that the quad lies in (the one covered).
FaceColor seen_from_z(const std::vector<ColorCube>& cubes, int x, int y) {
  for (int z = 0; z < 2; ++z)
    if (cubes[size_t(x + 2 * (y + 2 * z))].faces[4].coverage > 0.0f)
      return cubes[size_t(x + 2 * (y + 2 * z))].faces[4];
  return {};
}

// Leaf cubes see textures as the renderer draws them: each column of a 2 x 2 x 2 split gets
// its half's texel colour, lit; a mask material's transparent half covers nothing.
TEST(LeafBaker, TexturesColourTheCubesAndMasksCutThemOut) {
  const std::vector<uint32_t> triangles = {0, 1};
  const glm::vec3 red = gpu::shade({0, 0, 1}, {1, 0, 0}), blue = gpu::shade({0, 0, 1}, {0, 0, 1});
  const Scene scene = textured_leaf_scene(AlphaMode::opaque, 255);
  auto textures = leaf_textures(scene);
  ASSERT_TRUE(textures);
  const LeafBakeOptions options{.oversampling = 4, .cluster = 2};
  const auto cubes =
      bake_leaf(scene, triangle_materials(scene), triangles, unit_cell(), options, *textures);
  for (int y = 0; y < 2; ++y) {
    expect_near(seen_from_z(cubes, 0, y).rgb, red, 1e-4f);
    expect_near(seen_from_z(cubes, 1, y).rgb, blue, 1e-4f);
  }
  // Without its textures the quad is white.
  const auto plain = bake_leaf(scene, triangle_materials(scene), triangles, unit_cell(), options);
  expect_near(seen_from_z(plain, 1, 0).rgb, gpu::shade({0, 0, 1}, {1, 1, 1}), 1e-4f);

  const Scene masked = textured_leaf_scene(AlphaMode::mask, 0);
  auto mask_textures = leaf_textures(masked);
  ASSERT_TRUE(mask_textures);
  const auto cut = bake_leaf(masked, triangle_materials(masked), triangles, unit_cell(), options,
                             *mask_textures);
  EXPECT_EQ(seen_from_z(cut, 0, 0).coverage, 1.0f);
  EXPECT_EQ(seen_from_z(cut, 1, 0).coverage, 0.0f);
  EXPECT_EQ(seen_from_z(cut, 1, 1).coverage, 0.0f);
}

}  // namespace
}  // namespace farfield
