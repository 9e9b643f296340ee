// The command line as users and scripts meet it: exit statuses, messages, nothing half-written.
#include <gtest/gtest.h>

#include <random>

#include "farfield/scene/scene_file.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using test::run_farfield;
using test::TempDir;

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

TEST(Cli, HelpExplainsEveryCommand) {
  auto r = run_farfield("--help");
  EXPECT_EQ(r.exit_status, 0);
  for (const char* word : {"generate", "import", "info"})
    EXPECT_NE(r.output.find(word), std::string::npos) << word;
  r = run_farfield("generate city --help");
  EXPECT_EQ(r.exit_status, 0);
  for (const char* option : {"--seed", "--target-triangles", "--max-height", "--block-length",
                             "--block-width", "--rows", "--columns", "--blocks", "--street-width",
                             "--street-height", "--curb-width", "--curb-height", "--tree-distance"})
    EXPECT_NE(r.output.find(option), std::string::npos) << option;
}

TEST(Cli, UsageErrorsExitTwo) {
  TempDir dir;
  for (const char* args :
       {"", "--bogus", "info", "info a b", "generate", "generate city",
        "generate city --out x.ffscene --bogus", "generate city --out x.ffscene --rows many",
        "import --out x.ffscene", "teleport"}) {
    auto r = run_farfield(args, dir.path().string());
    EXPECT_EQ(r.exit_status, 2) << args << "\n" << r.output;
    EXPECT_FALSE(r.output.empty()) << args;
    EXPECT_TRUE(dir.entries().empty()) << args;
  }
  auto r = run_farfield("generate city --out x.ffscene --bogus");
  EXPECT_NE(r.output.find("--bogus"), std::string::npos) << r.output;
}

TEST(Cli, MessagesNameTheProblemOnce) {
  TempDir dir;
  // An unknown command is named as such, with the known ones.
  auto r = run_farfield("benc");
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.output.find("farfield: unknown command 'benc'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bench"), std::string::npos) << r.output;
  // CLI11's errors carry the prefix and one pointer to the command's help.
  r = run_farfield("bench --bogus");
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(r.output.rfind("farfield: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find("farfield bench --help"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("Run with --help"), std::string::npos) << r.output;
  // The option the user gave is the one named; numbers as written.
  r = run_farfield("generate city --blocks 0 --out " + quoted(dir.file("x.ffscene")));
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.output.find("--blocks"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("--blocks-x"), std::string::npos) << r.output;
  ASSERT_TRUE(write_scene(test::make_box_row(1), dir.file("one.ffscene")));
  r = run_farfield("path " + quoted(dir.file("one.ffscene")) + " --kind orbit --frames 1 --out " +
                   quoted(dir.file("p.json")));
  EXPECT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find(", 1 frame,"), std::string::npos) << r.output;
  r = run_farfield("bench " + quoted(dir.file("one.ffscene")) + " --path " +
                   quoted(dir.file("p.json")) + " --hfov 200 --out " + quoted(dir.file("b")));
  EXPECT_EQ(r.exit_status, 2);  // the same limits as view's, checked by the command line
  EXPECT_NE(r.output.find("--hfov"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("200"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("200.000000"), std::string::npos) << r.output;
  r = run_farfield("bench " + quoted(dir.file("one.ffscene")) + " --path " +
                   quoted(dir.file("p.json")) + " --frames 5 --out " + quoted(dir.file("b")));
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_NE(r.output.find("has only 1 frame"), std::string::npos) << r.output;
  // A file of another kind is called what it seems to be.
  r = run_farfield("info " + quoted(dir.file("p.json")));
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_NE(r.output.find("it is JSON"), std::string::npos) << r.output;
  // A screenshot name farfield cannot write is refused before the window opens.
  r = run_farfield("view " + quoted(dir.file("one.ffscene")) + " --screenshot " +
                   quoted(dir.file("s.gif")));
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.output.find(".png, .jpg or .jpeg"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("b")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("s.gif")));
}

TEST(Cli, InfoRefusesBrokenScenes) {
  TempDir dir;
  ASSERT_TRUE(write_scene(test::make_box_row(3), dir.file("good.ffscene")));
  const std::string bytes = test::read_file(dir.file("good.ffscene"));
  test::write_file(dir.file("cut.ffscene"), bytes.substr(0, bytes.size() / 2));
  std::string flipped = bytes;
  flipped[bytes.size() - 100] ^= 0x10;
  test::write_file(dir.file("flip.ffscene"), flipped);
  test::write_file(dir.file("empty.ffscene"), "");

  auto good = run_farfield("info " + quoted(dir.file("good.ffscene")));
  EXPECT_EQ(good.exit_status, 0) << good.output;
  EXPECT_NE(good.output.find("triangles:   36"), std::string::npos) << good.output;
  EXPECT_NE(good.output.find("building"), std::string::npos) << good.output;

  const std::pair<const char*, const char*> cases[] = {{"cut.ffscene", "truncated"},
                                                       {"flip.ffscene", "corrupted"},
                                                       {"empty.ffscene", "empty"},
                                                       {"missing.ffscene", "No such file"}};
  for (const auto& [name, expected] : cases) {
    auto r = run_farfield("info " + quoted(dir.file(name)));
    EXPECT_EQ(r.exit_status, 1) << name;
    EXPECT_NE(r.output.find(name), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
  }
}

TEST(Cli, ImportRefusesBadFilesAndWritesNothing) {
  TempDir dir;
  test::write_file(dir.file("empty.obj"), "");
  std::mt19937 random(7);
  std::string noise(4096, '\0');
  for (char& c : noise) c = static_cast<char>(random());
  test::write_file(dir.file("noise.ply"), noise);
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n";
  const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  ply.append(reinterpret_cast<const char*>(xyz), sizeof(xyz) - 8);  // cut inside the vertices
  test::write_file(dir.file("cut.ply"), ply);

  const std::pair<const char*, const char*> cases[] = {{"missing.obj", "no such file"},
                                                       {"empty.obj", "empty"},
                                                       {"noise.ply", "noise.ply"},
                                                       {"cut.ply", "cut.ply"}};
  for (const auto& [name, expected] : cases) {
    const auto before = dir.entries();
    auto r = run_farfield("import " + quoted(dir.file(name)) + " --out " +
                          quoted(dir.file("out.ffscene")));
    EXPECT_EQ(r.exit_status, 1) << name << "\n" << r.output;
    EXPECT_NE(r.output.find(name), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
    EXPECT_EQ(dir.entries(), before) << name;
  }
}

TEST(Cli, ImportRefusesAMissingTextureUnlessAskedToDropIt) {
  const std::filesystem::path box = "/usr/share/assimp/models/glTF2/BoxTextured-glTF";
  if (!std::filesystem::is_directory(box)) GTEST_SKIP() << "assimp-testmodels not installed";
  TempDir dir;
  std::filesystem::copy_file(box / "BoxTextured.gltf", dir.file("box.gltf"));
  std::filesystem::copy_file(box / "BoxTextured0.bin", dir.file("BoxTextured0.bin"));
  const auto before = dir.entries();
  auto r = run_farfield("import " + quoted(dir.file("box.gltf")) + " --out " +
                        quoted(dir.file("box.ffscene")));
  EXPECT_EQ(r.exit_status, 1) << r.output;
  EXPECT_NE(r.output.find("CesiumLogoFlat.png: texture not found"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--drop-bad-textures"), std::string::npos) << r.output;
  EXPECT_EQ(dir.entries(), before);
  r = run_farfield("import " + quoted(dir.file("box.gltf")) + " --drop-bad-textures --out " +
                   quoted(dir.file("box.ffscene")));
  EXPECT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("dropped a texture, kept the colour"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("0 textures"), std::string::npos) << r.output;
  std::filesystem::copy_file(box / "CesiumLogoFlat.png", dir.file("CesiumLogoFlat.png"));
  r = run_farfield("import " + quoted(dir.file("box.gltf")) + " --out " +
                   quoted(dir.file("box.ffscene")));
  EXPECT_EQ(r.exit_status, 0) << r.output;
  auto info = run_farfield("info " + quoted(dir.file("box.ffscene")));
  EXPECT_NE(info.output.find("textures:    1 ("), std::string::npos) << info.output;
}

TEST(Cli, GenerateCityIsDeterministicAndInfoReadsIt) {
  TempDir dir;
  const std::string args = " --blocks 2 --rows 3 --columns 3 --seed 5 -q --out ";
  auto a = run_farfield("generate city" + args + quoted(dir.file("a.ffscene")));
  auto b = run_farfield("generate city" + args + quoted(dir.file("b.ffscene")));
  ASSERT_EQ(a.exit_status, 0) << a.output;
  ASSERT_EQ(b.exit_status, 0) << b.output;
  EXPECT_EQ(test::read_file(dir.file("a.ffscene")), test::read_file(dir.file("b.ffscene")));
  auto info = run_farfield("info " + quoted(dir.file("a.ffscene")));
  EXPECT_EQ(info.exit_status, 0);
  for (const char* kind : {"building", "street", "curb"})
    EXPECT_NE(info.output.find(kind), std::string::npos) << info.output;
}

TEST(Cli, GenerateBuildingGivesRoomsAndAnInteriorPath) {
  TempDir dir;
  auto r = run_farfield("generate building --floors 2 --rooms 4 --books 5 -q --out " +
                        quoted(dir.file("b.ffscene")));
  ASSERT_EQ(r.exit_status, 0) << r.output;
  auto info = run_farfield("info " + quoted(dir.file("b.ffscene")));
  EXPECT_EQ(info.exit_status, 0);
  EXPECT_NE(info.output.find("cells:       16"), std::string::npos) << info.output;
  r = run_farfield("path " + quoted(dir.file("b.ffscene")) + " --kind interior --frames 50 --out " +
                   quoted(dir.file("p.json")));
  EXPECT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("interior path, 50 frames"), std::string::npos) << r.output;
  // A scene without rooms has no interior path, and nothing is written.
  ASSERT_EQ(run_farfield("generate city --blocks 1 -q --out " + quoted(dir.file("c.ffscene")))
                .exit_status,
            0);
  r = run_farfield("path " + quoted(dir.file("c.ffscene")) + " --kind interior --out " +
                   quoted(dir.file("q.json")));
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_NE(r.output.find("cells and portals"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("q.json")));
}

TEST(Cli, GenerateRejectsAbsurdOptionsAndWritesNothing) {
  TempDir dir;
  for (const char* options :
       {"city --block-length -3", "city --blocks 0", "city --tree-distance nan",
        "city --max-height 0", "city --target-triangles 999999999999999",
        "field --mesh missing.obj --count 4", "field --count 0 --mesh M",
        "field --spacing -1 --mesh M", "building --floors 0", "building --rooms 2",
        "building --storey nan"}) {
    std::string args = "generate ";
    args += options;
    args += " --out " + quoted(dir.file("x.ffscene"));
    const size_t m = args.find(" M ");
    if (m != std::string::npos) args.replace(m, 3, " " + quoted(dir.file("x.ffscene")) + " ");
    auto r = run_farfield(args);
    EXPECT_NE(r.exit_status, 0) << options;
    EXPECT_FALSE(r.output.empty()) << options;
    EXPECT_TRUE(dir.entries().empty()) << options;
  }
}

TEST(Cli, GenerateFieldCopiesAModel) {
  TempDir dir;
  ASSERT_TRUE(write_scene(test::make_box_row(2), dir.file("model.ffscene")));
  auto r = run_farfield("generate field -q --mesh " + quoted(dir.file("model.ffscene")) +
                        " --count 9 --spacing 20 --out " + quoted(dir.file("field.ffscene")));
  ASSERT_EQ(r.exit_status, 0) << r.output;
  auto field = read_scene(dir.file("field.ffscene"));
  ASSERT_TRUE(field) << field.error().message;
  EXPECT_EQ(field->objects.size(), 9u);
  EXPECT_EQ(field->triangle_count(), 9u * 24u);
}

}  // namespace
}  // namespace farfield
