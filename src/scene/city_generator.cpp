#include "farfield/scene/city_generator.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <glm/geometric.hpp>
#include <string>
#include <vector>

#include "farfield/core/text.hpp"
#include "farfield/core/assert.hpp"
#include "farfield/scene/scene_file_writer.hpp"
#include "city_textures.hpp"
#include "mesh_primitives.hpp"
#include "random.hpp"

namespace farfield {

namespace {

using detail::Rng;
using detail::splitmix64;

// Each block draws from its own stream, so growing the grid keeps the old blocks as they were.
Rng block_rng(uint64_t seed, uint32_t bx, uint32_t bz) {
  uint64_t state = seed;
  uint64_t h = splitmix64(state);
  h ^= (uint64_t(bx) << 32) | bz;
  return Rng(splitmix64(h));
}

// ---- Colours (linear RGB). ------------------------------------------------------------------

using Rgb = glm::vec3;
constexpr Rgb kWalls[] = {{0.80f, 0.78f, 0.74f}, {0.70f, 0.42f, 0.33f}, {0.85f, 0.79f, 0.66f},
                          {0.92f, 0.91f, 0.88f}, {0.55f, 0.56f, 0.58f}, {0.60f, 0.50f, 0.40f},
                          {0.78f, 0.70f, 0.55f}, {0.60f, 0.67f, 0.72f}};
constexpr Rgb kWindows[] = {
    {0.18f, 0.23f, 0.30f}, {0.30f, 0.38f, 0.46f}, {0.14f, 0.16f, 0.18f}, {0.34f, 0.44f, 0.50f}};
constexpr Rgb kGlass[] = {
    {0.55f, 0.75f, 0.88f}, {0.50f, 0.80f, 0.72f}, {0.72f, 0.80f, 0.92f}, {0.62f, 0.66f, 0.78f}};
constexpr Rgb kRoofs[] = {
    {0.48f, 0.20f, 0.15f}, {0.30f, 0.30f, 0.33f}, {0.36f, 0.56f, 0.46f}, {0.50f, 0.40f, 0.30f}};
constexpr Rgb kTrims[] = {{0.88f, 0.88f, 0.86f}, {0.42f, 0.42f, 0.44f}, {0.70f, 0.66f, 0.60f}};
constexpr Rgb kStreet{0.20f, 0.20f, 0.22f}, kCurb{0.72f, 0.72f, 0.70f},
    kGround{0.55f, 0.53f, 0.50f}, kGrass{0.30f, 0.55f, 0.22f}, kTrunk{0.40f, 0.27f, 0.16f},
    kLeaves{0.22f, 0.50f, 0.18f}, kNeedles{0.12f, 0.35f, 0.20f}, kWater{0.25f, 0.45f, 0.80f},
    kFountainWall{0.70f, 0.70f, 0.68f};

uint32_t color(const Rgb& c) {
  return pack_color(glm::vec4(c, 1.0f));
}
uint32_t jitter(Rng& rng, const Rgb& c, float amount = 0.04f) {
  const float d = rng.uniform(-amount, amount);  // brightness, so the hue stays
  return color(glm::clamp(c + d, 0.0f, 1.0f));
}

// ---- Layout. -------------------------------------------------------------------------------

struct Rect {  // in XZ
  float x0, z0, x1, z1;
  float w() const { return x1 - x0; }
  float d() const { return z1 - z0; }
  glm::vec2 center() const { return {0.5f * (x0 + x1), 0.5f * (z0 + z1)}; }
  Rect inset(float m) const { return {x0 + m, z0 + m, x1 - m, z1 - m}; }
};

// Sizes of what a city, a block or a street grid adds to a scene.
struct Counts {
  uint64_t objects = 0, vertices = 0, triangles = 0, name_bytes = 0;
  Counts& operator+=(const Counts& c) {
    objects += c.objects, vertices += c.vertices, triangles += c.triangles;
    name_bytes += c.name_bytes;
    return *this;
  }
  bool fits() const {  // Object and index offsets are 32-bit
    return vertices < UINT32_MAX && triangles * 3 <= UINT32_MAX && name_bytes <= UINT32_MAX;
  }
};

Counts counts_of(const Scene& s) {
  return {s.objects.size(), s.vertices.size(), s.triangle_count(), s.names.size()};
}

constexpr float kSidewalk = 4.0f;      // ground between the curb and the lots, m
constexpr float kTreeInset = 1.5f;     // street trees stand this far inside the curb, m
constexpr float kMinLot = 6.0f;        // a smaller lot is left empty, m
constexpr float kLotGap = 1.0f;        // each lot keeps this much from its neighbours, m
constexpr float kGrassHeight = 0.25f;  // raised grass beds of the parks, m
constexpr float kRecess = 0.2f;        // depth of a window in the wall, m
// A block this large on its own (absurd options) stops early and makes the city too large.
constexpr uint64_t kBlockMost = UINT32_MAX / 2;

// Writes the city into a scene, one object per building, tree, fountain, park strip, street
// piece and curb (paper 000, App. A).
class CityWriter {
 public:
  // `with_textures`: o.textures applies (the sizing pass leaves textures out: they change no
  // count).
  CityWriter(Scene& scene, const CityOptions& o, bool with_textures = false)
      : scene_(scene),
        b_(scene),
        o_(o),
        opaque_(b_.add_material(Material{glm::vec4(1.0f)})),
        glass_(b_.add_material(Material{glm::vec4(1.0f, 1.0f, 1.0f, 0.5f)})),
        street_y_(static_cast<float>(o.street_height)),
        ground_y_(static_cast<float>(o.street_height + o.curb_height)) {
    if (!(with_textures && o.textures)) return;
    auto textured = [&](const char* name, const Texels& texels) {
      auto texture = texture_from_texels(name, texels);
      FF_ASSERT(texture.ok(), "%s", texture.ok() ? "" : texture.error().message.c_str());
      return b_.add_material(
          Material{.base_color = glm::vec4(1.0f), .texture = b_.add_texture(std::move(*texture))});
    };
    facade_ = textured("city facade (procedural)", city::facade_texels());
    paving_ = textured("city paving (procedural)", city::paving_texels());
    asphalt_ = textured("city asphalt (procedural)", city::asphalt_texels());
  }

  // Blocks start at x = street_width and repeat every block_length + street_width.
  Rect block_rect(uint32_t bx, uint32_t bz) const {
    const double x = o_.street_width + bx * (o_.block_length + o_.street_width);
    const double z = o_.street_width + bz * (o_.block_width + o_.street_width);
    return {float(x), float(z), float(x + o_.block_length), float(z + o_.block_width)};
  }

  void streets(uint32_t nx, uint32_t nz);
  void block(uint32_t bx, uint32_t bz);

 private:
  void street_piece(const char* kind, uint32_t i, uint32_t j, const Rect& r);
  void open(ObjectKind kind, std::string_view what, int index = -1, int sub = -1,
            bool glass = false);
  void close();

  void curbs(const Rect& block);
  void street_trees(const Rect& block);
  void lots(const Rect& area);
  void park(const Rect& area, float arm_fraction, bool park_block);
  void building(const Rect& lot);
  void segment(const glm::vec2& c, float hx, float hz, int sides, float y0, int floors,
               float floor_h, bool alternating, bool dividers, bool cap, uint32_t wall,
               uint32_t window, uint32_t trim);
  void fountain(const glm::vec2& c, float radius);
  void tree(const glm::vec2& p, float y, bool conifer);

  Scene& scene_;
  SceneBuilder b_;
  const CityOptions& o_;
  uint32_t opaque_, glass_;
  // --textures: the materials of walls, sidewalks and streets (kNoTexture: none).
  uint32_t facade_ = kNoTexture, paving_ = kNoTexture, asphalt_ = kNoTexture;
  float street_y_, ground_y_;
  Rng rng_{0};
  std::string prefix_, name_;
  int buildings_ = 0, trees_ = 0, fountains_ = 0, parks_ = 0;
  size_t block_start_ = 0;  // the scene's vertex count when the block began
  std::vector<float> cuts_;
  std::vector<glm::vec2> corners_;
};

void CityWriter::open(ObjectKind kind, std::string_view what, int index, int sub, bool glass) {
  name_ = prefix_;
  name_ += what;
  if (index >= 0) (name_ += '_') += std::to_string(index);
  if (sub >= 0) (name_ += '_') += std::to_string(sub);
  uint32_t material = glass ? glass_ : opaque_;
  if (facade_ != kNoTexture && !glass) {
    if (kind == ObjectKind::building) material = facade_;
    if (kind == ObjectKind::ground) material = paving_;
    if (kind == ObjectKind::street) material = asphalt_;
  }
  b_.begin_object(name_, kind, material);
}

void CityWriter::close() {
  const size_t objects = scene_.objects.size();
  b_.end_object();
  if (scene_.objects.size() == objects) return;  // nothing drawn: dropped
  const Object& o = scene_.objects.back();
  if (!scene_.textured(o)) return;
  // Bricks a quarter of a metre high on walls, slabs of a metre on sidewalks.
  const float tile = o.material == facade_ ? 2.0f : o.material == paving_ ? 4.0f : 8.0f;
  city::project_texture_coordinates(scene_, o, tile);
}

// Streets run between and around the blocks: one piece per stretch between two crossings and
// one per crossing, each a slab with its top at street_height.
void CityWriter::streets(uint32_t nx, uint32_t nz) {
  prefix_.clear();
  const float s = static_cast<float>(o_.street_width);
  for (uint32_t j = 0; j <= nz; ++j) {
    for (uint32_t i = 0; i <= nx; ++i) {
      const Rect east = block_rect(i, j);  // the block to the +X +Z side of crossing (i, j)
      const Rect crossing{east.x0 - s, east.z0 - s, east.x0, east.z0};
      street_piece("crossing", i, j, crossing);
      if (i < nx) street_piece("street_x", i, j, {east.x0, crossing.z0, east.x1, crossing.z1});
      if (j < nz) street_piece("street_z", i, j, {crossing.x0, east.z0, crossing.x1, east.z1});
    }
  }
}

void CityWriter::street_piece(const char* kind, uint32_t i, uint32_t j, const Rect& r) {
  prefix_.clear();
  open(ObjectKind::street, kind, int(i), int(j));
  mesh::box(b_, {r.x0, 0.0f, r.z0}, {r.x1, street_y_, r.z1}, color(kStreet), mesh::kNoBottom);
  close();
}

void CityWriter::block(uint32_t bx, uint32_t bz) {
  rng_ = block_rng(o_.seed, bx, bz);
  block_start_ = scene_.vertices.size();
  prefix_ = "block_" + std::to_string(bx) + "_" + std::to_string(bz) + "/";
  buildings_ = trees_ = fountains_ = parks_ = 0;
  const Rect r = block_rect(bx, bz);
  const bool park_block = rng_.chance(o_.park_block_fraction);
  const bool lined = rng_.chance(o_.tree_block_fraction);

  curbs(r);
  const float cw = static_cast<float>(o_.curb_width);
  open(ObjectKind::ground, "ground");
  mesh::box(b_, {r.x0 + cw, ground_y_, r.z0 + cw}, {r.x1 - cw, ground_y_, r.z1 - cw},
            color(kGround), mesh::kPosY);
  close();
  if (lined) street_trees(r);

  // paper 000, App. A: a park block is one big park with a fountain in the middle.
  const Rect inner = r.inset(cw + kSidewalk);
  if (inner.w() < kMinLot || inner.d() < kMinLot) return;
  if (park_block)
    park(inner, 0.7f, true);
  else
    lots(inner);
}

// Four curb pieces along the block's edges, from the street top to the curb top.
void CityWriter::curbs(const Rect& r) {
  const float cw = static_cast<float>(o_.curb_width);
  const uint32_t c = color(kCurb);
  const Rect pieces[4] = {{r.x0, r.z0, r.x1, r.z0 + cw},
                          {r.x0, r.z1 - cw, r.x1, r.z1},
                          {r.x0, r.z0 + cw, r.x0 + cw, r.z1 - cw},
                          {r.x1 - cw, r.z0 + cw, r.x1, r.z1 - cw}};
  // The faces that look onto the street; the others lie under the ground or against a curb.
  const uint32_t faces[4] = {mesh::kPosY | mesh::kNegZ | mesh::kNegX | mesh::kPosX,
                             mesh::kPosY | mesh::kPosZ | mesh::kNegX | mesh::kPosX,
                             mesh::kPosY | mesh::kNegX, mesh::kPosY | mesh::kPosX};
  for (int i = 0; i < 4; ++i) {
    open(ObjectKind::curb, "curb", i);
    const Rect& p = pieces[i];
    mesh::box(b_, {p.x0, street_y_, p.z0}, {p.x1, ground_y_, p.z1}, c, faces[i]);
    close();
  }
}

// Trees along the four sides of the block, tree_distance apart, centred on each side.
void CityWriter::street_trees(const Rect& r) {
  const Rect path = r.inset(static_cast<float>(o_.curb_width) + kTreeInset);
  if (path.w() <= 0.0f || path.d() <= 0.0f) return;
  const bool conifer = rng_.chance(0.3);  // one kind of tree per block
  const double step = o_.tree_distance;
  auto line = [&](glm::vec2 a, glm::vec2 b) {
    const double length = glm::length(b - a);
    const int count = static_cast<int>(std::floor(length / step));
    const double start = 0.5 * (length - (count - 1) * step);
    for (int k = 0; k < count; ++k)
      tree(a + (b - a) * float((start + k * step) / length), ground_y_, conifer);
  };
  line({path.x0, path.z0}, {path.x1, path.z0});
  line({path.x0, path.z1}, {path.x1, path.z1});
  line({path.x0, path.z0}, {path.x0, path.z1});
  line({path.x1, path.z0}, {path.x1, path.z1});
}

// paper 000, App. A: rows at random spacing, each row divided into columns at random spacing;
// a lot too small stays empty, else holds a park, a building or a fountain.
void CityWriter::lots(const Rect& area) {
  auto split = [&](float lo, float hi, uint32_t most) {
    const uint32_t count = rng_.range(std::max(1u, (most + 1) / 2), most);
    cuts_.assign(1, lo);
    double total = 0.0;
    for (uint32_t k = 0; k < count; ++k) {
      cuts_.push_back(rng_.uniform(0.3, 1.7));
      total += cuts_.back();
    }
    double at = lo;
    for (uint32_t k = 1; k <= count; ++k) {
      at += (hi - lo) * cuts_[k] / total;
      cuts_[k] = k == count ? hi : static_cast<float>(at);
    }
    return cuts_;
  };
  const std::vector<float> rows = split(area.z0, area.z1, o_.rows);
  for (size_t row = 0; row + 1 < rows.size(); ++row) {
    const std::vector<float> columns = split(area.x0, area.x1, o_.columns);
    for (size_t col = 0; col + 1 < columns.size(); ++col) {
      const Rect lot =
          Rect{columns[col], rows[row], columns[col + 1], rows[row + 1]}.inset(kLotGap);
      if (lot.w() < kMinLot || lot.d() < kMinLot) continue;
      if (scene_.vertices.size() - block_start_ > kBlockMost) return;
      const double kind = rng_.uniform();
      if (kind < 0.10) {
        park(lot, 0.4f, false);
      } else if (kind < 0.20) {
        const float r = 0.5f * std::min(lot.w(), lot.d()) * rng_.uniform(0.5, 0.85);
        fountain(lot.center(), std::min(r, 10.0f));
      } else {
        building(lot);
      }
    }
  }
}

// paper 000, App. A: a park is four L-shaped grass strips, one at each corner, with paths
// between them; a park block has a fountain in the middle and trees on the grass.
void CityWriter::park(const Rect& area, float arm_fraction, bool park_block) {
  const int park = parks_++;
  const glm::vec2 c = area.center();
  const float path = std::clamp(0.06f * std::min(area.w(), area.d()), 1.5f, 6.0f);
  const float qw = 0.5f * (area.w() - path), qd = 0.5f * (area.d() - path);
  const float arm = arm_fraction * std::min(qw, qd);
  const uint32_t grass = jitter(rng_, kGrass);
  const float top = ground_y_ + kGrassHeight;
  for (int corner = 0; corner < 4; ++corner) {
    const float x0 = (corner & 1) ? c.x + 0.5f * path : area.x0;
    const float z0 = (corner & 2) ? c.y + 0.5f * path : area.z0;
    const glm::vec2 lo(x0, z0), hi(x0 + qw, z0 + qd);
    open(ObjectKind::park, "park", park, corner);
    mesh::l_shape(b_, lo, hi, arm, corner, ground_y_, top, grass);
    close();
    if (!park_block) continue;
    const bool conifer = rng_.chance(0.3);
    const float step = std::max(static_cast<float>(o_.tree_distance), 8.0f), margin = 1.5f;
    for (float u = 0.5f * step; u < qw; u += step) {  // u, v: from the block's outer corner
      for (float v = 0.5f * step; v < qd; v += step) {
        const float du = u + rng_.uniform(-0.25, 0.25) * step;
        const float dv = v + rng_.uniform(-0.25, 0.25) * step;
        const bool in_l = du > margin && dv > margin && du < qw - margin && dv < qd - margin &&
                          (du < arm - margin || dv < arm - margin);
        if (!in_l || !rng_.chance(0.6)) continue;
        tree({(corner & 1) ? hi.x - du : lo.x + du, (corner & 2) ? hi.y - dv : lo.y + dv}, top,
             conifer);
      }
    }
  }
  if (park_block) {
    const float plaza = std::min(qw, qd) - arm + 0.5f * path;  // half size of the open middle
    if (plaza > 1.5f) fountain(c, std::min(0.75f * plaza, 12.0f));
  }
}

// paper 000, App. A: a fountain is layers of wall and water, each inner layer smaller and
// taller than the one around it.
void CityWriter::fountain(const glm::vec2& c, float radius) {
  open(ObjectKind::fountain, "fountain", fountains_++);
  const uint32_t wall = jitter(rng_, kFountainWall), water = color(kWater);
  const int layers = static_cast<int>(rng_.range(2, 4));
  const int sides = std::clamp(4 * static_cast<int>(std::lround(radius * 0.8f)), 12, 32);
  float r = radius, base = ground_y_, top = ground_y_ + rng_.uniform(0.4, 0.7);
  for (int layer = 0; layer < layers && r > 0.4f; ++layer) {
    const float wall_w = std::max(0.15f, 0.08f * r), water_y = top - 0.15f;
    mesh::round_side(b_, c, r, base, r, top, sides, wall);
    mesh::annulus(b_, c, r - wall_w, r, top, sides, wall, true);
    mesh::round_side(b_, c, r - wall_w, water_y, r - wall_w, top, sides, wall, true);
    mesh::disk(b_, c, r - wall_w, water_y, sides, water, true);
    base = water_y;
    top += rng_.uniform(0.5, 1.1);
    r *= rng_.uniform(0.4, 0.6);
  }
  // A jet of water from the innermost basin.
  mesh::cone(b_, c, std::max(0.1f, 0.5f * r), base, top + rng_.uniform(0.5, 1.5), sides / 2, water,
             false);
  close();
}

// A trunk and either a round crown (broadleaf, 112 triangles) or three stacked cones (conifer,
// 66 triangles).
void CityWriter::tree(const glm::vec2& p, float y, bool conifer) {
  open(ObjectKind::tree, "tree", trees_++);
  const float scale = rng_.uniform(0.8, 1.2);
  const uint32_t trunk = jitter(rng_, kTrunk, 0.03f);
  const float trunk_r = 0.2f * scale;
  if (conifer) {
    const uint32_t needles = jitter(rng_, kNeedles);
    const float trunk_h = 1.2f * scale, r = 2.0f * scale, h = 3.0f * scale;
    mesh::round_side(b_, p, trunk_r, y, trunk_r, y + trunk_h, 6, trunk);
    for (int k = 0; k < 3; ++k) {
      const float base = y + trunk_h + k * 0.45f * h, rk = r * (1.0f - 0.25f * k);
      mesh::cone(b_, p, rk, base, base + h, 10, needles, true);
    }
  } else {
    const uint32_t leaves = jitter(rng_, kLeaves);
    const float trunk_h = 2.6f * scale, r = 2.0f * scale * rng_.uniform(0.9, 1.1);
    const float crown_y = y + trunk_h + 0.8f * r;
    mesh::round_side(b_, p, trunk_r, y, 0.6f * trunk_r, crown_y, 6, trunk);
    mesh::ellipsoid(b_, {p.x, crown_y, p.y}, {r, r * rng_.uniform(0.9, 1.3), r}, 10, 6, leaves);
  }
  close();
}

// paper 000, App. A: a building is cylindrical or rectangular, solid or semi-transparent,
// with a cone- or pyramid-shaped top, made of segments, each of one colour or of alternating
// colours, some with thin horizontal dividers between the floors.
void CityWriter::building(const Rect& lot) {
  const bool glass = rng_.chance(0.15), round = rng_.chance(0.3);
  const Rect foot = lot.inset(rng_.uniform(0.5, 2.0));
  float hx = 0.5f * foot.w(), hz = 0.5f * foot.d();
  if (round) hx = hz = std::min(hx, hz);
  const glm::vec2 c = foot.center();

  // Mostly low, a few towers: the cube of a uniform number, and no pencil towers.
  // Heights from the ground, so that the tallest top stays under max_height.
  const double max_h = std::max(o_.max_height - ground_y_, 1.0), min_h = std::min(6.0, max_h);
  double h = min_h + (max_h - min_h) * std::pow(rng_.uniform(), 3.0);
  h = std::min(h, std::max(min_h, 10.0 * std::min(hx, hz)));
  const double roof_h = std::min(0.2 * h, double(std::min(hx, hz) * rng_.uniform(0.15, 0.6)));
  const double body = h - roof_h;
  const int floors = std::max(1, static_cast<int>(std::lround(body / rng_.uniform(3.2, 3.9))));
  const float floor_h = static_cast<float>(body / floors);
  const int segments = 1 + (floors >= 6 ? int(rng_.range(0, 1)) : 0) +
                       (floors >= 15 ? int(rng_.range(0, 1)) : 0) +
                       (floors >= 30 ? int(rng_.range(0, 1)) : 0);

  const uint32_t wall = jitter(rng_, glass ? rng_.pick(kGlass) : rng_.pick(kWalls));
  const uint32_t window = jitter(rng_, rng_.pick(kWindows));
  const uint32_t trim = jitter(rng_, rng_.pick(kTrims));
  const uint32_t roof = jitter(rng_, rng_.pick(kRoofs));
  // A cone on round buildings and a pyramid on rectangular ones, mostly.
  const bool cone_top = rng_.chance(round ? 0.8 : 0.2);
  const bool roof_fits = cone_top == round;  // the roof covers the top exactly
  // Round sides: smoother for wider buildings.
  const int sides = round ? std::clamp(4 * static_cast<int>(std::lround(hx * 0.6f)), 12, 32) : 0;

  open(ObjectKind::building, "building", buildings_++, -1, glass);
  float y = ground_y_;
  int floors_left = floors;
  for (int s = 0; s < segments; ++s) {
    if (s > 0) {  // each segment set back from the one below
      const float shrink = rng_.uniform(0.7, 0.9);
      hx = std::max(hx * shrink, std::min(hx, 2.0f));
      hz = round ? hx : std::max(hz * shrink, std::min(hz, 2.0f));
    }
    const int left_after = segments - 1 - s;
    const int f = left_after == 0
                      ? floors_left
                      : std::clamp(int(std::lround(floors_left * rng_.uniform(0.4, 0.7))), 1,
                                   floors_left - left_after);
    floors_left -= f;
    const bool alternating = rng_.chance(0.65), dividers = f > 1 && rng_.chance(0.5);
    segment(c, hx, hz, sides, y, f, floor_h, alternating, dividers, left_after > 0 || !roof_fits,
            wall, window, trim);
    y += f * floor_h;
  }
  const float top = y + static_cast<float>(roof_h);
  if (cone_top) {  // on a rectangle: the largest circle inside it
    mesh::cone(b_, c, round ? hx : 0.95f * std::min(hx, hz), y, top, round ? sides : 16, roof,
               false);
  } else {  // on a circle: the largest square inside it
    const glm::vec2 half = round ? glm::vec2(0.95f * 0.7071f * hx) : glm::vec2(hx, hz);
    mesh::pyramid(b_, c - half, c + half, y, top, roof, false);
  }
  close();
}

// One segment of a building: `floors` floors of `floor_h` from y0, rectangular (sides = 0,
// half sizes hx, hz) or round (radius hx). Alternating colours: each floor a band of wall
// under a row of windows between piers. Dividers: a thin slab standing out at each floor line.
void CityWriter::segment(const glm::vec2& c, float hx, float hz, int sides, float y0, int floors,
                         float floor_h, bool alternating, bool dividers, bool cap, uint32_t wall,
                         uint32_t window, uint32_t trim) {
  const float y1 = y0 + floors * floor_h;
  if (alternating) {
    if (sides) {
      mesh::circle_points(c, hx, sides, corners_);
    } else {  // by increasing angle, like a circle's
      corners_ = {
          {c.x + hx, c.y - hz}, {c.x + hx, c.y + hz}, {c.x - hx, c.y + hz}, {c.x - hx, c.y - hz}};
    }
    const float sill = rng_.uniform(0.3, 0.45) * floor_h;
    const mesh::WindowRows rows{
        floor_h, sill, rng_.uniform(2.6, 3.6), rng_.uniform(0.5, 0.75), kRecess, wall, window};
    mesh::window_walls(b_, corners_, y0, floors, rows);
  } else if (sides) {
    mesh::round_side(b_, c, hx, y0, hx, y1, sides, wall);
  } else {
    mesh::box(b_, {c.x - hx, y0, c.y - hz}, {c.x + hx, y1, c.y + hz}, wall, mesh::kSides);
  }
  if (dividers) {
    const float t = std::min(0.3f, 0.1f * floor_h), out = 0.2f;
    for (int k = 1; k < floors; ++k) {
      const float a = y0 + k * floor_h - 0.5f * t, b = a + t;
      if (sides) {
        mesh::round_side(b_, c, hx + out, a, hx + out, b, sides, trim);
        mesh::annulus(b_, c, hx, hx + out, b, sides, trim, true);
        mesh::annulus(b_, c, hx, hx + out, a, sides, trim, false);
      } else {
        mesh::box(b_, {c.x - hx - out, a, c.y - hz - out}, {c.x + hx + out, b, c.y + hz + out},
                  trim);
      }
    }
  }
  if (cap) {
    if (sides)
      mesh::disk(b_, c, hx, y1, sides, wall, true);
    else
      mesh::box(b_, {c.x - hx, y1, c.y - hz}, {c.x + hx, y1, c.y + hz}, wall, mesh::kPosY);
  }
}

}  // namespace

namespace {

Result<void> check_size(const char* option, double v, double most) {
  if (!std::isfinite(v) || v <= 0.0)
    return make_error(option, " must be > 0 (got ", number_text(v), ")");
  if (v > most)
    return make_error(option, " must be at most ", number_text(most), " (got ", number_text(v),
                      ")");
  return {};
}

Result<void> check_count(const char* option, uint64_t v, uint64_t most) {
  if (v == 0) return make_error(option, " must be at least 1");
  if (v > most)
    return make_error(option, " must be at most ", std::to_string(most), " (got ",
                      std::to_string(v), ")");
  return {};
}

Result<void> check_fraction(const char* option, double v) {
  if (!(v >= 0.0 && v <= 1.0))  // also rejects NaN
    return make_error(option, " must be in [0, 1] (got ", number_text(v), ")");
  return {};
}

constexpr uint64_t kMostTargetTriangles = 1'000'000'000;  // indices stay below 2^32

// Lower bound on a block's triangles (ground and curbs), to refuse absurd grids at once.
constexpr uint64_t kLeastBlockTriangles = 2 + 4 * 6;

Error too_large(const Counts& c) {
  return make_error("the city would have at least ", std::to_string(c.triangles), " triangles and ",
                    std::to_string(c.vertices),
                    " vertices, over the 2^32 indices or vertices a scene can hold; use fewer "
                    "--blocks-x/--blocks-z or a lower --target-triangles");
}

}  // namespace

Result<void> validate_city_options(const CityOptions& o) {
  for (const Result<void>& r : {
           check_size("--max-height", o.max_height, 10000.0),
           check_size("--block-length", o.block_length, 10000.0),
           check_size("--block-width", o.block_width, 10000.0),
           check_count("--rows", o.rows, 1000),
           check_count("--columns", o.columns, 1000),
           check_count("--blocks-x", o.blocks_x, 100000),
           check_count("--blocks-z", o.blocks_z, 100000),
           check_size("--street-width", o.street_width, 10000.0),
           check_size("--street-height", o.street_height, 100.0),
           check_size("--curb-width", o.curb_width, 10000.0),
           check_size("--curb-height", o.curb_height, 100.0),
           check_size("--tree-distance", o.tree_distance, 10000.0),
           check_fraction("--park-blocks", o.park_block_fraction),
           check_fraction("--tree-blocks", o.tree_block_fraction),
       }) {
    if (!r) return r;
  }
  const double half_block = 0.5 * std::min(o.block_length, o.block_width);
  if (o.curb_width >= half_block)
    return make_error("--curb-width must be less than half the block (", number_text(half_block),
                      " m) (got ", number_text(o.curb_width), ")");
  if (o.tree_distance < 1.0)
    return make_error("--tree-distance must be at least 1 m (got ", number_text(o.tree_distance),
                      ")");
  if (o.target_triangles > kMostTargetTriangles)
    return make_error("--target-triangles must be at most ", std::to_string(kMostTargetTriangles),
                      " (got ", std::to_string(o.target_triangles), ")");
  return {};
}

namespace {

// The grid and what it holds, from pass 1.
struct CityPlan {
  uint32_t nx = 0, nz = 0;
  Counts total;
};

// Pass 1: sizes the city block by block in a scratch scene, which picks the grid for
// --target-triangles, refuses a city too large for a scene and lets pass 2 allocate once.
Result<CityPlan> plan_city(const CityOptions& options, Progress& progress) {
  if (auto ok = validate_city_options(options); !ok) return ok.error();
  Scene scratch;
  auto size = [&](auto&& write) {
    scratch.objects.clear(), scratch.vertices.clear(), scratch.indices.clear();
    scratch.names.clear(), scratch.materials.clear();
    CityWriter writer(scratch, options);
    write(writer);
    return counts_of(scratch);
  };
  auto size_block = [&](uint32_t bx, uint32_t bz) {
    Counts c = size([&](CityWriter& w) { w.block(bx, bz); });
    if (c.vertices > kBlockMost) c.vertices = UINT32_MAX;  // cut short: too large
    return c;
  };
  auto size_streets = [&](uint32_t nx, uint32_t nz) {
    return size([&](CityWriter& w) { w.streets(nx, nz); });
  };

  CityPlan plan{options.blocks_x, options.blocks_z, {}};
  Counts& total = plan.total;
  if (options.target_triangles == 0) {
    const uint64_t least = uint64_t(plan.nx) * plan.nz * kLeastBlockTriangles;
    if (least * 3 > UINT32_MAX) return too_large(Counts{0, least, least, 0});
    progress.start("size city", uint64_t(plan.nx) * plan.nz);
    total = size_streets(plan.nx, plan.nz);
    for (uint32_t bz = 0; bz < plan.nz && total.fits(); ++bz) {
      for (uint32_t bx = 0; bx < plan.nx && total.fits(); ++bx) {
        total += size_block(bx, bz);
        progress.advance();
      }
    }
  } else {  // grow the square grid ring by ring: block (x, z) is in ring max(x, z)
    progress.start("size city", options.target_triangles);
    Counts blocks;
    for (uint32_t n = 1;; ++n) {
      for (uint32_t k = 0; k < n; ++k) {
        blocks += size_block(k, n - 1);
        if (k != n - 1) blocks += size_block(n - 1, k);
      }
      const uint64_t before = std::min(total.triangles, options.target_triangles);
      total = blocks;
      total += size_streets(n, n);
      progress.advance(std::min(total.triangles, options.target_triangles) - before);
      if (total.triangles >= options.target_triangles || !total.fits()) {
        plan.nx = plan.nz = n;
        break;
      }
    }
  }
  if (!total.fits()) return too_large(total);
  return plan;
}

// Pass 2: the streets, then the blocks row by row, into `scene`; `part_done` is called after
// the streets and after each block.
Result<void> emit_city(const CityOptions& options, const CityPlan& plan, Scene& scene,
                       Progress& progress, const std::function<Result<void>()>& part_done) {
  CityWriter writer(scene, options, true);
  progress.start("generate city", uint64_t(plan.nx) * plan.nz);
  writer.streets(plan.nx, plan.nz);
  if (auto ok = part_done(); !ok) return ok;
  for (uint32_t bz = 0; bz < plan.nz; ++bz) {
    for (uint32_t bx = 0; bx < plan.nx; ++bx) {
      writer.block(bx, bz);
      if (auto ok = part_done(); !ok) return ok;
      progress.advance();
    }
  }
  return {};
}

}  // namespace

Result<Scene> generate_city(const CityOptions& options, Progress& progress) {
  auto plan = plan_city(options, progress);
  if (!plan) return plan.error();
  const Counts& total = plan->total;
  // Held whole in memory: refuse what this machine cannot hold rather than fail after the work
  // (write_city writes a city of any size without holding it).
  const uint64_t bytes = total.objects * sizeof(Object) + total.vertices * sizeof(Vertex) +
                         total.triangles * 3 * sizeof(uint32_t) + total.name_bytes;
  const uint64_t memory = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE));
  if (bytes > memory)
    return make_error("the city would have ", std::to_string(total.triangles),
                      " triangles and need ", number_text(double(bytes) / 1e9),
                      " GB of memory, more than this machine's ", number_text(double(memory) / 1e9),
                      " GB; use fewer --blocks-x/--blocks-z or a lower --target-triangles");
  Scene scene;
  scene.objects.reserve(total.objects);
  scene.vertices.reserve(total.vertices);
  scene.indices.reserve(total.triangles * 3);
  scene.names.reserve(total.name_bytes);
  if (auto ok = emit_city(options, *plan, scene, progress, [] { return Result<void>{}; }); !ok)
    return ok.error();
  FF_ASSERT(scene.triangle_count() == total.triangles && scene.vertices.size() == total.vertices,
            "sized %llu triangles, wrote %llu", (unsigned long long)total.triangles,
            (unsigned long long)scene.triangle_count());
  return scene;
}

Result<SceneFileInfo> write_city(const CityOptions& options, const std::string& path,
                                 Progress& progress) {
  auto plan = plan_city(options, progress);
  if (!plan) return plan.error();
  auto writer = SceneFileWriter::create(path, {plan->total.vertices, plan->total.triangles * 3});
  if (!writer) return writer.error();
  // A block at a time: what it made goes to the file, and the scene keeps only its materials,
  // textures and bounds.
  Scene scene;
  auto ok = emit_city(options, *plan, scene, progress, [&]() -> Result<void> {
    if (auto appended = writer->append(scene); !appended) return appended;
    scene.objects.clear(), scene.vertices.clear(), scene.indices.clear();
    scene.names.clear(), scene.uvs.clear();
    return {};
  });
  if (!ok) return ok.error();
  return writer->finish(scene);
}

}  // namespace farfield
