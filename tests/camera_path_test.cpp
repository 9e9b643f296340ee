// Camera paths: the JSON file (round trip, malformed input refused), the three generated kinds
// (street stays on the streets and turns smoothly, fly above the roofs, orbit looks at the
// centre) and the `path` command.
#include "farfield/core/camera_path.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <set>
#include <string>

#include "farfield/scene/city_generator.hpp"
#include "farfield/scene/path_generator.hpp"
#include "farfield/scene/scene_file.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using test::TempDir;

// 3 x 3 blocks, about 400 m square: enough crossings for 300 frames of driving.
const Scene& small_city() {
  static const Scene city = [] {
    CityOptions o;
    o.blocks_x = o.blocks_z = 3;
    o.seed = 1;
    Progress quiet(true);
    auto scene = generate_city(o, quiet);
    EXPECT_TRUE(scene) << scene.error().message;
    return scene ? std::move(scene).value() : Scene{};
  }();
  return city;
}

CameraPath generate(const Scene& scene, const PathOptions& o) {
  auto path = generate_path(scene, o);
  EXPECT_TRUE(path) << path.error().message;
  return path ? std::move(path).value() : CameraPath{};
}

PathOptions kind(const char* k, uint32_t frames = 300) {
  PathOptions o;
  o.kind = k;
  o.frames = frames;
  return o;
}

float yaw_step(float from, float to) {
  return std::remainder(to - from, 360.0f);
}

bool same_frames(const CameraPath& a, const CameraPath& b) {
  if (a.frames.size() != b.frames.size()) return false;
  for (size_t i = 0; i < a.frames.size(); ++i) {
    const CameraPose &p = a.frames[i], &q = b.frames[i];
    if (p.position != q.position || p.yaw_deg != q.yaw_deg || p.pitch_deg != q.pitch_deg)
      return false;
  }
  return true;
}

bool over(const Object& o, const glm::vec3& p, float eps = 1e-3f) {
  return p.x >= o.bounds.min.x - eps && p.x <= o.bounds.max.x + eps &&
         p.z >= o.bounds.min.z - eps && p.z <= o.bounds.max.z + eps;
}

// ---- The file. -----------------------------------------------------------------------------

TEST(CameraPathFile, RoundTripKeepsEveryFloat) {
  TempDir dir;
  CameraPath path{"street", "city \"1\".ffscene", {}};
  for (int i = 0; i < 50; ++i) {
    CameraPose p;
    p.position = {0.1f * i + 1e-7f, 1.7f, -1234.5678f * i};
    p.yaw_deg = std::nextafter(float(7 * i - 180), 1000.0f);
    p.pitch_deg = -89.99f + 3.5f * i;
    path.frames.push_back(p);
  }
  ASSERT_TRUE(write_camera_path(path, dir.file("p.json")));
  auto back = read_camera_path(dir.file("p.json"));
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(back->kind, path.kind);
  EXPECT_EQ(back->scene, path.scene);
  EXPECT_TRUE(same_frames(*back, path));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"p.json"});  // no temporary left
}

TEST(CameraPathFile, RefusesMalformedFilesNamingTheProblem) {
  TempDir dir;
  const std::string head = R"({"format": "farfield-path", "version": 1, "kind": "street", )";
  const std::string good = R"({"position": [1, 2, 3], "yaw_deg": 0, "pitch_deg": 0})";
  auto frames = [&](const std::string& second) {
    return head + R"("scene": "c.ffscene", "frames": [)" + good + ", " + second + "]}";
  };
  const struct {
    const char* name;
    std::string text;
    const char* expected;
  } cases[] = {
      {"empty.json", "", "empty"},
      {"garbage.json", "{\"format\": ", "parse error"},
      {"array.json", "[1, 2]", "not a farfield path"},
      {"format.json", R"({"format": "scene", "version": 1, "kind": "x", "frames": []})",
       "not a farfield path"},
      {"version.json", R"({"format": "farfield-path", "version": 2, "kind": "x", "frames": []})",
       "unsupported path version 2"},
      {"nokind.json", R"({"format": "farfield-path", "version": 1, "frames": []})", "\"kind\""},
      {"noframes.json", head + R"("scene": "c"})", "\"frames\""},
      {"zeroframes.json", head + R"("frames": []})", "no frames"},
      {"scene.json", head + R"("scene": 3, "frames": [)" + good + "]}", "\"scene\""},
      {"short.json", frames(R"({"position": [1, 2], "yaw_deg": 0, "pitch_deg": 0})"),
       "frame 1: position must be 3 numbers"},
      {"text.json", frames(R"({"position": [1, "2", 3], "yaw_deg": 0, "pitch_deg": 0})"),
       "frame 1: position must be 3 numbers"},
      {"huge.json", frames(R"({"position": [1, 2, 1e39], "yaw_deg": 0, "pitch_deg": 0})"),
       "frame 1: position must be finite"},
      {"inf.json", frames(R"({"position": [1, 2, 3], "yaw_deg": 1e999, "pitch_deg": 0})"),
       "number overflow"},
      {"yaw.json", frames(R"({"position": [1, 2, 3], "yaw_deg": -1e39, "pitch_deg": 0})"),
       "frame 1: yaw_deg must be a finite number"},
      {"noyaw.json", frames(R"({"position": [1, 2, 3], "pitch_deg": 0})"),
       "frame 1: missing \"yaw_deg\""},
      {"pitch.json", frames(R"({"position": [1, 2, 3], "yaw_deg": 0, "pitch_deg": 90})"),
       "frame 1: pitch_deg must be a number in (-90, 90)"},
      {"pitch2.json", frames(R"({"position": [1, 2, 3], "yaw_deg": 0, "pitch_deg": -95})"),
       "frame 1: pitch_deg"},
      {"notobject.json", frames("7"), "frame 1: must be an object"},
  };
  for (const auto& c : cases) {
    test::write_file(dir.file(c.name), c.text);
    auto path = read_camera_path(dir.file(c.name));
    ASSERT_FALSE(path) << c.name;
    EXPECT_NE(path.error().message.find(c.name), std::string::npos) << path.error().message;
    EXPECT_NE(path.error().message.find(c.expected), std::string::npos) << path.error().message;
  }
  auto missing = read_camera_path(dir.file("missing.json"));
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("missing.json: cannot open"), std::string::npos)
      << missing.error().message;
  auto folder = read_camera_path(dir.path().string());
  ASSERT_FALSE(folder);
  EXPECT_NE(folder.error().message.find("not a regular file"), std::string::npos);
  // The good frame on its own is a good file.
  test::write_file(dir.file("good.json"), head + R"("frames": [)" + good + "]}");
  auto ok = read_camera_path(dir.file("good.json"));
  ASSERT_TRUE(ok) << ok.error().message;
  EXPECT_EQ(ok->frames.size(), 1u);
  EXPECT_EQ(ok->frames[0].position, glm::vec3(1, 2, 3));
}

TEST(CameraPathFile, RefusesToWriteWhatItWouldNotRead) {
  TempDir dir;
  CameraPath empty{"street", "", {}};
  EXPECT_FALSE(write_camera_path(empty, dir.file("a.json")));
  CameraPath bad{"street", "", {CameraPose{}, CameraPose{}}};
  bad.frames[1].pitch_deg = 90.0f;
  auto r = write_camera_path(bad, dir.file("b.json"));
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("frame 1"), std::string::npos) << r.error().message;
  bad.frames[1].pitch_deg = 0.0f;
  bad.frames[1].position.y = NAN;
  EXPECT_FALSE(write_camera_path(bad, dir.file("c.json")));
  EXPECT_TRUE(dir.entries().empty());
}

// ---- Generated paths. ----------------------------------------------------------------------

TEST(PathGenerator, SameOptionsGiveTheSameFrames) {
  for (const char* k : {"street", "fly", "orbit"}) {
    const CameraPath a = generate(small_city(), kind(k)), b = generate(small_city(), kind(k));
    EXPECT_EQ(a.frames.size(), 300u) << k;
    EXPECT_EQ(a.kind, k);
    EXPECT_TRUE(same_frames(a, b)) << k;
  }
  PathOptions other = kind("street", 1000);
  other.seed = 2;
  EXPECT_FALSE(
      same_frames(generate(small_city(), kind("street", 1000)), generate(small_city(), other)));
}

// Crossings driven through and turns taken (the heading through a crossing changes by more
// than 45 degrees), from the city's crossing_I_J objects.
struct StreetStats {
  size_t crossings = 0, turns = 0;
};
StreetStats street_stats(const Scene& city, const CameraPath& path) {
  std::vector<int> in(path.frames.size(), -1);  // the crossing each frame is in
  for (size_t k = 0; k < path.frames.size(); ++k) {
    for (size_t i = 0; i < city.objects.size(); ++i) {
      if (city.object_name(city.objects[i]).starts_with("crossing_") &&
          over(city.objects[i], path.frames[k].position, 0.0f))
        in[k] = int(i);
    }
  }
  std::set<int> seen(in.begin(), in.end());
  seen.erase(-1);
  StreetStats s{seen.size(), 0};
  for (size_t k = 0; k < in.size();) {
    size_t end = k;
    while (end < in.size() && in[end] == in[k]) ++end;
    if (in[k] >= 0 && k > 0 && end < in.size() &&
        std::abs(yaw_step(path.frames[k - 1].yaw_deg, path.frames[end].yaw_deg)) > 45.0f)
      ++s.turns;
    k = end;
  }
  return s;
}

TEST(PathGenerator, StreetPathStaysOnTheStreetsAndTurnsSmoothly) {
  const Scene& city = small_city();
  const PathOptions o = kind("street");
  const CameraPath path = generate(city, o);
  ASSERT_EQ(path.frames.size(), 300u);
  for (size_t k = 0; k < path.frames.size(); ++k) {
    const CameraPose& p = path.frames[k];
    bool on_street = false;
    for (const Object& s : city.objects) {
      on_street |= s.kind == ObjectKind::street && over(s, p.position) &&
                   std::abs(p.position.y - (s.bounds.max.y + 1.7f)) < 1e-4f;
    }
    EXPECT_TRUE(on_street) << "frame " << k;
    EXPECT_EQ(p.pitch_deg, 0.0f);
    if (k == 0) continue;
    const CameraPose& q = path.frames[k - 1];
    EXPECT_LE(glm::distance(p.position, q.position), 1.5f * 1.01f) << "frame " << k;
    EXPECT_LE(std::abs(yaw_step(q.yaw_deg, p.yaw_deg)), 15.0f) << "frame " << k;
  }
  // Looking where it goes: the heading is the direction of travel along the way.
  for (size_t k = 1; k < path.frames.size(); ++k) {
    const glm::vec3 step = path.frames[k].position - path.frames[k - 1].position;
    if (glm::length(step) < 1.4f) continue;  // on an arc, or turning on the spot
    EXPECT_NEAR(glm::dot(glm::normalize(step), path.frames[k].forward()), 1.0f, 1e-3f);
  }
  const StreetStats stats = street_stats(city, path);
  EXPECT_GE(stats.crossings, 2u);
  EXPECT_GE(stats.turns, 1u);
}

TEST(PathGenerator, StreetPathTakesSpeedAndEyeHeight) {
  PathOptions o = kind("street", 400);
  o.speed = 4.0;
  o.eye_height = 10.0;
  o.seed = 7;
  const CameraPath path = generate(small_city(), o);
  float travelled = 0.0f;
  for (size_t k = 0; k < path.frames.size(); ++k) {
    EXPECT_NEAR(path.frames[k].position.y, 10.2f, 1e-4f);  // street top at 0.2 m
    if (k == 0) continue;
    const float step = glm::distance(path.frames[k].position, path.frames[k - 1].position);
    EXPECT_LE(step, 4.0f * 1.01f);
    travelled += step;
  }
  EXPECT_GT(travelled, 0.8f * 4.0f * 399);  // slower only on the arcs
  EXPECT_GE(street_stats(small_city(), path).crossings, 5u);
  EXPECT_EQ(generate(small_city(), kind("street", 1)).frames.size(), 1u);
}

// Street pieces as flat quads at height `top`, given as XZ rectangles {x0, z0, x1, z1}.
Scene street_scene(std::initializer_list<glm::vec4> rects, float top) {
  Scene scene;
  SceneBuilder b(scene);
  const uint32_t m = b.add_material(Material{});
  int n = 0;
  for (const glm::vec4& r : rects) {
    b.begin_object("piece_" + std::to_string(n++), ObjectKind::street, m);
    for (int c = 0; c < 4; ++c)
      b.add_vertex({c & 1 ? r.z : r.x, top, c & 2 ? r.w : r.y}, {0, 1, 0}, 0xffffffffu);
    b.add_triangle(0, 2, 1);
    b.add_triangle(1, 2, 3);
    b.end_object();
  }
  return scene;
}

TEST(PathGenerator, StreetPathFollowsAnyNetworkAndTurnsAtDeadEnds) {
  // An L: crossing, street along X, crossing, street along Z, crossing; dead ends at both
  // ends, so the walk goes back and forth, turning on the spot at the ends.
  const Scene scene = street_scene(
      {{0, 0, 10, 10}, {10, 0, 60, 10}, {60, 0, 70, 10}, {60, 10, 70, 80}, {60, 80, 70, 90}}, 0.5f);
  const CameraPath path = generate(scene, kind("street", 400));
  float turned = 0.0f;
  for (size_t k = 0; k < path.frames.size(); ++k) {
    const CameraPose& p = path.frames[k];
    bool on_street = false;
    for (const Object& s : scene.objects) on_street |= over(s, p.position);
    EXPECT_TRUE(on_street) << "frame " << k;
    EXPECT_NEAR(p.position.y, 2.2f, 1e-5f);
    if (k == 0) continue;
    const CameraPose& q = path.frames[k - 1];
    EXPECT_LE(glm::distance(p.position, q.position), 1.5f * 1.01f);
    EXPECT_LE(std::abs(yaw_step(q.yaw_deg, p.yaw_deg)), 15.0f);
    turned += std::abs(yaw_step(q.yaw_deg, p.yaw_deg));
  }
  // 400 frames: 3 times along the 140 m of the L and more (an arc of 90 degrees through the
  // middle crossing each time), 3 turns of 180 degrees (18 frames each) at its ends.
  EXPECT_GT(turned, 3 * 90.0f + 3 * 180.0f - 1.0f);
  const Scene lone = street_scene({{0, 0, 10, 10}, {20, 0, 30, 80}}, 0.0f);
  auto none = generate_path(lone, kind("street"));
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().message.find("crossings joined by streets"), std::string::npos)
      << none.error().message;
}

TEST(PathGenerator, StreetPathNeedsStreets) {
  const Scene boxes = test::make_box_row(5);
  auto path = generate_path(boxes, kind("street"));
  ASSERT_FALSE(path);
  EXPECT_NE(path.error().message.find("street paths need street objects"), std::string::npos)
      << path.error().message;
  EXPECT_TRUE(generate_path(boxes, kind("fly")));
  EXPECT_TRUE(generate_path(boxes, kind("orbit")));
  EXPECT_FALSE(generate_path(Scene{}, kind("orbit")));
}

TEST(PathGenerator, FlyPathLoopsAboveTheRoofsLookingDown) {
  const Scene& city = small_city();
  const CameraPath path = generate(city, kind("fly"));
  float step = 0.0f;
  for (size_t k = 0; k < path.frames.size(); ++k) {
    const CameraPose& p = path.frames[k];
    EXPECT_GT(p.position.y, city.bounds.max.y + 20.0f);
    EXPECT_TRUE(city.bounds.contains({p.position.x, city.bounds.min.y, p.position.z}));
    EXPECT_LE(p.pitch_deg, -15.0f);
    EXPECT_GE(p.pitch_deg, -70.0f);
    const CameraPose& next = path.frames[(k + 1) % path.frames.size()];  // a closed loop
    const float d = glm::distance(p.position, next.position);
    if (k == 0) step = d;
    EXPECT_NEAR(d, step, 0.01f * step) << "frame " << k;  // evenly spread
    EXPECT_LE(std::abs(yaw_step(p.yaw_deg, next.yaw_deg)), 15.0f);
  }
}

TEST(PathGenerator, OrbitLooksAtTheCentre) {
  const Scene& city = small_city();
  const CameraPath path = generate(city, kind("orbit", 100));
  const glm::vec3 centre = city.bounds.center();
  for (const CameraPose& p : path.frames) {
    const glm::vec3 to = glm::normalize(centre - p.position);
    EXPECT_GT(glm::dot(to, p.forward()), std::cos(glm::radians(1.0f)));
    EXPECT_GT(glm::distance(glm::vec2(p.position.x, p.position.z), glm::vec2(centre.x, centre.z)),
              0.5f * city.bounds.size().x);
    EXPECT_GT(p.position.y, centre.y);
  }
}

// Whether `p` lands inside the protocol's view (1024x768, 90 degrees) from `pose`.
bool in_view(const CameraPose& pose, const glm::vec3& p) {
  View view;
  view.pose = pose;
  const glm::vec4 clip = view.view_projection() * glm::vec4(p, 1.0f);
  return clip.w > 0 && std::abs(clip.x) <= clip.w && std::abs(clip.y) <= clip.w && clip.z <= clip.w;
}

TEST(PathGenerator, OrbitAndFlyFrameModelsOfAnySize) {
  // A 2 m model, a 7 m one and a 700 m one: an orbit keeps every corner of the
  // bounds in view, a fly path keeps the middle in view and stays above the top.
  for (const float scale : {0.3f, 1.0f, 100.0f}) {
    Scene scene = test::make_box_row(4);  // 7 x 1 x 1
    for (Vertex& v : scene.vertices) v.position *= scale;
    for (Object& o : scene.objects) o.bounds.min *= scale, o.bounds.max *= scale;
    scene.bounds.min *= scale;
    scene.bounds.max *= scale;
    for (const CameraPose& p : generate(scene, kind("orbit", 40)).frames)
      for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 q(corner & 1 ? scene.bounds.max.x : scene.bounds.min.x,
                          corner & 2 ? scene.bounds.max.y : scene.bounds.min.y,
                          corner & 4 ? scene.bounds.max.z : scene.bounds.min.z);
        EXPECT_TRUE(in_view(p, q)) << "scale " << scale << " corner " << corner;
      }
    for (const CameraPose& p : generate(scene, kind("fly", 40)).frames) {
      EXPECT_TRUE(in_view(p, scene.bounds.center())) << "scale " << scale;
      EXPECT_GT(p.position.y, scene.bounds.max.y);
    }
  }
}

TEST(PathGenerator, RefusesBadOptionsNamingThem) {
  PathOptions speed = kind("orbit"), nan_speed = kind("orbit"), eye = kind("street"),
              inf_eye = kind("street");
  speed.speed = -1.0;
  nan_speed.speed = NAN;
  eye.eye_height = 0.0;
  inf_eye.eye_height = INFINITY;
  const std::pair<PathOptions, const char*> cases[] = {
      {kind("walk"), "--kind"},
      {kind("street", 0), "--frames"},
      {kind("fly", 1'000'001), "--frames"},
      {speed, "--speed"},
      {nan_speed, "--speed"},
      {eye, "--eye-height"},
      {inf_eye, "--eye-height"},
  };
  for (const auto& [options, name] : cases) {
    auto path = generate_path(small_city(), options);
    ASSERT_FALSE(path) << name;
    EXPECT_NE(path.error().message.find(name), std::string::npos) << path.error().message;
  }
}

// ---- The command. --------------------------------------------------------------------------

TEST(PathCli, WritesAPathAndRefusesBadInput) {
  TempDir dir;
  ASSERT_TRUE(write_scene(small_city(), dir.file("city.ffscene")));
  ASSERT_TRUE(write_scene(test::make_box_row(3), dir.file("boxes.ffscene")));
  auto r = test::run_farfield("path city.ffscene --kind street --frames 50 --out p.json",
                              dir.path().string());
  EXPECT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("50 frames"), std::string::npos) << r.output;
  auto path = read_camera_path(dir.file("p.json"));
  ASSERT_TRUE(path) << path.error().message;
  EXPECT_EQ(path->frames.size(), 50u);
  EXPECT_EQ(path->scene, "city.ffscene");
  PathOptions o = kind("street", 50);
  EXPECT_TRUE(same_frames(*path, generate(small_city(), o)));

  const struct {
    const char* args;
    int status;
    const char* expected;
  } cases[] = {
      {"path city.ffscene --kind walk --out q.json", 2, "--kind"},
      {"path city.ffscene --frames -3 --out q.json", 2, "--frames"},
      {"path city.ffscene --kind fly", 2, "--out"},
      {"path missing.ffscene --out q.json", 1, "missing.ffscene"},
      {"path city.ffscene --frames 0 --out q.json", 1, "--frames must be at least 1"},
      {"path city.ffscene --speed -2 --out q.json", 1, "--speed"},
      {"path city.ffscene --eye-height 0 --out q.json", 1, "--eye-height"},
      {"path boxes.ffscene --out q.json", 1, "boxes.ffscene: street paths need street objects"},
  };
  for (const auto& c : cases) {
    r = test::run_farfield(c.args, dir.path().string());
    EXPECT_EQ(r.exit_status, c.status) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
  }
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"boxes.ffscene", "city.ffscene", "p.json"}));
  r = test::run_farfield("path boxes.ffscene --kind orbit --out o.json", dir.path().string());
  EXPECT_EQ(r.exit_status, 0) << r.output;
  EXPECT_NE(r.output.find("300 frames"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace farfield
