// glTF 2.0 export: hand-made scenes read back through assimp (geometry, names, materials,
// textures), object selection, the command line with its refusals, a round trip through
// `import`, and the Khronos validator where web/'s npm packages are installed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/GltfMaterial.h>

#include "farfield/scene/glb_export.hpp"
#include "farfield/scene/scene_file.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

const aiScene* read_back(Assimp::Importer& importer, const std::string& glb) {
  return importer.ReadFileFromMemory(glb.data(), glb.size(), aiProcess_ValidateDataStructure,
                                     "glb");
}

TEST(GlbExport, ReadsBackThroughAssimp) {
  // A box of the row's opaque material, and a textured quad cut out by its texture's alpha.
  Scene scene = test::make_textured_scene(AlphaMode::mask);
  scene.materials[scene.objects[1].material].double_sided = 1;
  scene.materials[scene.objects[1].material].wrap_u = TextureWrap::clamp;
  GlbSummary summary;
  auto glb = encode_glb(scene, {}, &summary);
  ASSERT_TRUE(glb) << glb.error().message;
  EXPECT_EQ(summary.objects, 2u);
  EXPECT_EQ(summary.triangles, scene.triangle_count());
  EXPECT_EQ(summary.textures, 1u);
  EXPECT_EQ(summary.bytes, glb->size());
  Assimp::Importer importer;
  const aiScene* read = read_back(importer, *glb);
  ASSERT_NE(read, nullptr) << importer.GetErrorString();
  ASSERT_EQ(read->mRootNode->mNumChildren, 2u);
  for (unsigned i = 0; i < 2; ++i) {
    const Object& o = scene.objects[i];
    const aiNode* node = read->mRootNode->mChildren[i];
    EXPECT_EQ(std::string(node->mName.C_Str()), std::string(scene.object_name(o)));
    ASSERT_EQ(node->mNumMeshes, 1u);
    const aiMesh* mesh = read->mMeshes[node->mMeshes[0]];
    ASSERT_EQ(mesh->mNumFaces, o.triangle_count());
    ASSERT_EQ(mesh->mNumVertices, o.vertex_count);
    for (unsigned f = 0; f < mesh->mNumFaces; ++f)
      for (unsigned c = 0; c < 3; ++c) {
        const uint32_t index = scene.indices[o.first_index + 3 * f + c];
        const aiVector3D p = mesh->mVertices[mesh->mFaces[f].mIndices[c]];
        EXPECT_EQ(glm::vec3(p.x, p.y, p.z), scene.vertices[index].position);
        EXPECT_EQ(mesh->mFaces[f].mIndices[c], index - o.first_vertex);
      }
    ASSERT_TRUE(mesh->HasNormals() && mesh->HasVertexColors(0));
    const glm::vec4 colour = unpack_color(scene.vertices[o.first_vertex].color);
    EXPECT_NEAR(mesh->mColors[0][0].r, colour.r, 1e-6);
    EXPECT_EQ(mesh->HasTextureCoords(0), scene.textured(o));
    if (scene.textured(o))
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        // assimp turns glTF's top-left origin to the bottom left (import turns it back).
        EXPECT_FLOAT_EQ(mesh->mTextureCoords[0][v].x, scene.uvs[o.first_uv + v].x);
        EXPECT_FLOAT_EQ(1.0f - mesh->mTextureCoords[0][v].y, scene.uvs[o.first_uv + v].y);
      }
    const aiMaterial* material = read->mMaterials[mesh->mMaterialIndex];
    aiString mode;
    ASSERT_EQ(material->Get(AI_MATKEY_GLTF_ALPHAMODE, mode), AI_SUCCESS);
    EXPECT_EQ(std::string(mode.C_Str()), i == 1 ? "MASK" : "OPAQUE");
    int two_sided = 0;
    material->Get(AI_MATKEY_TWOSIDED, two_sided);
    EXPECT_EQ(two_sided != 0, i == 1);
  }
  // The texture travels as the PNG it was, embedded.
  ASSERT_EQ(read->mNumTextures, 1u);
  EXPECT_EQ(read->mTextures[0]->mHeight, 0u);
  ASSERT_EQ(read->mTextures[0]->mWidth, scene.textures[0].encoded.size());
  EXPECT_EQ(std::memcmp(read->mTextures[0]->pcData, scene.textures[0].encoded.data(),
                        scene.textures[0].encoded.size()),
            0);
}

// An instance whose prototype is exported too places the prototype's mesh with its transform
// as the node's matrix: the model once in the file, every copy where the scene has it. Without
// its prototype (another --objects) it is a mesh of its own.
TEST(GlbExport, InstancesPlaceTheirPrototypesMesh) {
  Scene scene = test::make_box_row(1);
  SceneBuilder b(scene);
  const glm::mat3 turn(glm::vec3(0, 0, -2), glm::vec3(0, 2, 0), glm::vec3(2, 0, 0));
  b.add_instance("moved", ObjectKind::mesh, 0, glm::mat3(1.0f), {10.0f, 0.0f, 0.0f});
  b.add_instance("turned", ObjectKind::mesh, 0, turn, {0.0f, 0.0f, 20.0f});
  GlbSummary summary;
  auto glb = encode_glb(scene, {}, &summary);
  ASSERT_TRUE(glb) << glb.error().message;
  EXPECT_EQ(summary.objects, 3u);
  EXPECT_EQ(summary.triangles, scene.triangle_count());
  Assimp::Importer importer;
  const aiScene* read = read_back(importer, *glb);
  ASSERT_NE(read, nullptr) << importer.GetErrorString();
  EXPECT_EQ(read->mNumMeshes, 1u);
  ASSERT_EQ(read->mRootNode->mNumChildren, 3u);
  for (unsigned i = 0; i < 3; ++i) {
    const Object& o = scene.objects[i];
    const aiNode* node = read->mRootNode->mChildren[i];
    EXPECT_EQ(std::string(node->mName.C_Str()), std::string(scene.object_name(o)));
    ASSERT_EQ(node->mNumMeshes, 1u);
    const aiMesh* mesh = read->mMeshes[node->mMeshes[0]];
    ASSERT_EQ(mesh->mNumVertices, o.vertex_count);
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D p = node->mTransformation * mesh->mVertices[v];
      EXPECT_LT(glm::length(glm::vec3(p.x, p.y, p.z) - scene.vertices[o.first_vertex + v].position),
                1e-4f)
          << "object " << i << " vertex " << v;
    }
  }
  // The turned copy alone: its own mesh, no matrix.
  auto alone = encode_glb(scene, {.objects = "turned"});
  ASSERT_TRUE(alone);
  const aiScene* one = read_back(importer, *alone);
  ASSERT_NE(one, nullptr);
  // Assimp makes a glTF scene's only node its root.
  const aiNode* node = one->mRootNode;
  ASSERT_EQ(node->mNumChildren, 0u);
  ASSERT_EQ(node->mNumMeshes, 1u);
  EXPECT_EQ(std::string(node->mName.C_Str()), "turned");
  EXPECT_TRUE(node->mTransformation.IsIdentity());
  EXPECT_EQ(one->mMeshes[0]->mVertices[0].z, scene.vertices[scene.objects[2].first_vertex].position.z);
}

TEST(GlbExport, ExportsTheObjectsAskedAndRefusesNone) {
  const Scene scene = test::make_box_row(3);
  GlbSummary summary;
  auto one = encode_glb(scene, {.objects = std::string(scene.object_name(scene.objects[1]))},
                        &summary);
  ASSERT_TRUE(one) << one.error().message;
  EXPECT_EQ(summary.objects, 1u);
  EXPECT_EQ(summary.triangles, scene.objects[1].triangle_count());
  EXPECT_EQ(summary.textures, 0u);
  auto all = encode_glb(scene, {.objects = "*"}, &summary);
  ASSERT_TRUE(all);
  EXPECT_EQ(summary.objects, 3u);
  auto none = encode_glb(scene, {.objects = "no such*"});
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().message.find("no object matches --objects 'no such*'"),
            std::string::npos)
      << none.error().message;
}

TEST(GlbCli, ExportsImportsAgainAndRefusesBadOptions) {
  test::TempDir dir;
  using test::run_farfield;
  ASSERT_EQ(run_farfield("generate city --blocks 1 --textures -q --out " + dir.file("c.ffscene"))
                .exit_status,
            0);
  auto r = run_farfield("export " + dir.file("c.ffscene") + " --out " + dir.file("c.glb"));
  ASSERT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("wrote "), std::string::npos) << r.output;
  r = run_farfield("import -q " + dir.file("c.glb") + " --out " + dir.file("again.ffscene"));
  ASSERT_EQ(r.exit_status, 0) << r.output;
  auto source = read_scene(dir.file("c.ffscene")), again = read_scene(dir.file("again.ffscene"));
  ASSERT_TRUE(source && again);
  EXPECT_EQ(again->triangle_count(), source->triangle_count());
  EXPECT_EQ(again->objects.size(), source->objects.size());
  EXPECT_EQ(again->textures.size(), source->textures.size());

  struct Bad {
    std::string args;
    int status;
    std::string says;
  };
  const Bad bad[] = {
      {"export " + dir.file("c.ffscene") + " --format obj --out " + dir.file("b.glb"), 2, "obj"},
      {"export " + dir.file("c.ffscene") + " --out " + dir.file("b.gltf"), 2, "b.gltf"},
      {"export " + dir.file("missing.ffscene") + " --out " + dir.file("b.glb"), 1,
       "missing.ffscene"},
      {"export " + dir.file("c.ffscene") + " --objects 'nothing*' --out " + dir.file("b.glb"), 1,
       "nothing*"},
      {"export " + dir.file("c.ffscene") + " --out " + dir.file("no/folder/b.glb"), 1, "b.glb"},
  };
  for (const Bad& b : bad) {
    auto refused = run_farfield(b.args);
    EXPECT_EQ(refused.exit_status, b.status) << b.args << "\n" << refused.output;
    EXPECT_NE(refused.output.find(b.says), std::string::npos) << refused.output;
  }
  EXPECT_FALSE(std::filesystem::exists(dir.file("b.glb"))) << "a refused export wrote its file";
}

TEST(GlbCli, PassesTheKhronosValidator) {
  const std::string web = std::string(FARFIELD_SOURCE_DIR) + "/web";
  if (!std::filesystem::exists(web + "/node_modules/gltf-validator") ||
      std::system("node --version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the glTF validator is not installed (make deps: npm ci in web/)";
  test::TempDir dir;
  using test::run_farfield;
  ASSERT_EQ(run_farfield("generate city --blocks 1 --textures -q --out " + dir.file("c.ffscene"))
                .exit_status,
            0);
  ASSERT_EQ(run_farfield("generate tree -q --out " + dir.file("t.ffscene")).exit_status, 0);
  ASSERT_EQ(run_farfield("generate field -q --count 4 --mesh " + dir.file("t.ffscene") +
                         " --out " + dir.file("f.ffscene"))
                .exit_status,
            0);
  for (const char* name : {"c", "t", "f"})
    ASSERT_EQ(run_farfield("export " + dir.file(std::string(name) + ".ffscene") + " --out " +
                           dir.file(std::string(name) + ".glb"))
                  .exit_status,
              0);
  const test::CommandResult r = test::run_shell("node " + web + "/validate_glb.mjs " +
                                                 dir.file("c.glb") + " " + dir.file("t.glb") +
                                                 " " + dir.file("f.glb"));
  const std::string& output = r.output;
  EXPECT_EQ(r.exit_status, 0) << output;
  EXPECT_NE(output.find("c.glb: 0 errors"), std::string::npos) << output;
  EXPECT_NE(output.find("t.glb: 0 errors"), std::string::npos) << output;
  EXPECT_NE(output.find("f.glb: 0 errors"), std::string::npos) << output;
}

}  // namespace
}  // namespace farfield
