#include "farfield/scene/landscape_generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <string>
#include <vector>

#include "farfield/core/assert.hpp"
#include "farfield/scene/tree_generator.hpp"
#include "random.hpp"

namespace farfield {

namespace {

using detail::Rng;
using detail::splitmix64;

constexpr double kBaseCycles = 3.0;     // hills per terrain side in the first octave
constexpr float kShape = 1.4f;          // > 1 widens the valleys and sharpens the tops
constexpr float kTreeSink = 0.2f;       // metres
constexpr float kTreeMaxSlope = 0.87f;  // least normal.y under a tree (about 30 degrees)
constexpr float kTreeLine = 0.75f;      // no trees above this fraction of the relief
constexpr int kTreeTries = 64;
constexpr uint32_t kGroveTrees = 16;  // trees per grove
constexpr float kTreeSpacing = 7.0f;  // metres: a grove of n trees spans 7 sqrt(n) m
const glm::vec3 kLush{0.22f, 0.42f, 0.12f}, kDry{0.36f, 0.47f, 0.17f}, kRock{0.46f, 0.43f, 0.39f};

// Hash of a lattice point to [0, 1): the same on every platform, for any order of evaluation.
double lattice(uint64_t seed, uint64_t octave, int64_t ix, int64_t iz) {
  uint64_t state = seed ^ (octave * 0x9e3779b97f4a7c15ull);
  state = splitmix64(state) ^ (uint64_t(ix) * 0xd1b54a32d192ed03ull);
  state = splitmix64(state) ^ (uint64_t(iz) * 0xaef17502108ef2d9ull);
  return double(splitmix64(state) >> 11) * 0x1.0p-53;
}

// Value noise in [0, 1]: the lattice values blended with the quintic fade (C2 continuous).
double value_noise(uint64_t seed, uint64_t octave, double x, double z) {
  const double fx = std::floor(x), fz = std::floor(z);
  const auto ix = static_cast<int64_t>(fx), iz = static_cast<int64_t>(fz);
  auto fade = [](double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); };
  const double u = fade(x - fx), v = fade(z - fz);
  const double a = lattice(seed, octave, ix, iz), b = lattice(seed, octave, ix + 1, iz);
  const double c = lattice(seed, octave, ix, iz + 1), d = lattice(seed, octave, ix + 1, iz + 1);
  return (a + (b - a) * u) * (1.0 - v) + (c + (d - c) * u) * v;
}

// Fractal sum of `octaves` octaves at (x, z) in cycles of the first octave, in [0, 1].
double fbm(uint64_t seed, double x, double z, int octaves) {
  double sum = 0.0, amplitude = 1.0, total = 0.0, frequency = 1.0;
  for (int k = 0; k < octaves; ++k) {
    sum += amplitude * value_noise(seed, k, x * frequency, z * frequency);
    total += amplitude;
    amplitude *= 0.5, frequency *= 2.0;
  }
  return sum / total;
}

float smooth(float edge0, float edge1, float x) {  // smoothstep, either order of edges
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// The ground: heights and normals at the (n + 1)^2 grid points, row by row along X.
struct HeightField {
  uint32_t n = 0;
  float cell = 0.0f, origin = 0.0f, relief = 0.0f;  // metres; origin: x and z of point (0, 0)
  std::vector<float> height;
  std::vector<glm::vec3> normal;

  size_t at(uint32_t i, uint32_t j) const { return size_t(j) * (n + 1) + i; }
  glm::vec3 position(uint32_t i, uint32_t j) const {
    return {origin + cell * i, height[at(i, j)], origin + cell * j};
  }
  // Height of the triangulated surface at (x, z), clamped to the grid: cell (i, j) is split
  // along its diagonal from (i, j) to (i + 1, j + 1), as the tiles are.
  float surface(float x, float z) const {
    const float fx = std::clamp((x - origin) / cell, 0.0f, float(n));
    const float fz = std::clamp((z - origin) / cell, 0.0f, float(n));
    const uint32_t i = std::min(uint32_t(fx), n - 1), j = std::min(uint32_t(fz), n - 1);
    const float u = fx - i, v = fz - j;
    const float h00 = height[at(i, j)], h10 = height[at(i + 1, j)];
    const float h01 = height[at(i, j + 1)], h11 = height[at(i + 1, j + 1)];
    return v >= u ? h00 + v * (h01 - h00) + u * (h11 - h01)
                  : h00 + u * (h10 - h00) + v * (h11 - h10);
  }
  glm::vec3 nearest_normal(float x, float z) const {
    const auto i = uint32_t(std::clamp(std::lround((x - origin) / cell), 0l, long(n)));
    const auto j = uint32_t(std::clamp(std::lround((z - origin) / cell), 0l, long(n)));
    return normal[at(i, j)];
  }
};

HeightField make_height_field(const LandscapeOptions& o) {
  HeightField f;
  f.n = o.resolution;
  f.cell = float(o.size / o.resolution);
  f.origin = float(-0.5 * o.size);
  f.relief = float(o.relief);
  // Octaves down to a wavelength of 2 cells: finer ones would only alias.
  const int octaves =
      std::max(1, int(std::floor(std::log2(o.resolution / (2.0 * kBaseCycles)))) + 1);
  const uint32_t n = f.n;
  std::vector<double> raw(size_t(n + 1) * (n + 1));
  double lo = INFINITY, hi = -INFINITY;
  for (uint32_t j = 0; j <= n; ++j) {
    for (uint32_t i = 0; i <= n; ++i) {
      const double v = fbm(o.seed, kBaseCycles * i / n, kBaseCycles * j / n, octaves);
      raw[f.at(i, j)] = v;
      lo = std::min(lo, v), hi = std::max(hi, v);
    }
  }
  f.height.resize(raw.size());
  for (size_t k = 0; k < raw.size(); ++k) {
    const double t = hi > lo ? (raw[k] - lo) / (hi - lo) : 0.0;
    f.height[k] = f.relief * std::pow(float(t), kShape);
  }
  // Normals by central differences over the whole grid, so that tiles meet without a crease.
  f.normal.resize(raw.size());
  for (uint32_t j = 0; j <= n; ++j) {
    for (uint32_t i = 0; i <= n; ++i) {
      const uint32_t i0 = i ? i - 1 : 0, i1 = std::min(i + 1, n);
      const uint32_t j0 = j ? j - 1 : 0, j1 = std::min(j + 1, n);
      const float dx = (f.height[f.at(i1, j)] - f.height[f.at(i0, j)]) / (f.cell * (i1 - i0));
      const float dz = (f.height[f.at(i, j1)] - f.height[f.at(i, j0)]) / (f.cell * (j1 - j0));
      f.normal[f.at(i, j)] = glm::normalize(glm::vec3(-dx, 1.0f, -dz));
    }
  }
  return f;
}

// Grass by height, rock on steep slopes and on the tops, with a little noise per grid point.
uint32_t ground_color(const HeightField& f, uint32_t i, uint32_t j, uint64_t seed) {
  const float t = f.relief > 0.0f ? f.height[f.at(i, j)] / f.relief : 0.0f;
  const float up = f.normal[f.at(i, j)].y;
  const glm::vec3 grass = glm::mix(kLush, kDry, smooth(0.3f, 0.8f, t));
  const float rock = std::max(smooth(0.88f, 0.74f, up), 0.8f * smooth(0.82f, 0.97f, t));
  const float shade = 1.0f + 0.12f * float(lattice(seed ^ 0x5eed, 7, i, j) - 0.5);
  return pack_color(glm::vec4(glm::clamp(glm::mix(grass, kRock, rock) * shade, 0.0f, 1.0f), 1.0f));
}

void add_tile(SceneBuilder& b, const HeightField& f, uint32_t ti, uint32_t tj, uint32_t tile,
              uint32_t material, uint64_t seed) {
  const uint32_t i0 = ti * tile, i1 = std::min(i0 + tile, f.n);
  const uint32_t j0 = tj * tile, j1 = std::min(j0 + tile, f.n);
  const uint32_t w = i1 - i0 + 1;
  b.begin_object("terrain_" + std::to_string(ti) + "_" + std::to_string(tj), ObjectKind::terrain,
                 material);
  for (uint32_t j = j0; j <= j1; ++j) {
    for (uint32_t i = i0; i <= i1; ++i)
      b.add_vertex(f.position(i, j), f.normal[f.at(i, j)], ground_color(f, i, j, seed));
  }
  for (uint32_t j = 0; j + j0 < j1; ++j) {
    for (uint32_t i = 0; i + i0 < i1; ++i) {
      const uint32_t v00 = j * w + i, v10 = v00 + 1, v01 = v00 + w, v11 = v01 + 1;
      // Counter-clockwise seen from above (+Y): x to the right, z towards the viewer.
      b.add_triangle(v00, v01, v11);
      b.add_triangle(v00, v11, v10);
    }
  }
  b.end_object();
}

// Where a tree may stand: on gentle slopes under the tree line. The score ranks the places
// that may not, for when a tree finds no better.
float site_score(const HeightField& f, float x, float z) {
  const float up = f.nearest_normal(x, z).y;
  const float t = f.relief > 0.0f ? f.surface(x, z) / f.relief : 0.0f;
  return up >= kTreeMaxSlope && t <= kTreeLine ? 1.0f : up - t;
}

// The best of kTreeTries places drawn by `draw`, the first that may hold a tree if any.
template <class Draw>
glm::vec2 pick_site(const HeightField& f, Draw&& draw) {
  glm::vec2 best{0.0f};
  float best_score = -INFINITY;
  for (int k = 0; k < kTreeTries && best_score < 1.0f; ++k) {
    const glm::vec2 p = draw();
    if (const float score = site_score(f, p.x, p.y); score > best_score)
      best_score = score, best = p;
  }
  return best;
}

// Trees grow in groves of about kGroveTrees, scattered over a disk that grows with their count.
std::vector<glm::vec3> tree_sites(const HeightField& f, const LandscapeOptions& o, Rng& rng) {
  const float size = float(o.size), margin = std::min(3.0f, 0.05f * size);
  const float lo = f.origin + margin, hi = f.origin + size - margin;
  const uint32_t groves = std::max(1u, o.trees / kGroveTrees);
  std::vector<glm::vec2> centres;
  for (uint32_t g = 0; g < groves; ++g)
    centres.push_back(
        pick_site(f, [&] { return glm::vec2(rng.uniform(lo, hi), rng.uniform(lo, hi)); }));
  const float radius = std::min(kTreeSpacing * std::sqrt(float(kGroveTrees)), 0.25f * size);
  std::vector<glm::vec3> sites;
  for (uint32_t k = 0; k < o.trees; ++k) {
    const glm::vec2 c = centres[k % groves];
    const glm::vec2 p = pick_site(f, [&] {
      const float r = radius * std::sqrt(float(rng.uniform())), a = rng.uniform(0.0, 6.283185307);
      return glm::clamp(c + r * glm::vec2(std::cos(a), std::sin(a)), lo, hi);
    });
    sites.push_back({p.x, f.surface(p.x, p.y), p.y});
  }
  return sites;
}

Result<void> check_range(const char* option, double v, double lo, double hi, bool open_lo) {
  if (!(open_lo ? v > lo : v >= lo) || !(v <= hi)) {  // also rejects NaN
    char text[160];
    std::snprintf(text, sizeof text, "%s must be in %s%g, %g] (got %g)", option,
                  open_lo ? "(" : "[", lo, hi, v);
    return Error{text};
  }
  return {};
}

}  // namespace

Result<void> validate_landscape_options(const LandscapeOptions& o) {
  for (const Result<void>& r : {
           check_range("--size", o.size, 0.0, 1e6, true),
           check_range("--resolution", o.resolution, 1, 8192, false),
           check_range("--tile", o.tile_cells, 1, 4096, false),
           check_range("--relief", o.relief, 0.0, 1e4, false),
           check_range("--trees", o.trees, 0, 50000, false),
       }) {
    if (!r) return r;
  }
  return {};
}

Result<Scene> generate_landscape(const LandscapeOptions& o, Progress& progress) {
  if (auto ok = validate_landscape_options(o); !ok) return ok.error();
  const HeightField field = make_height_field(o);
  const uint32_t tiles = (o.resolution + o.tile_cells - 1) / o.tile_cells;

  Scene scene;
  SceneBuilder b(scene);
  const uint32_t material = b.add_material(Material{glm::vec4(1.0f)});
  progress.start("generate landscape", uint64_t(tiles) * tiles + o.trees);
  for (uint32_t tj = 0; tj < tiles; ++tj) {
    for (uint32_t ti = 0; ti < tiles; ++ti) {
      add_tile(b, field, ti, tj, o.tile_cells, material, o.seed);
      progress.advance();
    }
  }
  uint64_t state = o.seed ^ 0x7ee5;
  Rng rng(splitmix64(state));
  const std::vector<glm::vec3> sites = tree_sites(field, o, rng);
  for (uint32_t k = 0; k < o.trees; ++k) {
    const glm::vec3& site = sites[k];
    TreeOptions tree;  // the default L-system, smaller and varied
    tree.iterations = rng.chance(0.5) ? 4 : 5;
    tree.height = rng.uniform(7.0, 15.0);
    tree.branch_angle_deg = rng.uniform(24.0, 40.0);
    tree.divergence_deg = rng.uniform(100.0, 140.0);
    tree.length_ratio = rng.uniform(0.72, 0.82);
    tree.leaf_size = 0.05 * tree.height;
    tree.leaves = 14;
    tree.sides = 6;
    tree.objects = 1;
    tree.seed = rng.next();
    auto ok =
        add_tree(b, tree, site - glm::vec3(0.0f, kTreeSink, 0.0f), "tree_" + std::to_string(k));
    FF_ASSERT(ok.ok(), "tree %u: %s", k, ok.error().message.c_str());
    progress.advance();
  }
  return scene;
}

}  // namespace farfield
