#include "farfield/scene/building_generator.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <string>
#include <vector>

#include "farfield/core/text.hpp"
#include "mesh_primitives.hpp"
#include "random.hpp"

namespace farfield {

namespace {

constexpr float kHalfWall = 0.1f;  // walls are 0.2 m thick, centred on the cells' boundaries
constexpr float kSlab = 0.3f;      // floor slab under the storey above
constexpr float kDoorWidth = 1.0f, kDoorHeight = 2.1f;
constexpr float kWindowWidth = 1.4f, kSill = 0.9f, kWindowTop = 2.4f;
constexpr float kLanding = 1.5f;  // stairwell landings' length along X
constexpr int kSteps = 20;        // per flight

const glm::vec3 kUp(0.0f, 1.0f, 0.0f);

// A rectangular hole in a wall: along the wall from its start, and heights from the floor.
struct Hole {
  float s0, s1, y0, y1;
};

// Quads overlap their neighbours by this much (m) on every side: pieces of a wall, a wall and
// its floor, a jamb and its wall meet without the rasterizer's hairline cracks, through which
// one room would glimpse another (and portal rendering, which does not draw it, would differ
// from brute force by a pixel).
constexpr float kOverlap = 0.002f;

// One quad o, o+u, o+u+v, o+v that faces along `normal`, grown by kOverlap on every side.
void facing_quad(SceneBuilder& b, glm::vec3 o, glm::vec3 u, glm::vec3 v, const glm::vec3& normal,
                 uint32_t colour) {
  const glm::vec3 du = glm::normalize(u) * kOverlap, dv = glm::normalize(v) * kOverlap;
  o -= du + dv;
  u += 2.0f * du;
  v += 2.0f * dv;
  if (glm::dot(glm::cross(u, v), normal) >= 0.0f)
    mesh::quad(b, o, u, v, colour);
  else
    mesh::quad(b, o + u, -u, v, colour);
}

// The face of a wall from `a` along `along` (unit, horizontal) for `length`, from height y0 to
// y1 above a's, facing `normal`, less its holes (sorted, within the wall).
void wall_face(SceneBuilder& b, const glm::vec3& a, const glm::vec3& along, float length,
               float height, const glm::vec3& normal, std::vector<Hole> holes, uint32_t colour) {
  std::sort(holes.begin(), holes.end(), [](const Hole& x, const Hole& y) { return x.s0 < y.s0; });
  auto piece = [&](float s0, float s1, float y0, float y1) {
    s0 = std::clamp(s0, 0.0f, length);
    s1 = std::clamp(s1, 0.0f, length);
    if (s1 - s0 < 1e-4f || y1 - y0 < 1e-4f) return;
    facing_quad(b, a + along * s0 + kUp * y0, along * (s1 - s0), kUp * (y1 - y0), normal, colour);
  };
  float s = 0.0f;
  for (const Hole& h : holes) {
    piece(s, h.s0, 0.0f, height);
    piece(h.s0, h.s1, 0.0f, h.y0);
    piece(h.s0, h.s1, h.y1, height);
    s = std::max(s, h.s1);
  }
  piece(s, length, 0.0f, height);
}

// The sides of a hole through a wall: the hole's rectangle at `a` + along * [s0, s1], heights
// [y0, y1], swept by `depth` across the wall; faces look into the hole. At floor level the
// sill is the threshold between two floors that end at the wall's faces.
void hole_sides(SceneBuilder& b, const glm::vec3& a, const glm::vec3& along, const Hole& h,
                const glm::vec3& depth, uint32_t colour) {
  const glm::vec3 p0 = a + along * h.s0 + kUp * h.y0, p1 = a + along * h.s1 + kUp * h.y0;
  const float height = h.y1 - h.y0, width = h.s1 - h.s0;
  facing_quad(b, p0, depth, kUp * height, along, colour);                 // left jamb, facing along
  facing_quad(b, p1, depth, kUp * height, -along, colour);                // right jamb
  facing_quad(b, p0 + kUp * height, along * width, depth, -kUp, colour);  // head
  facing_quad(b, p0, along * width, depth, kUp, colour);                  // sill
}

// The cells as they are built: their boxes, names and objects.
struct CellDraft {
  std::string name;
  Bounds3 bounds;
  std::vector<uint32_t> objects;
};

class BuildingBuilder {
 public:
  BuildingBuilder(const BuildingOptions& o, Scene& scene)
      : o_(o), scene_(scene), b_(scene), rng_(o.seed) {
    material_ = b_.add_material(Material{});
    n_ = o.rooms_per_side;
    w_ = float(o.room_width);
    d_ = float(o.room_depth);
    c_ = float(o.corridor_width);
    h_ = float(o.storey);
    length_ = float(n_) * w_;
    stair_x_ = float(n_ - 2) * w_;
    segments_ = (n_ + o.segment_rooms - 1) / o.segment_rooms;
  }

  void build(Progress& progress) {
    outside_ = add_cell("outside",
                        {{-50.0f, -1.0f, -(c_ / 2 + d_) - 50.0f},
                         {length_ + 50.0f, float(o_.floors) * h_ + 50.0f, c_ / 2 + d_ + 50.0f}});
    stairwell_ = add_cell(
        "stairwell", {{stair_x_, 0.0f, -(c_ / 2 + d_)}, {length_, float(o_.floors) * h_, -c_ / 2}});
    progress.start("building floors", o_.floors);
    for (uint32_t k = 0; k < o_.floors; ++k) {
      floor(k);
      progress.advance();
    }
    stairwell();
    outside();
    finish();
  }

 private:
  uint32_t add_cell(std::string name, const Bounds3& bounds) {
    cells_.push_back({std::move(name), bounds, {}});
    return uint32_t(cells_.size() - 1);
  }
  void begin(const std::string& name, ObjectKind kind) { b_.begin_object(name, kind, material_); }
  // Ends the object and lists it in the cells that see it.
  void end(std::initializer_list<uint32_t> cells) {
    const size_t before = scene_.objects.size();
    b_.end_object();
    if (scene_.objects.size() == before) return;  // no triangles
    for (uint32_t c : cells) cells_[c].objects.push_back(uint32_t(before));
  }
  // A portal of four corners; `into_first` points from the portal into cells[0].
  void add_portal(uint32_t first, uint32_t second, std::vector<glm::vec3> q,
                  const glm::vec3& into_first) {
    if (glm::dot(glm::cross(q[1] - q[0], q[2] - q[0]), into_first) < 0.0f)
      std::reverse(q.begin(), q.end());
    portals_.push_back({{first, second}, uint32_t(points_.size()), uint32_t(q.size())});
    points_.insert(points_.end(), q.begin(), q.end());
  }
  uint32_t colour(float r, float g, float b) { return pack_color({r, g, b, 1.0f}); }
  uint32_t segment_of(float x) const {
    return std::min(uint32_t(x / (w_ * float(o_.segment_rooms))), segments_ - 1);
  }

  void floor(uint32_t k) {
    const float y0 = float(k) * h_;
    segment_base_ = uint32_t(cells_.size());
    for (uint32_t s = 0; s < segments_; ++s) {
      const float x0 = float(s * o_.segment_rooms) * w_;
      const float x1 = std::min(float((s + 1) * o_.segment_rooms) * w_, length_);
      add_cell(formatted("floor_%u/corridor_%u", k, s), {{x0, y0, -c_ / 2}, {x1, y0 + h_, c_ / 2}});
    }
    for (int side : {1, -1})
      for (uint32_t i = 0; i < n_; ++i)
        if (side == 1 || i + 2 < n_) room(k, i, side);
    corridor(k);
  }

  // Room slot i of floor k on the north (side 1) or south (-1) of the corridor.
  void room(uint32_t k, uint32_t i, int side) {
    const float y0 = float(k) * h_, sg = float(side);
    const float x0 = float(i) * w_;
    const float z_near = sg * c_ / 2, z_far = sg * (c_ / 2 + d_);
    Bounds3 box;
    box.expand(glm::vec3(x0, y0, z_near));
    box.expand(glm::vec3(x0 + w_, y0 + h_, z_far));
    const std::string name = formatted("floor_%u/room_%s_%u", k, side > 0 ? "n" : "s", i);
    const uint32_t cell = add_cell(name, box);
    const uint32_t corridor = segment_base_ + segment_of(x0 + 1.2f);
    // Inner faces: 0.1 m inside the cell's box; the ceiling under the slab of the floor above.
    const float ix0 = x0 + kHalfWall, ix1 = x0 + w_ - kHalfWall;
    const float iz_near = z_near + sg * kHalfWall, iz_far = z_far - sg * kHalfWall;
    const float height = h_ - kSlab;
    const glm::vec3 into(0.0f, 0.0f, sg);  // from the corridor towards the outside
    const glm::vec3 x_axis(1.0f, 0.0f, 0.0f);
    const float tint = rng_.uniform(0.0, 1.0);
    const uint32_t walls = colour(0.80f + 0.15f * tint, 0.78f + 0.1f * (1 - tint), 0.70f);
    const Hole door{0.6f, 0.6f + kDoorWidth, 0.0f, kDoorHeight};  // from ix0
    const float wx[2] = {w_ / 4 - kHalfWall, 3 * w_ / 4 - kHalfWall};
    const Hole windows[2] = {
        {wx[0] - kWindowWidth / 2, wx[0] + kWindowWidth / 2, kSill, kWindowTop},
        {wx[1] - kWindowWidth / 2, wx[1] + kWindowWidth / 2, kSill, kWindowTop}};
    const float inner_width = ix1 - ix0, inner_depth = std::abs(iz_far - iz_near);

    begin(name + "/walls", ObjectKind::building);
    wall_face(b_, {ix0, y0, iz_near}, x_axis, inner_width, height, into, {door}, walls);
    wall_face(b_, {ix0, y0, iz_far}, x_axis, inner_width, height, -into, {windows[0], windows[1]},
              walls);
    wall_face(b_, {ix0, y0, iz_near}, into, inner_depth, height, x_axis, {}, walls);
    wall_face(b_, {ix1, y0, iz_near}, into, inner_depth, height, -x_axis, {}, walls);
    const uint32_t floor_colour = colour(0.55f, 0.42f, 0.30f), ceiling = colour(0.93f, 0.93f, 0.9f);
    facing_quad(b_, {ix0, y0, iz_near}, x_axis * inner_width, into * inner_depth, kUp,
                floor_colour);
    facing_quad(b_, {ix0, y0 + height, iz_near}, x_axis * inner_width, into * inner_depth, -kUp,
                ceiling);
    end({cell});

    // The door's jambs and head through the corridor wall, seen from both sides.
    begin(name + "/door", ObjectKind::building);
    hole_sides(b_, {ix0, y0, z_near - sg * kHalfWall}, x_axis, door, into * (2 * kHalfWall),
               colour(0.45f, 0.30f, 0.20f));
    end({cell, corridor});
    add_portal(cell, corridor,
               {{ix0 + door.s0, y0, z_near},
                {ix0 + door.s1, y0, z_near},
                {ix0 + door.s1, y0 + kDoorHeight, z_near},
                {ix0 + door.s0, y0 + kDoorHeight, z_near}},
               into);
    begin(name + "/windows", ObjectKind::building);
    for (const Hole& wnd : windows) {
      hole_sides(b_, {ix0, y0, iz_far}, x_axis, wnd, into * (2 * kHalfWall),
                 colour(0.9f, 0.9f, 0.9f));
      add_portal(cell, outside_,
                 {{ix0 + wnd.s0, y0 + wnd.y0, z_far},
                  {ix0 + wnd.s1, y0 + wnd.y0, z_far},
                  {ix0 + wnd.s1, y0 + wnd.y1, z_far},
                  {ix0 + wnd.s0, y0 + wnd.y1, z_far}},
                 -into);
    }
    end({cell, outside_});
    furnish(name, cell, {ix0, y0, iz_near}, sg, inner_width, inner_depth, height);

    // The facade outside this room: the outer face of the wall, with the windows' holes.
    const float fz = z_far + sg * kHalfWall;
    const float fx0 = i == 0 ? -kHalfWall : x0, fx1 = i + 1 == n_ ? length_ + kHalfWall : x0 + w_;
    std::vector<Hole> holes;
    for (const Hole& wnd : windows)
      holes.push_back({wnd.s0 + ix0 - fx0, wnd.s1 + ix0 - fx0, wnd.y0, wnd.y1});
    begin(name + "/facade", ObjectKind::building);
    wall_face(b_, {fx0, y0, fz}, x_axis, fx1 - fx0, h_, into, holes, colour(0.62f, 0.6f, 0.58f));
    end({outside_});
  }

  // The furniture of a room whose inner floor starts at `o` (west wall, corridor side),
  // `depth` metres deep towards the outside (sg: +Z or -Z).
  void furnish(const std::string& name, uint32_t cell, const glm::vec3& o, float sg, float width,
               float depth, float height) {
    // Local (u along X, v away from the corridor, y up) to world.
    auto at = [&](float u, float y, float v) { return glm::vec3(o.x + u, o.y + y, o.z + sg * v); };
    auto block = [&](float u0, float y0, float v0, float u1, float y1, float v1, uint32_t c,
                     uint32_t faces = mesh::kAllFaces) {
      const glm::vec3 p = at(u0, y0, v0), q = at(u1, y1, v1);
      mesh::box(b_, glm::min(p, q), glm::max(p, q), c, faces);
    };
    auto leg = [&](float u, float v, float r, float y0, float y1, int sides, uint32_t c) {
      const glm::vec3 p = at(u, 0.0f, v);
      mesh::cylinder(b_, {p.x, p.z}, r, o.y + y0, o.y + y1, sides, c);
    };
    const uint32_t wood = colour(0.50f, 0.33f, 0.18f), dark = colour(0.15f, 0.15f, 0.17f);

    // Two bookshelves against the side walls, full of books.
    for (int shelf = 0; shelf < 2; ++shelf) {
      begin(name + (shelf ? "/shelf_w" : "/shelf_e"), ObjectKind::mesh);
      const float u0 = shelf ? 0.0f : width - 0.4f, u1 = u0 + 0.4f;
      const float v0 = shelf ? 2.4f : 1.4f, v1 = v0 + 2.8f;
      const float back = shelf ? u0 : u1;  // against the wall
      const float dir = shelf ? 1.0f : -1.0f;
      block(u0, 0.0f, v0, u1, 2.0f, v0 + 0.03f, wood);
      block(u0, 0.0f, v1 - 0.03f, u1, 2.0f, v1, wood);
      block(back, 0.0f, v0, back + dir * 0.02f, 2.0f, v1, wood);
      constexpr int kLevels = 5;
      const uint32_t per_level = (o_.books + kLevels - 1) / kLevels;
      uint32_t placed = 0;
      for (int level = 0; level <= kLevels; ++level) {
        const float y = 0.05f + float(level) * 0.38f;
        block(u0, y - 0.03f, v0 + 0.03f, u1, y, v1 - 0.03f, wood);
        if (level == kLevels) break;
        float v = v0 + 0.05f;
        for (uint32_t k = 0; k < per_level && placed < o_.books; ++k, ++placed) {
          const float thick = rng_.uniform(0.025, 0.06), tall = rng_.uniform(0.20, 0.32);
          const float deep = rng_.uniform(0.17, 0.27);
          if (v + thick > v1 - 0.05f) break;
          const uint32_t c =
              colour(rng_.uniform(0.1, 0.9), rng_.uniform(0.1, 0.8), rng_.uniform(0.1, 0.7));
          block(back + dir * 0.03f, y, v, back + dir * (0.03f + deep), y + tall, v + thick, c,
                mesh::kNoBottom);
          v += thick + 0.004f;
        }
      }
      end({cell});
    }

    // A desk under the windows, with a chair, a screen, a lamp and a globe.
    begin(name + "/desk", ObjectKind::mesh);
    const float du = width / 2 - 0.8f, dv = depth - 0.9f;
    block(du, 0.72f, dv, du + 1.6f, 0.76f, dv + 0.8f, wood);
    for (float lu : {du + 0.06f, du + 1.54f})
      for (float lv : {dv + 0.06f, dv + 0.74f}) leg(lu, lv, 0.025f, 0.0f, 0.72f, 10, dark);
    const float cu = width / 2, cv = dv - 0.5f;
    block(cu - 0.23f, 0.44f, cv - 0.23f, cu + 0.23f, 0.49f, cv + 0.23f, colour(0.2f, 0.3f, 0.6f));
    block(cu - 0.23f, 0.49f, cv - 0.25f, cu + 0.23f, 0.95f, cv - 0.21f, colour(0.2f, 0.3f, 0.6f));
    for (float lu : {cu - 0.2f, cu + 0.2f})
      for (float lv : {cv - 0.2f, cv + 0.2f}) leg(lu, lv, 0.015f, 0.0f, 0.44f, 8, dark);
    block(du + 0.55f, 0.76f, dv + 0.55f, du + 1.05f, 1.08f, dv + 0.58f, dark);  // screen
    block(du + 0.5f, 0.76f, dv + 0.2f, du + 1.1f, 0.78f, dv + 0.36f, dark);     // keyboard
    const glm::vec3 lamp = at(du + 1.4f, 0.0f, dv + 0.6f);
    mesh::cylinder(b_, {lamp.x, lamp.z}, 0.07f, o.y + 0.76f, o.y + 0.78f, 16, dark);
    mesh::cylinder(b_, {lamp.x, lamp.z}, 0.012f, o.y + 0.78f, o.y + 1.1f, 8, dark);
    mesh::round_side(b_, {lamp.x, lamp.z}, 0.12f, o.y + 1.05f, 0.05f, o.y + 1.2f, 16,
                     colour(0.9f, 0.85f, 0.5f));
    const glm::vec3 globe = at(du + 0.2f, 0.98f, dv + 0.6f);
    mesh::cylinder(b_, {globe.x, globe.z}, 0.05f, o.y + 0.76f, o.y + 0.84f, 12, wood);
    mesh::ellipsoid(b_, globe, glm::vec3(0.14f), 20, 12, colour(0.2f, 0.45f, 0.75f));
    end({cell});

    // A plant in the far corner, a lamp under the ceiling, a rug.
    begin(name + "/plant", ObjectKind::mesh);
    const glm::vec3 pot = at(width - 0.35f, 0.0f, depth - 0.35f);
    mesh::round_side(b_, {pot.x, pot.z}, 0.16f, o.y, 0.2f, o.y + 0.35f, 16,
                     colour(0.6f, 0.3f, 0.2f));
    mesh::ellipsoid(b_, pot + glm::vec3(0.0f, 0.8f, 0.0f), {0.3f, 0.45f, 0.3f}, 16, 10,
                    colour(0.2f, 0.5f, 0.2f));
    end({cell});
    begin(name + "/light", ObjectKind::mesh);
    const glm::vec3 light = at(width / 2, height - 0.35f, depth / 2);
    mesh::cylinder(b_, {light.x, light.z}, 0.01f, light.y, o.y + height, 6, dark);
    mesh::ellipsoid(b_, light, {0.25f, 0.12f, 0.25f}, 16, 8, colour(1.0f, 0.95f, 0.8f));
    end({cell});
    begin(name + "/rug", ObjectKind::mesh);
    block(width / 2 - 1.0f, 0.0f, depth / 2 - 0.7f, width / 2 + 1.0f, 0.01f, depth / 2 + 0.7f,
          colour(0.6f, 0.15f, 0.15f), mesh::kNoBottom);
    end({cell});
  }

  // The corridor of floor k: per segment its walls (doors' holes), floor, ceiling and lamps,
  // and the open portals between segments.
  void corridor(uint32_t k) {
    const float y0 = float(k) * h_, height = h_ - kSlab;
    const glm::vec3 x_axis(1.0f, 0.0f, 0.0f);
    const float iz = c_ / 2 - kHalfWall;
    const uint32_t walls = colour(0.85f, 0.85f, 0.8f);
    for (uint32_t s = 0; s < segments_; ++s) {
      const uint32_t cell = segment_base_ + s;
      const Bounds3& box = cells_[cell].bounds;
      const float x0 = box.min.x + (s == 0 ? kHalfWall : 0.0f);
      const float x1 = box.max.x - (s + 1 == segments_ ? kHalfWall : 0.0f);
      std::vector<Hole> north, south;
      for (uint32_t i = 0; i < n_; ++i) {
        const float door0 = float(i) * w_ + kHalfWall + 0.6f;
        if (segment_of(door0 + 0.5f) != s) continue;
        north.push_back({door0 - x0, door0 + kDoorWidth - x0, 0.0f, kDoorHeight});
        if (i + 2 < n_) south.push_back(north.back());
      }
      for (float door0 : {stair_x_ + 0.2f, length_ - 0.2f - kDoorWidth})
        if (segment_of(door0 + 0.5f) == s)
          south.push_back({door0 - x0, door0 + kDoorWidth - x0, 0.0f, kDoorHeight});
      begin(cells_[cell].name + "/walls", ObjectKind::building);
      wall_face(b_, {x0, y0, iz}, x_axis, x1 - x0, height, {0, 0, -1}, north, walls);
      wall_face(b_, {x0, y0, -iz}, x_axis, x1 - x0, height, {0, 0, 1}, south, walls);
      if (s == 0) wall_face(b_, {x0, y0, -iz}, {0, 0, 1}, 2 * iz, height, x_axis, {}, walls);
      if (s + 1 == segments_)
        wall_face(b_, {x1, y0, -iz}, {0, 0, 1}, 2 * iz, height, -x_axis, {}, walls);
      facing_quad(b_, {x0, y0, -iz}, x_axis * (x1 - x0), glm::vec3(0, 0, 2 * iz), kUp,
                  colour(0.35f, 0.35f, 0.38f));
      facing_quad(b_, {x0, y0 + height, -iz}, x_axis * (x1 - x0), glm::vec3(0, 0, 2 * iz), -kUp,
                  colour(0.93f, 0.93f, 0.9f));
      end({cell});
      begin(cells_[cell].name + "/lamps", ObjectKind::mesh);
      for (float x = x0 + w_ / 2; x < x1; x += w_)
        mesh::cylinder(b_, {x, 0.0f}, 0.2f, y0 + height - 0.08f, y0 + height, 16,
                       colour(1.0f, 1.0f, 0.9f));
      end({cell});
      if (s + 1 < segments_)
        add_portal(cell, cell + 1,
                   {{box.max.x, y0, -iz},
                    {box.max.x, y0, iz},
                    {box.max.x, y0 + height, iz},
                    {box.max.x, y0 + height, -iz}},
                   -x_axis);
    }
  }

  // The stairwell: walls with two doors a floor, landings, one flight a floor.
  void stairwell() {
    const glm::vec3 x_axis(1.0f, 0.0f, 0.0f), z_axis(0.0f, 0.0f, 1.0f);
    const float ix0 = stair_x_ + kHalfWall, ix1 = length_ - kHalfWall;
    const float iz0 = -(c_ / 2 + d_) + kHalfWall, iz1 = -c_ / 2 - kHalfWall;
    const uint32_t walls = colour(0.75f, 0.75f, 0.78f), concrete = colour(0.6f, 0.6f, 0.6f);
    const float run = (ix1 - kLanding - (ix0 + kLanding)) / float(kSteps);
    const float rise = h_ / float(kSteps);
    for (uint32_t k = 0; k < o_.floors; ++k) {
      const float y0 = float(k) * h_;
      const Hole doors[2] = {{0.1f, 0.1f + kDoorWidth, 0.0f, kDoorHeight},
                             {ix1 - ix0 - 0.1f - kDoorWidth, ix1 - ix0 - 0.1f, 0.0f, kDoorHeight}};
      const std::string name = formatted("stairwell/floor_%u", k);
      begin(name + "/walls", ObjectKind::building);
      wall_face(b_, {ix0, y0, iz1}, x_axis, ix1 - ix0, h_, -z_axis, {doors[0], doors[1]}, walls);
      wall_face(b_, {ix0, y0, iz0}, x_axis, ix1 - ix0, h_, z_axis, {}, walls);
      wall_face(b_, {ix0, y0, iz0}, z_axis, iz1 - iz0, h_, x_axis, {}, walls);
      wall_face(b_, {ix1, y0, iz0}, z_axis, iz1 - iz0, h_, -x_axis, {}, walls);
      if (k == 0)
        facing_quad(b_, {ix0, 0.0f, iz0}, x_axis * (ix1 - ix0), z_axis * (iz1 - iz0), kUp,
                    concrete);
      if (k + 1 == o_.floors)
        facing_quad(b_, {ix0, y0 + h_ - kSlab, iz0}, x_axis * (ix1 - ix0), z_axis * (iz1 - iz0),
                    -kUp, concrete);
      end({stairwell_});
      const uint32_t corridor = segment_base_of(k);
      for (const Hole& door : doors) {
        begin(name + "/door", ObjectKind::building);
        hole_sides(b_, {ix0, y0, iz1}, x_axis, door, z_axis * (2 * kHalfWall),
                   colour(0.45f, 0.30f, 0.20f));
        end({stairwell_, corridor + segment_of(ix0 + door.s0 + 0.5f)});
        const float z = -c_ / 2;
        add_portal(stairwell_, corridor + segment_of(ix0 + door.s0 + 0.5f),
                   {{ix0 + door.s0, y0, z},
                    {ix0 + door.s1, y0, z},
                    {ix0 + door.s1, y0 + kDoorHeight, z},
                    {ix0 + door.s0, y0 + kDoorHeight, z}},
                   -z_axis);
      }
      begin(name + "/stairs", ObjectKind::building);
      if (k >
          0) {  // the landings of this floor: west, the next flight's foot; east, the last's top
        mesh::box(b_, {ix0, y0 - kSlab, iz0}, {ix0 + kLanding, y0, iz1}, concrete);
        mesh::box(b_, {ix1 - kLanding, y0 - kSlab, iz0}, {ix1, y0, iz1}, concrete);
      }
      if (k + 1 < o_.floors)
        for (int j = 0; j < kSteps; ++j) {
          const float x = ix0 + kLanding + float(j) * run, top = y0 + float(j + 1) * rise;
          const float bottom = k == 0 ? std::max(top - 0.45f, 0.0f) : top - 0.45f;
          mesh::box(b_, {x, bottom, iz0}, {x + run, top, iz1}, concrete);
        }
      end({stairwell_});
    }
  }

  uint32_t segment_base_of(uint32_t k) const {
    // Cells: outside, stairwell, then per floor its segments and its rooms.
    const uint32_t rooms = 2 * n_ - 2;
    return 2 + k * (segments_ + rooms);
  }

  // Ground, roof, end walls, the stairwell's facades and trees.
  void outside() {
    const float zf = c_ / 2 + d_ + kHalfWall, top = float(o_.floors) * h_;
    const glm::vec3 x_axis(1.0f, 0.0f, 0.0f), z_axis(0.0f, 0.0f, 1.0f);
    const uint32_t facade = colour(0.62f, 0.6f, 0.58f);
    begin("outside/ground", ObjectKind::ground);
    const float gx0 = -50.0f, gx1 = length_ + 50.0f, gz = zf + 50.0f;
    const uint32_t grass = colour(0.35f, 0.55f, 0.3f);
    facing_quad(b_, {gx0, 0, -gz}, x_axis * (gx1 - gx0), z_axis * (gz - zf), kUp, grass);
    facing_quad(b_, {gx0, 0, zf}, x_axis * (gx1 - gx0), z_axis * (gz - zf), kUp, grass);
    facing_quad(b_, {gx0, 0, -zf}, x_axis * (-kHalfWall - gx0), z_axis * (2 * zf), kUp, grass);
    facing_quad(b_, {length_ + kHalfWall, 0, -zf}, x_axis * (gx1 - length_ - kHalfWall),
                z_axis * (2 * zf), kUp, grass);
    end({outside_});
    begin("outside/roof", ObjectKind::building);
    facing_quad(b_, {-kHalfWall, top, -zf}, x_axis * (length_ + 2 * kHalfWall), z_axis * (2 * zf),
                kUp, colour(0.4f, 0.4f, 0.42f));
    end({outside_});
    for (uint32_t k = 0; k < o_.floors; ++k) {
      const float y0 = float(k) * h_;
      begin(formatted("outside/ends_%u", k), ObjectKind::building);
      wall_face(b_, {-kHalfWall, y0, -zf}, z_axis, 2 * zf, h_, -x_axis, {}, facade);
      wall_face(b_, {length_ + kHalfWall, y0, -zf}, z_axis, 2 * zf, h_, x_axis, {}, facade);
      wall_face(b_, {stair_x_, y0, -zf}, x_axis, length_ + kHalfWall - stair_x_, h_, -z_axis, {},
                facade);
      end({outside_});
    }
    for (int side : {1, -1}) {
      for (uint32_t i = 0; i < n_; ++i) {
        begin(formatted("outside/tree_%s_%u", side > 0 ? "n" : "s", i), ObjectKind::tree);
        const glm::vec2 c((float(i) + 0.5f) * w_ + rng_.uniform(-1.0, 1.0),
                          float(side) * (zf + 8.0f + rng_.uniform(-1.5, 1.5)));
        const float tall = rng_.uniform(5.0, 9.0);
        mesh::cylinder(b_, c, 0.2f, 0.0f, tall * 0.5f, 10, colour(0.4f, 0.28f, 0.15f));
        mesh::ellipsoid(b_, {c.x, tall * 0.65f, c.y}, {1.8f, tall * 0.35f, 1.8f}, 14, 9,
                        colour(0.2f, 0.45f + rng_.uniform(0.0, 0.15), 0.18f));
        end({outside_});
      }
    }
  }

  void finish() {
    for (const CellDraft& draft : cells_) {
      Cell c;
      c.bounds = draft.bounds;
      c.first_object = uint32_t(scene_.cell_objects.size());
      c.object_count = uint32_t(draft.objects.size());
      c.name_offset = uint32_t(scene_.names.size());
      c.name_size = uint32_t(draft.name.size());
      scene_.names += draft.name;
      scene_.cell_objects.insert(scene_.cell_objects.end(), draft.objects.begin(),
                                 draft.objects.end());
      scene_.cells.push_back(c);
    }
    scene_.portals = std::move(portals_);
    scene_.portal_points = std::move(points_);
  }

  const BuildingOptions& o_;
  Scene& scene_;
  SceneBuilder b_;
  detail::Rng rng_;
  uint32_t material_ = 0;
  uint32_t n_ = 0, segments_ = 0;
  float w_ = 0, d_ = 0, c_ = 0, h_ = 0, length_ = 0, stair_x_ = 0;
  std::vector<CellDraft> cells_;
  std::vector<Portal> portals_;
  std::vector<glm::vec3> points_;
  uint32_t outside_ = 0, stairwell_ = 0, segment_base_ = 0;
};

}  // namespace

Result<void> validate_building_options(const BuildingOptions& o) {
  auto bad = [](const char* option, const std::string& rule, double value) {
    return make_error("--", option, " must be ", rule, " (got ", number_text(value), ")");
  };
  if (o.floors < 1 || o.floors > 200) return bad("floors", "in [1, 200]", o.floors);
  if (o.rooms_per_side < 3 || o.rooms_per_side > 2000)
    return bad("rooms", "in [3, 2000] (two slots hold the stairwell)", o.rooms_per_side);
  if (o.segment_rooms < 1 || o.segment_rooms > 2000)
    return bad("segment-rooms", "in [1, 2000]", o.segment_rooms);
  if (!(o.room_width >= 3.0 && o.room_width <= 50.0))
    return bad("room-width", "in [3, 50] m", o.room_width);
  if (!(o.room_depth >= 5.5 && o.room_depth <= 50.0))
    return bad("room-depth", "in [5.5, 50] m", o.room_depth);
  if (!(o.corridor_width >= 1.5 && o.corridor_width <= 20.0))
    return bad("corridor-width", "in [1.5, 20] m", o.corridor_width);
  if (!(o.storey >= 3.0 && o.storey <= 10.0)) return bad("storey", "in [3, 10] m", o.storey);
  if (o.books > 1000) return bad("books", "at most 1000", o.books);
  return {};
}

Result<Scene> generate_building(const BuildingOptions& options, Progress& progress) {
  if (auto ok = validate_building_options(options); !ok) return ok.error();
  Scene scene;
  BuildingBuilder(options, scene).build(progress);
  progress.finish();
  if (std::string problem = validate_scene(scene); !problem.empty())
    return make_error("generate building: the generated scene is invalid (", problem, ")");
  return scene;
}

}  // namespace farfield
