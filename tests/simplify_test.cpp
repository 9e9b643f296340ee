// Mesh simplification (scene/simplify): triangle counts, stored errors against measured
// distances, hard edges, the sloppy fallback.
#include "farfield/scene/simplify.hpp"

#include <gtest/gtest.h>

#include <random>

#include <glm/geometric.hpp>

#include "farfield/core/progress.hpp"
#include "farfield/scene/tree_generator.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// A cube of side 2 centred at `centre`, each face an n x n grid of quads with its own
// (flat) normals, one object.
void add_grid_cube(SceneBuilder& b, const glm::vec3& centre, int n, uint32_t material) {
  b.begin_object("cube", ObjectKind::mesh, material);
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2) {
      glm::vec3 normal(0.0f);
      normal[axis] = float(sign);
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const uint32_t first = b.vertex_count();  // in the object, as add_triangle takes them
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          glm::vec3 p = centre;
          p[axis] += float(sign);
          p[u] += -1.0f + 2.0f * float(i) / float(n);
          p[v] += -1.0f + 2.0f * float(j) / float(n);
          b.add_vertex(p, normal, 0xffffffffu);
        }
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const uint32_t a = first + uint32_t(j * (n + 1) + i), c = a + 1, d = a + uint32_t(n + 1),
                         e = d + 1;
          // Counter-clockwise seen from outside: u x v = axis direction.
          if (sign > 0) {
            b.add_triangle(a, c, e);
            b.add_triangle(a, e, d);
          } else {
            b.add_triangle(a, e, c);
            b.add_triangle(a, d, e);
          }
        }
    }
  b.end_object();
}

std::vector<uint32_t> all_objects(const Scene& scene) {
  std::vector<uint32_t> out(scene.objects.size());
  for (uint32_t i = 0; i < out.size(); ++i) out[i] = i;
  return out;
}

TEST(Simplify, FarthestDistanceToATriangle) {
  MeshPart m;
  const uint32_t n = pack_normal({0, 0, 1});
  m.vertices = {{{0, 0, 0}, n, 0}, {{1, 0, 0}, n, 0}, {{0, 1, 0}, n, 0}};
  m.indices = {0, 1, 2};
  EXPECT_FLOAT_EQ(farthest_distance({{0.2f, 0.2f, 0.5f}}, m), 0.5f);   // above the inside
  EXPECT_FLOAT_EQ(farthest_distance({{-3.0f, 0.0f, 4.0f}}, m), 5.0f);  // nearest a corner
  EXPECT_FLOAT_EQ(farthest_distance({{0.2f, 0.2f, 0.0f}, {2.0f, 0.0f, 0.0f}}, m), 1.0f);
  EXPECT_EQ(farthest_distance({}, m), 0.0f);
}

// The tree's LOD chain: fewer triangles at each step, and the stored error bounds the
// distance from random points of either surface to the other.
TEST(Simplify, StoredErrorBoundsTheDistanceBetweenTheSurfaces) {
  Progress quiet(true);
  TreeOptions options;
  options.iterations = 4;
  options.objects = 1;
  auto tree = generate_tree(options, quiet);
  ASSERT_TRUE(tree) << tree.error().message;
  const MeshPart part = gather_part(*tree, all_objects(*tree), tree->objects[0].material);
  ASSERT_GT(part.triangle_count(), 1000u);
  uint64_t previous = part.triangle_count();
  for (double ratio : {0.5, 0.25, 0.1, 0.03}) {
    const SimplifiedPart lod = simplify_part(part, {.target_ratio = ratio});
    SCOPED_TRACE(testing::Message() << "ratio " << ratio << ", " << lod.mesh.triangle_count()
                                    << " triangles, error " << lod.error_m << " m");
    ASSERT_GT(lod.mesh.triangle_count(), 0u);
    EXPECT_LT(lod.mesh.triangle_count(), previous);
    EXPECT_LE(double(lod.mesh.triangle_count()), 1.3 * ratio * double(part.triangle_count()) + 4);
    EXPECT_TRUE(std::isfinite(lod.error_m));
    const float there = farthest_distance(test::random_surface_points(part, 4000, 1), lod.mesh);
    const float back = farthest_distance(test::random_surface_points(lod.mesh, 4000, 2), part);
    EXPECT_LE(there, lod.error_m * 1.001f + 1e-5f);
    EXPECT_LE(back, lod.error_m * 1.001f + 1e-5f);
    previous = lod.mesh.triangle_count();
  }
}

// A finely gridded cube simplifies to a cube: no distance lost, and every vertex keeps the
// normal of its face (the welded seams do not smooth the hard edges).
TEST(Simplify, HardEdgesStayHard) {
  Scene scene;
  SceneBuilder b(scene);
  const uint32_t m = b.add_material(Material{glm::vec4(1.0f)});
  add_grid_cube(b, glm::vec3(0.0f), 8, m);
  const MeshPart part = gather_part(scene, all_objects(scene), m);
  ASSERT_EQ(part.triangle_count(), 6u * 8 * 8 * 2);
  const SimplifiedPart lod = simplify_part(part, {.target_ratio = 0.02});
  EXPECT_LE(lod.mesh.triangle_count(), 24u);
  EXPECT_GE(lod.mesh.triangle_count(), 12u);
  // Exact, but the bound's resolution is the longest edge / (16 sqrt 3): 2.83 m / 28.
  EXPECT_LT(lod.error_m, 0.103f);
  for (size_t t = 0; t < lod.mesh.indices.size(); t += 3) {
    const glm::vec3 a = lod.mesh.vertices[lod.mesh.indices[t]].position,
                    c = lod.mesh.vertices[lod.mesh.indices[t + 1]].position,
                    d = lod.mesh.vertices[lod.mesh.indices[t + 2]].position;
    const glm::vec3 face = glm::normalize(glm::cross(c - a, d - a));
    for (int k = 0; k < 3; ++k)
      EXPECT_GT(
          glm::dot(unpack_normal(lod.mesh.vertices[lod.mesh.indices[t + size_t(k)]].normal), face),
          0.99f);
  }
}

// A plane whose vertices alternate black and white by column, simplified to a few triangles:
// each takes the mean colour of what it covers (mid grey; every fine triangle is 1/3 or 2/3
// grey), not the colour under its centre.
TEST(Simplify, ASimplifiedTriangleTakesTheMeanColourOfWhatItCovers) {
  constexpr int kSquares = 24;
  const uint32_t up = pack_normal({0, 0, 1});
  MeshPart plane;
  for (int j = 0; j <= kSquares; ++j)
    for (int i = 0; i <= kSquares; ++i)
      plane.vertices.push_back(
          {{float(i), float(j), 0.0f}, up, i % 2 ? 0xffffffffu : 0xff000000u});
  for (int j = 0; j < kSquares; ++j)
    for (int i = 0; i < kSquares; ++i) {
      const uint32_t a = uint32_t(j * (kSquares + 1) + i), b = a + 1,
                     c = a + uint32_t(kSquares + 1), d = c + 1;
      for (const uint32_t v : {a, b, d, a, d, c}) plane.indices.push_back(v);
    }
  const SimplifiedPart coarse =
      simplify_part(plane, {.target_ratio = 0.005, .allow_sloppy = false});
  ASSERT_GT(coarse.mesh.triangle_count(), 0u);
  ASSERT_LE(coarse.mesh.triangle_count(), 16u);
  double weighted = 0, area = 0;
  for (size_t t = 0; t < coarse.mesh.indices.size(); t += 3) {
    const Vertex& a = coarse.mesh.vertices[coarse.mesh.indices[t]];
    const glm::vec3 b = coarse.mesh.vertices[coarse.mesh.indices[t + 1]].position,
                    c = coarse.mesh.vertices[coarse.mesh.indices[t + 2]].position;
    const double size = 0.5 * glm::length(glm::cross(b - a.position, c - a.position));
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(coarse.mesh.vertices[coarse.mesh.indices[t + size_t(k)]].color, a.color);
    const int red = int(a.color & 0xffu);
    EXPECT_EQ(red, int(a.color >> 8 & 0xffu));
    EXPECT_EQ(a.color >> 24, 0xffu);
    // 64 samples of 85 or 170, a fair coin: within three of their standard deviations.
    if (size >= 16.0) {
      EXPECT_NEAR(red, 127.5, 16.0) << "a triangle of " << size << " squares";
    }
    weighted += size * red;
    area += size;
  }
  EXPECT_NEAR(area, double(kSquares * kSquares), 1e-3);
  EXPECT_NEAR(weighted / area, 127.5, 8.0);
}

// Many separate cubes cannot lose triangles without losing whole cubes: the sloppy simplifier
// takes over, and its error says how far the surfaces moved. An error limit is kept.
TEST(Simplify, SeparatePartsFallBackToTheSloppySimplifier) {
  Scene scene;
  SceneBuilder b(scene);
  const uint32_t m = b.add_material(Material{glm::vec4(1.0f)});
  for (int i = 0; i < 64; ++i)
    add_grid_cube(b, glm::vec3(float(i % 8) * 3.0f, 0.0f, float(i / 8) * 3.0f), 1, m);
  const MeshPart part = gather_part(scene, all_objects(scene), m);
  const SimplifiedPart lod = simplify_part(part, {.target_ratio = 0.1});
  EXPECT_TRUE(lod.sloppy);
  EXPECT_LT(lod.mesh.triangle_count(), part.triangle_count() / 2);
  EXPECT_GT(lod.error_m, 0.5f);
  EXPECT_LE(farthest_distance(test::random_surface_points(part, 4000, 3), lod.mesh),
            lod.error_m * 1.001f + 1e-5f);
  const SimplifiedPart strict = simplify_part(part, {.target_ratio = 0.1, .allow_sloppy = false});
  EXPECT_FALSE(strict.sloppy);
  EXPECT_EQ(strict.mesh.triangle_count(), part.triangle_count());
  EXPECT_LT(strict.error_m, 0.103f);
}

TEST(Simplify, AnErrorLimitStopsEarly) {
  Progress quiet(true);
  TreeOptions options;
  options.iterations = 4;
  options.objects = 1;
  auto tree = generate_tree(options, quiet);
  ASSERT_TRUE(tree);
  const MeshPart part = gather_part(*tree, all_objects(*tree), tree->objects[0].material);
  const SimplifiedPart free = simplify_part(part, {.target_ratio = 0.05});
  const SimplifiedPart limited =
      simplify_part(part, {.target_ratio = 0.05, .max_error_m = free.error_m * 0.1f});
  EXPECT_GT(limited.mesh.triangle_count(), free.mesh.triangle_count());
  EXPECT_LT(limited.error_m, free.error_m);
}

}  // namespace
}  // namespace farfield
