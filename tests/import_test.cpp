#include "farfield/scene/import.hpp"
#include "farfield/scene/scene_file.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/geometric.hpp>

#include "farfield/scene/texture_image.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using test::same_bytes;

using test::TempDir;
using test::write_file;

// Debian's assimp-testmodels: real models that nobody here wrote.
const std::filesystem::path kTestModels = "/usr/share/assimp/models";

const Object* find_object(const Scene& scene, std::string_view name) {
  for (const Object& o : scene.objects)
    if (scene.object_name(o) == name) return &o;
  return nullptr;
}

bool same_scene(const Scene& a, const Scene& b) {
  return same_bytes(a.objects, b.objects) && same_bytes(a.materials, b.materials) &&
         same_bytes(a.vertices, b.vertices) && a.indices == b.indices && a.names == b.names &&
         a.bounds.min == b.bounds.min && a.bounds.max == b.bounds.max;
}

// Two objects, each with its own material from the .mtl.
void write_obj(const TempDir& dir) {
  write_file(dir.file("two.mtl"),
             "newmtl red\nKd 1 0 0\n"
             "newmtl glass\nKd 0 0 1\nd 0.5\n");
  write_file(dir.file("two.obj"),
             "mtllib two.mtl\n"
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
             "v 0 0 2\nv 1 0 2\nv 0 1 2\n"
             "o wall\nusemtl red\nf 1 2 3 4\n"
             "o pane\nusemtl glass\nf 5 6 7\n");
}

// A glTF triangle (0,0,0) (1,0,0) (0,1,0), front face +Z, instanced by a node moved by
// (10,0,0) and a node mirrored in X and moved by (0,0,5). `x0` is the first coordinate.
void write_gltf(const TempDir& dir, const std::string& name, float x0 = 0.0f) {
  const float xyz[9] = {x0, 0, 0, 1, 0, 0, 0, 1, 0};
  write_file(dir.file(name + ".bin"), std::string(reinterpret_cast<const char*>(xyz), sizeof(xyz)));
  write_file(dir.file(name + ".gltf"), R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"name": "moved", "mesh": 0, "translation": [10, 0, 0]},
              {"name": "mirrored", "mesh": 0, "scale": [-1, 1, 1], "translation": [0, 0, 5]}],
    "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
    "materials": [{"name": "green", "pbrMetallicRoughness": {"baseColorFactor": [0, 1, 0, 1]}}],
    "buffers": [{"uri": ")" + name + R"(.bin", "byteLength": 36}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]}]})");
}

// A unit cube as a PLY: 8 vertices, 6 quads (12 triangles).
std::string cube_ply(bool binary) {
  const float v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                         {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int f[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                       {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  std::string s = std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") +
                  " 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 6\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : v) {
    if (binary)
      s.append(reinterpret_cast<const char*>(p), sizeof(p));
    else
      s += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  }
  for (const auto& q : f) {
    if (binary) {
      s += char(4);
      s.append(reinterpret_cast<const char*>(q), sizeof(q));  // little-endian host
    } else {
      s += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) +
           " " + std::to_string(q[3]) + "\n";
    }
  }
  return s;
}

// Expects `path` to be refused with a message naming it and containing `what`, leaving a
// scene that already holds a model exactly as it was.
void expect_refused(const std::string& path, const std::string& what) {
  static const Scene before = [] {
    TempDir dir;
    write_obj(dir);
    Scene scene;
    EXPECT_TRUE(import_model(dir.file("two.obj"), scene).ok());
    return scene;
  }();
  Scene scene = before;
  const Result<void> r = import_model(path, scene);
  ASSERT_FALSE(r.ok()) << path;
  EXPECT_NE(r.error().message.find(path), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find(what), std::string::npos) << r.error().message;
  EXPECT_TRUE(same_scene(scene, before)) << path;
}

TEST(Import, UpAxisAndScaleTurnAndSizeTheModel) {
  // A triangle standing 1000 units up along +Z: in a Z-up file in millimetres, 1 m up.
  TempDir dir;
  test::write_file(dir.file("z.obj"), "v 0 0 0\nv 1000 0 0\nv 0 0 1000\nf 1 2 3\n");
  Scene as_is, turned;
  ASSERT_TRUE(import_model(dir.file("z.obj"), as_is).ok());
  ASSERT_TRUE(import_model(dir.file("z.obj"), turned, {.up = 'z', .scale = 0.001}).ok());
  EXPECT_FLOAT_EQ(as_is.bounds.size().z, 1000.0f);
  EXPECT_FLOAT_EQ(as_is.bounds.size().y, 0.0f);
  EXPECT_NEAR(turned.bounds.max.y, 1.0f, 1e-6);  // up is +Y, in metres
  EXPECT_NEAR(turned.bounds.size().x, 1.0f, 1e-6);
  EXPECT_NEAR(turned.bounds.size().z, 0.0f, 1e-6);
  // The normal turns with it: perpendicular to the triangle, which now lies in the XY plane.
  EXPECT_NEAR(std::abs(unpack_normal(turned.vertices[0].normal).z), 1.0f, 1e-2);
  for (const ImportOptions& bad :
       {ImportOptions{.up = 'x'}, ImportOptions{.scale = 0.0}, ImportOptions{.scale = -1.0}}) {
    Scene scene;
    EXPECT_FALSE(import_model(dir.file("z.obj"), scene, bad).ok());
    EXPECT_TRUE(scene.objects.empty());
  }
}

TEST(Import, FbxUnitsBecomeMetres) {
  // assimp's test models (Debian's assimp-testmodels, which make installs): the same spider as
  // OBJ (no units) and as FBX in centimetres (UnitScaleFactor 1) arrive the same size.
  const std::string models = "/usr/share/assimp/models/";
  if (!std::filesystem::exists(models + "FBX/spider.fbx"))
    GTEST_SKIP() << "assimp-testmodels missing";
  Scene obj, fbx;
  ASSERT_TRUE(import_model(models + "OBJ/spider.obj", obj).ok());
  // The FBX names its textures by the absolute Windows paths it was made with, and none of
  // them lies beside it.
  EXPECT_FALSE(import_model(models + "FBX/spider.fbx", fbx).ok());
  ImportOptions drop;
  drop.drop_bad_textures = true;
  ImportReport report;
  ASSERT_TRUE(import_model(models + "FBX/spider.fbx", fbx, drop, &report).ok());
  EXPECT_FALSE(report.dropped_textures.empty());
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(fbx.bounds.size()[a], obj.bounds.size()[a], 0.01f) << a;
}

TEST(Import, ObjKeepsObjectNamesAndDiffuseColours) {
  TempDir dir;
  write_obj(dir);
  Scene scene;
  ASSERT_TRUE(import_model(dir.file("two.obj"), scene).ok());
  EXPECT_EQ(validate_scene(scene), "");
  ASSERT_EQ(scene.objects.size(), 2u);
  const Object* wall = find_object(scene, "wall");
  const Object* pane = find_object(scene, "pane");
  ASSERT_TRUE(wall && pane) << scene.names;
  EXPECT_EQ(wall->triangle_count(), 2u);  // the quad, triangulated
  EXPECT_EQ(pane->triangle_count(), 1u);
  EXPECT_EQ(scene.materials[wall->material].base_color, glm::vec4(1, 0, 0, 1));
  EXPECT_EQ(scene.materials[pane->material].base_color, glm::vec4(0, 0, 1, 0.5f));
  EXPECT_EQ(wall->kind, ObjectKind::mesh);
  EXPECT_EQ(scene.vertices[wall->first_vertex].color, 0xffffffffu);  // no vertex colours: white
  EXPECT_EQ(scene.bounds.min, glm::vec3(0, 0, 0));
  EXPECT_EQ(scene.bounds.max, glm::vec3(1, 1, 2));
}

TEST(Import, GltfNodeTransformsMoveAndMirror) {
  TempDir dir;
  write_gltf(dir, "tri");
  Scene scene;
  const Result<void> r = import_model(dir.file("tri.gltf"), scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(validate_scene(scene), "");
  const Object* moved = find_object(scene, "moved/tri");
  const Object* mirrored = find_object(scene, "mirrored/tri");
  ASSERT_TRUE(moved && mirrored) << scene.names;
  EXPECT_EQ(moved->bounds.min, glm::vec3(10, 0, 0));
  EXPECT_EQ(moved->bounds.max, glm::vec3(11, 1, 0));
  EXPECT_EQ(mirrored->bounds.min, glm::vec3(-1, 0, 5));
  EXPECT_EQ(mirrored->bounds.max, glm::vec3(0, 1, 5));
  EXPECT_EQ(scene.materials[moved->material].base_color, glm::vec4(0, 1, 0, 1));
  for (const Object* o : {moved, mirrored}) {
    ASSERT_EQ(o->triangle_count(), 1u);
    const uint32_t* t = &scene.indices[o->first_index];
    const glm::vec3 a = scene.vertices[t[0]].position, b = scene.vertices[t[1]].position,
                    c = scene.vertices[t[2]].position;
    const glm::vec3 face = glm::normalize(glm::cross(b - a, c - a));
    for (int k = 0; k < 3; ++k) {
      // The mirror keeps the front face +Z: normals follow, and the winding is flipped to agree.
      EXPECT_NEAR(glm::dot(unpack_normal(scene.vertices[t[k]].normal), glm::vec3(0, 0, 1)), 1.0f,
                  0.01f);
      EXPECT_NEAR(glm::dot(face, glm::vec3(0, 0, 1)), 1.0f, 1e-5f);
    }
  }
}

TEST(Import, ColladaZUpBecomesYUp) {
  TempDir dir;
  write_file(dir.file("pole.dae"), R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="1" name="meter"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="tri" name="tri"><mesh>
    <source id="tri-pos">
      <float_array id="tri-pos-array" count="9">0 0 0 1 0 0 0 0 3</float_array>
      <technique_common><accessor source="#tri-pos-array" count="3" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common>
    </source>
    <vertices id="tri-vtx"><input semantic="POSITION" source="#tri-pos"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#tri-vtx" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene">
    <node id="pole" name="pole"><translate>5 0 0</translate><instance_geometry url="#tri"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>)");
  Scene scene;
  const Result<void> r = import_model(dir.file("pole.dae"), scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_EQ(scene.object_name(scene.objects[0]), "pole/tri");
  // Moved 5 along X; the pole's 3 metres along Z (up in the file) are 3 metres along +Y.
  const Bounds3& b = scene.bounds;
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(b.min[axis], glm::vec3(5, 0, 0)[axis], 1e-5f) << axis;
    EXPECT_NEAR(b.max[axis], glm::vec3(6, 3, 0)[axis], 1e-5f) << axis;
  }
}

TEST(Import, SeveralFilesMakeOneScene) {
  TempDir dir;
  write_obj(dir);
  write_gltf(dir, "tri");
  write_file(dir.file("cube.ply"), cube_ply(true));
  const std::vector<std::string> paths{dir.file("two.obj"), dir.file("tri.gltf"),
                                       dir.file("cube.ply")};
  Progress quiet(true);
  Result<Scene> scene = import_models(paths, quiet);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(validate_scene(*scene), "");
  EXPECT_EQ(scene->objects.size(), 5u);
  EXPECT_EQ(scene->triangle_count(), 3u + 2u + 12u);
  EXPECT_TRUE(find_object(*scene, "wall") && find_object(*scene, "moved/tri"));
  EXPECT_TRUE(find_object(*scene, "cube/0")) << scene->names;  // unnamed: file stem + index
  EXPECT_EQ(scene->bounds.min, glm::vec3(-1, 0, 0));
  EXPECT_EQ(scene->bounds.max, glm::vec3(11, 1, 5));
  EXPECT_EQ(scene->materials.size(), 4u);  // red, glass, green, the PLY's default

  // The first failing file stops the import and is named.
  const std::vector<std::string> with_missing{dir.file("two.obj"), dir.file("nope.obj")};
  Result<Scene> failed = import_models(with_missing, quiet);
  ASSERT_FALSE(failed.ok());
  EXPECT_NE(failed.error().message.find("nope.obj: no such file"), std::string::npos);
}

TEST(Import, MissingEmptyAndNonModelFilesAreRefused) {
  TempDir dir;
  expect_refused(dir.file("missing.obj"), "no such file");
  expect_refused(dir.path().string(), "is a directory");
  write_file(dir.file("empty.obj"), "");
  expect_refused(dir.file("empty.obj"), "file is empty");
  std::mt19937 random(7);
  std::string noise(4096, '\0');
  for (char& c : noise) c = char(random());
  write_file(dir.file("noise.ply"), noise);
  expect_refused(dir.file("noise.ply"), "not a readable model");
  write_file(dir.file("words.stl"), "these are not the triangles you are looking for\n");
  expect_refused(dir.file("words.stl"), "not a readable model");
  write_file(dir.file("points.ply"),
             "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
             "property float y\nproperty float z\nend_header\n0 0 0\n");
  expect_refused(dir.file("points.ply"), "contains no triangles");
  write_file(dir.file("lines.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\n");
  expect_refused(dir.file("lines.obj"), "contains no triangles");
}

TEST(Import, NonFiniteCoordinatesAreRefused) {
  TempDir dir;
  write_gltf(dir, "inf", std::numeric_limits<float>::infinity());
  expect_refused(dir.file("inf.gltf"), "non-finite");
}

// Imports `bytes` whole, then every cut of it shorter than `complete` bytes, which must be
// refused; cuts longer than the magic word must be called truncated.
void expect_cuts_refused(const std::string& name, const std::string& bytes, size_t complete,
                         size_t magic, uint64_t triangles) {
  TempDir dir;
  write_file(dir.file(name), bytes);
  Scene whole;
  const Result<void> r = import_model(dir.file(name), whole);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(whole.triangle_count(), triangles);
  for (size_t cut = 1; cut < complete; ++cut) {
    const std::string path = dir.file(std::to_string(cut) + "_" + name);
    write_file(path, bytes.substr(0, cut));
    expect_refused(path, cut > magic ? "truncated" : "");
  }
}

TEST(Import, EveryCutOfABinaryPlyIsRefused) {
  const std::string ply = cube_ply(true);
  expect_cuts_refused("cube.ply", ply, ply.size(), 3, 12);
}

TEST(Import, EveryCutOfAnAsciiPlyIsRefused) {
  const std::string ply = cube_ply(false);
  expect_cuts_refused("cube.ply", ply, ply.find_last_not_of('\n'), 3, 12);  // the last digit
}

TEST(Import, EveryCutOfAnOffIsRefused) {
  const std::string off = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
  expect_cuts_refused("quad.off", off, off.size() - 2, 3, 2);
}

TEST(Import, EveryCutOfAnAsciiStlIsRefused) {
  const std::string stl =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
      "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
  expect_cuts_refused("t.stl", stl, stl.rfind("endsolid") + 8, 5, 1);
}

TEST(Import, CountsBeyondTheFileAreRefused) {
  TempDir dir;
  // The headers promise more than the files hold; assimp would try to allocate it all.
  write_file(dir.file("huge.off"), "OFF\n353535235358 6 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expect_refused(dir.file("huge.off"), "truncated OFF");
  write_file(dir.file("huge.ply"),
             "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
             "property float x\nelement face 1\n"
             "property list uchar int vertex_indices\nend_header\n1234");
  expect_refused(dir.file("huge.ply"), "truncated PLY");
  write_file(dir.file("cut.ifc"), "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\n");
  expect_refused(dir.file("cut.ifc"), "truncated STEP/IFC");
}

// ---- real models from assimp-testmodels ----------------------------------------------------

struct Expected {
  uint64_t objects = 0, triangles = 0;
};

// Counts what an import must give, straight from assimp with the same steps: every (node,
// mesh) instance with triangles is an object.
Expected count_with_assimp(const std::string& path) {
  Assimp::Importer importer;
  importer.SetPropertyBool(AI_CONFIG_PP_FD_REMOVE, true);
  importer.SetPropertyBool(AI_CONFIG_PP_FD_CHECKAREA, false);
  const aiScene* s =
      importer.ReadFile(path, aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                                  aiProcess_FindDegenerates | aiProcess_SortByPType |
                                  aiProcess_GenSmoothNormals | aiProcess_JoinIdenticalVertices);
  Expected e;
  if (!s) return e;
  std::function<void(const aiNode*)> walk = [&](const aiNode* node) {
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
      const aiMesh* m = s->mMeshes[node->mMeshes[i]];
      uint64_t triangles = 0;
      for (unsigned f = 0; f < m->mNumFaces; ++f) triangles += m->mFaces[f].mNumIndices == 3;
      e.objects += triangles > 0;
      e.triangles += triangles;
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) walk(node->mChildren[c]);
  };
  walk(s->mRootNode);
  return e;
}

class ImportTestModels : public ::testing::TestWithParam<const char*> {};

TEST_P(ImportTestModels, CountsMatchAssimp) {
  if (!std::filesystem::is_directory(kTestModels))
    GTEST_SKIP() << "assimp-testmodels not installed";
  const std::string path = (kTestModels / GetParam()).string();
  const Expected expected = count_with_assimp(path);
  ASSERT_GT(expected.triangles, 0u) << path;
  Scene scene;
  const Result<void> r = import_model(path, scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(validate_scene(scene), "");
  EXPECT_EQ(scene.objects.size(), expected.objects);
  EXPECT_EQ(scene.triangle_count(), expected.triangles);
  EXPECT_FALSE(scene.bounds.empty());
  std::printf("%s: %zu objects, %llu triangles, %zu materials, bounds (%g %g %g)-(%g %g %g)\n",
              GetParam(), scene.objects.size(),
              static_cast<unsigned long long>(scene.triangle_count()), scene.materials.size(),
              scene.bounds.min.x, scene.bounds.min.y, scene.bounds.min.z, scene.bounds.max.x,
              scene.bounds.max.y, scene.bounds.max.z);
}

INSTANTIATE_TEST_SUITE_P(Import, ImportTestModels,
                         ::testing::Values("OBJ/spider.obj", "PLY/Wuson.ply",
                                           "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
                                           "IFC/AC14-FZK-Haus.ifc"));

TEST(Import, TestModelNamesColoursAndUpAxis) {
  if (!std::filesystem::is_directory(kTestModels))
    GTEST_SKIP() << "assimp-testmodels not installed";
  Scene spider;
  ASSERT_TRUE(import_model((kTestModels / "OBJ/spider.obj").string(), spider).ok());
  EXPECT_TRUE(find_object(spider, "HLeib01")) << spider.names;
  EXPECT_GT(spider.materials.size(), 1u);
  // The IFC house on its plot: +Y up, so lower than it is wide and deep.
  Scene house;
  ASSERT_TRUE(import_model((kTestModels / "IFC/AC14-FZK-Haus.ifc").string(), house).ok());
  const glm::vec3 size = house.bounds.size();
  EXPECT_LT(size.y, std::min(size.x, size.z)) << size.x << " " << size.y << " " << size.z;
}

TEST(Import, TruncatedTestModelsAreRefused) {
  if (!std::filesystem::is_directory(kTestModels))
    GTEST_SKIP() << "assimp-testmodels not installed";
  TempDir dir;
  for (const char* name : {"PLY/Wuson.ply", "PLY/cube_binary.ply", "IFC/AC14-FZK-Haus.ifc"}) {
    const std::string bytes = test::read_file((kTestModels / name).string());
    for (size_t percent : {1, 10, 50, 90, 99}) {
      const std::string path =
          dir.file(std::to_string(percent) + "_" + std::filesystem::path(name).filename().string());
      write_file(path, bytes.substr(0, bytes.size() * percent / 100));
      expect_refused(path, "truncated");
    }
  }
}

}  // namespace
}  // namespace farfield

namespace farfield {
namespace {

// The base-colour texture of every textured test model is found (beside the file, in its
// .bin, embedded as base64, or under an absolute path the model was authored with) and
// decodes; its objects carry texture coordinates.
TEST(Import, TexturedTestModelsKeepTheirTextures) {
  if (!std::filesystem::is_directory(kTestModels))
    GTEST_SKIP() << "assimp-testmodels not installed";
  struct Case {
    const char* file;
    size_t textures;
  };
  for (const Case& c :
       {Case{"glTF2/BoxTextured-glTF/BoxTextured.gltf", 1},
        Case{"glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", 1},
        Case{"glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf", 1}, Case{"OBJ/spider.obj", 4},
        Case{"AC/SphereWithLight.ac", 1}, Case{"Collada/duck.dae", 1}}) {
    Scene scene;
    const Result<void> r = import_model((kTestModels / c.file).string(), scene);
    ASSERT_TRUE(r.ok()) << c.file << ": " << r.error().message;
    EXPECT_EQ(validate_scene(scene), "") << c.file;
    EXPECT_EQ(scene.textures.size(), c.textures) << c.file;
    uint64_t textured_vertices = 0;
    for (const Object& o : scene.objects)
      if (scene.textured(o)) textured_vertices += o.vertex_count;
    EXPECT_GT(textured_vertices, 0u) << c.file;
    EXPECT_EQ(scene.uvs.size(), textured_vertices) << c.file;
    for (const Texture& t : scene.textures) {
      auto texels = decode_texture(t);
      EXPECT_TRUE(texels) << c.file << ": " << (texels ? "" : texels.error().message);
    }
  }
  // glTF doubleSided becomes a double-sided material.
  Scene two_sided;
  ASSERT_TRUE(import_model((kTestModels / "glTF2/BoxTexcoords-glTF/boxTexcoords.gltf").string(),
                           two_sided));
  EXPECT_EQ(two_sided.materials[two_sided.objects[0].material].double_sided, 1);
  // glTF's texture coordinates are kept as the file has them (origin top-left): the box's
  // are within [0, 1].
  Scene box;
  ASSERT_TRUE(
      import_model((kTestModels / "glTF2/BoxTextured-glTF/BoxTextured.gltf").string(), box));
  for (const glm::vec2& uv : box.uvs) {
    EXPECT_GE(uv.x, 0.0f);
    EXPECT_LE(uv.y, 1.0f);
  }
}

// A texture that is missing or does not decode refuses the import, naming the file, and
// leaves the scene as it was; drop_bad_textures imports the colour and reports the texture.
TEST(Import, MissingAndCorruptTexturesAreRefusedOrDropped) {
  if (!std::filesystem::is_directory(kTestModels))
    GTEST_SKIP() << "assimp-testmodels not installed";
  TempDir dir;
  const std::filesystem::path box = kTestModels / "glTF2/BoxTextured-glTF";
  std::filesystem::copy_file(box / "BoxTextured.gltf", dir.file("box.gltf"));
  std::filesystem::copy_file(box / "BoxTextured0.bin", dir.file("BoxTextured0.bin"));
  Scene scene = test::make_box_row(1);
  const Scene before = scene;
  Result<void> missing = import_model(dir.file("box.gltf"), scene);
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("CesiumLogoFlat.png"), std::string::npos)
      << missing.error().message;
  EXPECT_NE(missing.error().message.find("not found"), std::string::npos);
  EXPECT_TRUE(same_scene(scene, before));
  EXPECT_TRUE(scene.textures.empty() && scene.uvs.empty());

  write_file(dir.file("CesiumLogoFlat.png"), "\x89PNG but then nothing of the kind");
  Result<void> corrupt = import_model(dir.file("box.gltf"), scene);
  ASSERT_FALSE(corrupt);
  EXPECT_NE(corrupt.error().message.find("CesiumLogoFlat.png"), std::string::npos);
  EXPECT_TRUE(same_scene(scene, before));

  ImportReport report;
  ImportOptions options;
  options.drop_bad_textures = true;
  ASSERT_TRUE(import_model(dir.file("box.gltf"), scene, options, &report));
  EXPECT_TRUE(scene.textures.empty());
  ASSERT_EQ(report.dropped_textures.size(), 1u);
  EXPECT_NE(report.dropped_textures[0].find("CesiumLogoFlat.png"), std::string::npos);
  EXPECT_EQ(scene.objects.size(), 2u);
  EXPECT_FALSE(scene.textured(scene.objects[1]));
}

}  // namespace
}  // namespace farfield

namespace farfield {
namespace {

// A mesh placed by several nodes (the engine's repeated parts): its later placements are
// instances of its first, stored once, and the scene is the one imported without them, up to
// float rounding.
TEST(Import, RepeatedMeshesBecomeInstancesOfTheirFirstPlacement) {
  if (!std::filesystem::is_directory(kTestModels))
    GTEST_SKIP() << "assimp-testmodels not installed";
  const std::string engine =
      (kTestModels / "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb").string();
  Scene with, without;
  ASSERT_TRUE(import_model(engine, with));
  ASSERT_TRUE(import_model(engine, without, ImportOptions{.instances = false}));
  EXPECT_EQ(validate_scene(with), "");
  EXPECT_GT(with.instances.size(), 50u);
  EXPECT_TRUE(without.instances.empty());
  ASSERT_EQ(with.objects.size(), without.objects.size());
  ASSERT_EQ(with.vertices.size(), without.vertices.size());
  EXPECT_EQ(with.names, without.names);
  EXPECT_TRUE(test::same_bytes(with.indices, without.indices));
  const float tolerance = 1e-5f * glm::length(with.bounds.size());
  for (size_t v = 0; v < with.vertices.size(); ++v) {
    ASSERT_LT(glm::length(with.vertices[v].position - without.vertices[v].position), tolerance)
        << "vertex " << v;
    ASSERT_LT(glm::length(unpack_normal(with.vertices[v].normal) -
                          unpack_normal(without.vertices[v].normal)),
              0.01f)
        << "vertex " << v;
  }
  TempDir dir;
  ASSERT_TRUE(write_scene(with, dir.file("with.ffscene")));
  ASSERT_TRUE(write_scene(without, dir.file("without.ffscene")));
  EXPECT_LT(std::filesystem::file_size(dir.file("with.ffscene")) * 3 / 2,
            std::filesystem::file_size(dir.file("without.ffscene")));
  auto read = read_scene(dir.file("with.ffscene"));
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(scene_fingerprint(*read), scene_fingerprint(with));
}

}  // namespace
}  // namespace farfield
