// Shared test helpers: a temporary folder per test, small hand-made scenes, running the CLI.
#pragma once

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "farfield/core/view.hpp"
#include "farfield/gpu/device.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/scene/simplify.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield::test {

// A fresh empty folder, removed with everything in it on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  // Names of the entries in the folder, sorted.
  std::vector<std::string> entries() const;

 private:
  std::filesystem::path path_;
};

// A cuboid of six flat faces into the current object, counter-clockwise seen from outside.
void add_cuboid(SceneBuilder& b, const glm::vec3& lo, const glm::vec3& hi);

// `boxes` unit cubes along X, one object each, alternating an opaque and a transparent material.
Scene make_box_row(int boxes);
// A 128 x 96 view (small images keep llvmpipe fast) from `eye` towards `target`.
View look_at(const glm::vec3& eye, const glm::vec3& target);

// One untextured unit box, then a 2 m textured quad facing +Z at z = 3 with a 4 x 4 checker
// texture (PNG, black and white texels), material alpha mode `mode`.
Scene make_textured_scene(AlphaMode mode = AlphaMode::opaque);

// Loads a technique for `scene` with its resources on `device` (the renderer of a GL test; a
// MemoryDevice that lives as long as the tests when null), from `store` when given.
Result<void> load_technique(Technique& technique, const Scene& scene, gpu::Device* device = nullptr,
                            const Store* store = nullptr);
// One frame's selection of the whole scene into `list`, cleared first.
void select_view(Technique& technique, const View& view, DrawList& list, uint64_t frame = 0);
// A technique's figure by name (a test failure, and -1, where it has none).
double figure(const Technique& technique, const std::string& name);
// Settings from "TECHNIQUE.KEY=VALUE" assignments, which must be well formed.
TechniqueSettings settings_of(std::initializer_list<const char*> assignments);

struct CommandResult {
  int exit_status = -1;
  std::string output;  // stdout and stderr together
};
// Runs the farfield executable with `args` (shell-quoted by the caller), in folder `cwd` when
// one is given, behind `wrapper` (e.g. "xvfb-run -a ") when one is given.
CommandResult run_farfield(const std::string& args, const std::string& cwd = "",
                           const std::string& wrapper = "");
// Runs `command` in the shell; its exit status and output (stdout and stderr together).
CommandResult run_shell(const std::string& command);

// Starts the farfield executable with `args` in a child process, its stderr sent to
// /dev/null (for tests that kill it half-way); returns the child's pid.
int spawn_farfield(const std::vector<std::string>& args);

void write_file(const std::string& path, const std::string& bytes);

// `scene` written to `path` in chunks of at most `chunk_triangles` (SceneFileWriter), its
// fingerprint read back from the file; false (with a test failure) where that fails.
bool write_in_chunks(const Scene& scene, const std::string& path, uint32_t chunk_triangles);

// `count` random points on the triangles of `mesh` (uniform over triangles, then area).
std::vector<glm::vec3> random_surface_points(const MeshPart& mesh, int count, uint32_t seed);

// Arrays of plain records equal byte for byte (padding included, as written to files).
template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}
std::string read_file(const std::string& path);
// A .ffscene's header checksum made that of its header and section table as they now are.
void reseal_scene_header(std::string& file);

}  // namespace farfield::test
