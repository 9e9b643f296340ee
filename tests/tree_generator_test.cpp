#include "farfield/scene/tree_generator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <glm/geometric.hpp>
#include <map>
#include <set>
#include <string>

#include "farfield/scene/scene_file.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using test::same_bytes;

Scene generate(const TreeOptions& options) {
  Progress quiet(true);
  auto scene = generate_tree(options, quiet);
  EXPECT_TRUE(scene) << scene.error().message;
  return scene ? std::move(scene).value() : Scene{};
}

const Scene& default_tree() {
  static const Scene tree = generate(TreeOptions{});
  return tree;
}

TreeOptions small_tree(uint32_t iterations = 3) {
  TreeOptions o;
  o.iterations = iterations;
  return o;
}

glm::vec3 face_normal(const Scene& s, size_t i) {
  const glm::vec3 a = s.vertices[s.indices[i]].position, b = s.vertices[s.indices[i + 1]].position,
                  c = s.vertices[s.indices[i + 2]].position;
  return glm::cross(b - a, c - a);
}

bool is_leaf(const Vertex& v) {  // leaves are green, bark is brown (red over green)
  const glm::vec4 c = unpack_color(v.color);
  return c.g > c.r;
}

TEST(TreeGenerator, SameOptionsGiveTheSameTree) {
  const Scene a = generate(small_tree(4)), b = generate(small_tree(4));
  ASSERT_GT(a.triangle_count(), 0u);
  EXPECT_TRUE(same_bytes(a.vertices, b.vertices));
  EXPECT_TRUE(same_bytes(a.indices, b.indices));
  EXPECT_TRUE(same_bytes(a.objects, b.objects));
  EXPECT_TRUE(same_bytes(a.materials, b.materials));
  EXPECT_EQ(a.names, b.names);
  TreeOptions other = small_tree(4);
  other.seed = 2;
  EXPECT_FALSE(same_bytes(a.vertices, generate(other).vertices));
}

// The sub-linear experiment (paper 002, Sec. 6.3) wants 256 trees to reach 10M triangles.
TEST(TreeGenerator, DefaultTreeHasAboutFiftyThousandTrianglesInTwentyEightObjects) {
  const Scene& s = default_tree();
  EXPECT_EQ(validate_scene(s), "");
  EXPECT_GE(256 * s.triangle_count(), 10'000'000u);
  EXPECT_LE(s.triangle_count(), 70'000u);
  ASSERT_EQ(s.objects.size(), 28u);
  EXPECT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].base_color, glm::vec4(1.0f));
  std::set<std::string_view> names;
  for (const Object& o : s.objects) {
    EXPECT_EQ(o.kind, ObjectKind::tree);
    EXPECT_TRUE(names.insert(s.object_name(o)).second) << s.object_name(o);
  }
  EXPECT_TRUE(names.contains("tree/trunk"));
  EXPECT_TRUE(names.contains("tree/subtree_26"));
  // The subtrees are the parts to cull: none holds most of the tree.
  for (const Object& o : s.objects) EXPECT_LT(o.triangle_count(), s.triangle_count() / 8);
}

TEST(TreeGenerator, TrianglesGrowWithIterations) {
  uint64_t last = 0;
  for (uint32_t n = 1; n <= 5; ++n) {
    const Scene s = generate(small_tree(n));
    EXPECT_EQ(validate_scene(s), "") << n;
    EXPECT_GT(s.triangle_count(), 2 * last) << n;
    last = s.triangle_count();
  }
  TreeOptions more = small_tree(4);
  more.sides = 16, more.leaves = 20;
  EXPECT_GT(generate(more).triangle_count(), 1.9 * generate(small_tree(4)).triangle_count());
}

// Leaves are two quads facing opposite ways, so back-face culling keeps one of them; every
// triangle, leaf or branch, winds counter-clockwise seen from the side its normals face.
TEST(TreeGenerator, LeavesShowFromBothSidesAndFacesAgreeWithNormals) {
  const Scene s = generate(small_tree(3));
  std::map<std::array<float, 9>, std::vector<glm::vec3>> faces;  // sorted corners -> normals
  size_t leaves = 0, wrong = 0;
  for (size_t i = 0; i < s.indices.size(); i += 3) {
    const glm::vec3 face = face_normal(s, i);
    glm::vec3 normal(0.0f);
    std::array<glm::vec3, 3> corners;
    for (int k = 0; k < 3; ++k) {
      normal += unpack_normal(s.vertices[s.indices[i + k]].normal);
      corners[k] = s.vertices[s.indices[i + k]].position;
    }
    wrong += glm::dot(face, normal) <= 0.0f;
    if (!is_leaf(s.vertices[s.indices[i]])) continue;
    ++leaves;
    std::sort(corners.begin(), corners.end(), [](const glm::vec3& a, const glm::vec3& b) {
      return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    });
    std::array<float, 9> key;
    std::memcpy(key.data(), corners.data(), sizeof key);
    faces[key].push_back(glm::normalize(face));
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(leaves, 27u * 10u * 4u);  // 3^3 twigs, 10 leaves each, 4 triangles a leaf
  for (const auto& [corners, normals] : faces) {
    ASSERT_EQ(normals.size(), 2u);
    EXPECT_LT(glm::dot(normals[0], normals[1]), -0.99f);
  }
}

TEST(TreeGenerator, StandsOnTheOriginAndIsAsTallAsAsked) {
  for (double height : {3.0, 10.0, 40.0}) {
    TreeOptions o = small_tree(4);
    o.height = height;
    const Scene s = generate(o);
    EXPECT_NEAR(s.bounds.min.y, 0.0f, 1e-4f) << height;
    EXPECT_GE(s.bounds.max.y, height - 1e-3) << height;         // the top branch
    EXPECT_LE(s.bounds.max.y, height + o.leaf_size) << height;  // and its leaves
    EXPECT_LT(s.bounds.size().x, 2.0 * height) << height;
  }
}

TEST(TreeGenerator, RunsAnyLSystem) {
  TreeOptions o;
  o.axiom = "X";
  o.rules = {"X=F[+X][-X]FX", "F=FF"};  // ABOP Fig. 1.24 (f), in 3D
  o.iterations = 4;
  o.objects = 1;
  o.leaves = 0;
  const Scene s = generate(o);
  EXPECT_EQ(validate_scene(s), "");
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.object_name(s.objects[0]), "tree");
  EXPECT_GT(s.triangle_count(), 100u * 2 * o.sides);
  for (const Vertex& v : s.vertices) EXPECT_FALSE(is_leaf(v));

  Progress quiet(true);
  o.rules = {"X=+X"};  // draws nothing
  auto none = generate_tree(o, quiet);
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().message.find("no branch"), std::string::npos) << none.error().message;
  o.axiom = "F";
  o.rules = {"F=FFFFFFFFFF"};
  o.iterations = 12;
  auto huge = generate_tree(o, quiet);
  ASSERT_FALSE(huge);
  EXPECT_NE(huge.error().message.find("--iterations"), std::string::npos);
}

TEST(TreeGenerator, OddOptionsStillGiveAValidTree) {
  TreeOptions o = small_tree(5);
  o.length_ratio = o.radius_ratio = o.segment_taper = 1e-30;  // under float resolution
  o.jitter = 0.5;
  o.branch_angle_deg = 180.0;
  o.divergence_deg = 360.0;
  o.sides = 3;
  o.objects = 100000;
  EXPECT_EQ(validate_scene(generate(o)), "");
  o = small_tree(2);
  o.axiom = "|F[&F]";  // turned round: nothing rises above the base
  Progress quiet(true);
  auto down = generate_tree(o, quiet);
  ASSERT_FALSE(down);
  EXPECT_NE(down.error().message.find("never rise"), std::string::npos) << down.error().message;
}

TEST(TreeGenerator, RejectsBadOptionsNamingThem) {
  auto message = [](auto change) {
    TreeOptions o;
    change(o);
    auto ok = validate_tree_options(o);
    return ok ? std::string("accepted") : ok.error().message;
  };
  EXPECT_EQ(message([](TreeOptions& o) { o.iterations = 13; }),
            "--iterations must be in [0, 12] (got 13)");
  const std::pair<void (*)(TreeOptions&), const char*> cases[] = {
      {[](TreeOptions& o) { o.branch_angle_deg = NAN; }, "--branch-angle"},
      {[](TreeOptions& o) { o.divergence_deg = -1; }, "--divergence"},
      {[](TreeOptions& o) { o.length_ratio = 0; }, "--length-ratio"},
      {[](TreeOptions& o) { o.radius_ratio = 1.5; }, "--radius-ratio"},
      {[](TreeOptions& o) { o.segment_taper = 0; }, "--taper"},
      {[](TreeOptions& o) { o.jitter = 0.9; }, "--jitter"},
      {[](TreeOptions& o) { o.height = 0; }, "--height"},
      {[](TreeOptions& o) { o.height = INFINITY; }, "--height"},
      {[](TreeOptions& o) { o.leaf_size = -1; }, "--leaf-size"},
      {[](TreeOptions& o) { o.leaves = 5000; }, "--leaves"},
      {[](TreeOptions& o) { o.sides = 2; }, "--sides"},
      {[](TreeOptions& o) { o.objects = 0; }, "--objects"},
      {[](TreeOptions& o) { o.axiom = ""; }, "--axiom"},
      {[](TreeOptions& o) { o.axiom = "F]"; }, "--axiom 'F]'"},
      {[](TreeOptions& o) { o.rules = {"A"}; }, "--rule 'A'"},
      {[](TreeOptions& o) { o.rules = {"A=F[A"}; }, "'[' without ']'"},
      {[](TreeOptions& o) { o.rules = {"A=F(2)"}; }, "'(' is not a symbol"},
      {[](TreeOptions& o) {
         o.rules = {"A=F", "A=FF"};
       },
       "a second rule for 'A'"},
  };
  for (const auto& [change, expected] : cases) {
    const std::string m = message(change);
    EXPECT_NE(m.find(expected), std::string::npos) << expected << ": " << m;
  }
  EXPECT_EQ(message([](TreeOptions&) {}), "accepted");
}

TEST(TreeGenerator, CommandLineWritesATreeAndAFieldOfThem) {
  test::TempDir dir;
  auto r = test::run_farfield("generate tree --out t.ffscene --iterations 3 --seed 4 -q",
                              dir.path().string());
  ASSERT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("wrote t.ffscene: "), std::string::npos) << r.output;
  auto tree = read_scene(dir.file("t.ffscene"));
  ASSERT_TRUE(tree) << tree.error().message;
  TreeOptions o = small_tree(3);
  o.seed = 4;
  EXPECT_TRUE(same_bytes(tree->vertices, generate(o).vertices));

  r = test::run_farfield(
      "generate field --mesh t.ffscene --count 4 --spacing 15 --out f.ffscene -q",
      dir.path().string());
  ASSERT_EQ(r.exit_status, 0) << r.output;
  auto field = read_scene(dir.file("f.ffscene"));
  ASSERT_TRUE(field) << field.error().message;
  EXPECT_EQ(field->triangle_count(), 4 * tree->triangle_count());

  r = test::run_farfield("generate tree --out bad.ffscene --sides 2", dir.path().string());
  EXPECT_EQ(r.exit_status, 1) << r.output;
  EXPECT_NE(r.output.find("--sides"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad.ffscene")));
}

}  // namespace
}  // namespace farfield
