#include "test_util.hpp"

#include "farfield/scene/instances.hpp"

#include <fcntl.h>
#include <xxhash.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <unistd.h>

#include <gtest/gtest.h>

#include "farfield/core/assert.hpp"
#include "farfield/core/image.hpp"
#include "farfield/scene/scene_file_writer.hpp"

namespace farfield::test {

Result<void> load_technique(Technique& technique, const Scene& scene, gpu::Device* device,
                            const Store* store) {
  static gpu::MemoryDevice memory;
  Progress quiet(true);
  return technique.load({scene, store, device ? *device : memory, quiet});
}

double figure(const Technique& technique, const std::string& name) {
  for (const auto& [key, value] : technique.figures())
    if (key == name) return value;
  ADD_FAILURE() << "no figure " << name;
  return -1;
}

void select_view(Technique& technique, const View& view, DrawList& list, uint64_t frame) {
  list.clear();
  technique.select({view, frame, Region::everything(), {}}, list);
}

TechniqueSettings settings_of(std::initializer_list<const char*> assignments) {
  TechniqueSettings settings;
  for (const char* a : assignments) {
    const Result<void> ok = settings.add(a);
    if (!ok) std::fprintf(stderr, "settings_of: %s\n", ok.error().message.c_str());
  }
  return settings;
}

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = std::filesystem::temp_directory_path() /
          ("farfield-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::vector<std::string> TempDir::entries() const {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(path_))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

Scene make_textured_scene(AlphaMode mode) {
  Scene scene = make_box_row(1);
  SceneBuilder b(scene);
  Image checker(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) std::fill_n(checker.pixel(x, y), 3, uint8_t((x + y) % 2 ? 255 : 0));
  auto png = encode_png(checker);
  FF_ASSERT(png.ok(), "checker PNG");
  const uint32_t texture = b.add_texture(Texture{.name = "checker.png",
                                                 .codec = TextureCodec::png,
                                                 .width = 4,
                                                 .height = 4,
                                                 .has_alpha = false,
                                                 .encoded = std::move(*png)});
  const uint32_t material = b.add_material(
      Material{.base_color = glm::vec4(1.0f), .texture = texture, .alpha_mode = mode});
  b.begin_object("quad", ObjectKind::mesh, material);
  const glm::vec3 n(0.0f, 0.0f, 1.0f);
  b.add_vertex({-1.0f, 0.0f, 3.0f}, n, 0xffffffffu, {0.0f, 1.0f});
  b.add_vertex({1.0f, 0.0f, 3.0f}, n, 0xffffffffu, {1.0f, 1.0f});
  b.add_vertex({-1.0f, 2.0f, 3.0f}, n, 0xffffffffu, {0.0f, 0.0f});
  b.add_vertex({1.0f, 2.0f, 3.0f}, n, 0xffffffffu, {1.0f, 0.0f});
  b.add_triangle(0, 1, 3);
  b.add_triangle(0, 3, 2);
  b.end_object();
  return scene;
}

void add_cuboid(SceneBuilder& b, const glm::vec3& lo, const glm::vec3& hi) {
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2) {
      glm::vec3 n(0.0f);
      n[axis] = float(sign);
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const uint32_t first = b.vertex_count();
      for (int corner = 0; corner < 4; ++corner) {
        glm::vec3 p;
        p[axis] = sign > 0 ? hi[axis] : lo[axis];
        p[u] = corner & 1 ? hi[u] : lo[u];
        p[v] = (corner >> 1) & 1 ? hi[v] : lo[v];
        b.add_vertex(p, n, 0xffffffffu);
      }
      if (sign > 0) {
        b.add_triangle(first, first + 1, first + 3);
        b.add_triangle(first, first + 3, first + 2);
      } else {
        b.add_triangle(first, first + 3, first + 1);
        b.add_triangle(first, first + 2, first + 3);
      }
    }
}

View look_at(const glm::vec3& eye, const glm::vec3& target) {
  View view;
  view.width = 128;
  view.height = 96;
  const glm::vec3 d = glm::normalize(target - eye);
  view.pose.position = eye;
  view.pose.yaw_deg = glm::degrees(std::atan2(d.z, d.x));
  view.pose.pitch_deg = glm::degrees(std::asin(d.y));
  return view;
}

Scene make_box_row(int boxes) {
  Scene scene;
  SceneBuilder b(scene);
  const uint32_t opaque = b.add_material(Material{{0.8f, 0.2f, 0.1f, 1.0f}});
  const uint32_t glass = b.add_material(Material{{0.5f, 0.7f, 1.0f, 0.5f}});
  for (int i = 0; i < boxes; ++i) {
    b.begin_object("box_" + std::to_string(i), i % 5 == 0 ? ObjectKind::building : ObjectKind::mesh,
                   i % 2 ? glass : opaque);
    add_cuboid(b, glm::vec3(2.0f * i, 0.0f, 0.0f), glm::vec3(2.0f * i + 1.0f, 1.0f, 1.0f));
    b.end_object();
  }
  return scene;
}

CommandResult run_farfield(const std::string& args, const std::string& cwd,
                           const std::string& wrapper) {
  std::string command = wrapper + FARFIELD_EXE + " " + args;
  if (!cwd.empty()) command = "cd '" + cwd + "' && " + command;
  return run_shell(command);
}

CommandResult run_shell(const std::string& command) {
  CommandResult result;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

int spawn_farfield(const std::vector<std::string>& args) {
  const pid_t child = fork();
  if (child != 0) return child;
  std::vector<char*> argv{const_cast<char*>(FARFIELD_EXE)};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const int devnull = ::open("/dev/null", O_WRONLY);
  dup2(devnull, 2);
  execv(FARFIELD_EXE, argv.data());
  _exit(127);
}

bool write_in_chunks(const Scene& scene, const std::string& path, uint32_t chunk_triangles) {
  const StoredGeometry stored = stored_geometry(scene);
  auto writer = SceneFileWriter::create(path, {stored.vertices, stored.indices}, chunk_triangles);
  Result<void> ok = writer ? writer->append(scene) : Result<void>(writer.error());
  if (ok) {
    // Without instances the writer reads the fingerprint back from the file (tested so).
    auto finished = scene.instances.empty() ? writer->finish(scene)
                                            : writer->finish(scene, scene_fingerprint(scene));
    if (!finished) ok = finished.error();
  }
  EXPECT_TRUE(ok) << (ok ? "" : ok.error().message);
  return bool(ok);
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void reseal_scene_header(std::string& file) {
  uint32_t count;
  std::memcpy(&count, file.data() + 40, 4);
  XXH3_state_t* state = XXH3_createState();
  XXH3_64bits_reset(state);
  XXH3_64bits_update(state, file.data(), 56);
  XXH3_64bits_update(state, file.data() + 64, count * 48);
  const uint64_t header = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  std::memcpy(file.data() + 56, &header, 8);
}

std::vector<glm::vec3> random_surface_points(const MeshPart& mesh, int count, uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_int_distribution<size_t> triangle(0, mesh.triangle_count() - 1);
  std::vector<glm::vec3> out;
  for (int i = 0; i < count; ++i) {
    const size_t t = triangle(random);
    float r1 = unit(random), r2 = unit(random);
    if (r1 + r2 > 1.0f) {
      r1 = 1.0f - r1;
      r2 = 1.0f - r2;
    }
    const glm::vec3 a = mesh.vertices[mesh.indices[3 * t]].position,
                    b = mesh.vertices[mesh.indices[3 * t + 1]].position,
                    c = mesh.vertices[mesh.indices[3 * t + 2]].position;
    out.push_back(a + r1 * (b - a) + r2 * (c - a));
  }
  return out;
}

}  // namespace farfield::test
