// Portal rendering on hand-built cells (spatial/portal_walk, techniques/portal): a corridor
// of rooms, a loop of rooms, a portal seen edge-on, the eye in a doorway; and on random views
// every object a ray from the eye reaches is drawn (conservative, both clip variants).
#include "farfield/spatial/portal_walk.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "farfield/scene/scene_file.hpp"
#include "farfield/spatial/ray_caster.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

constexpr float kRoom = 4.0f, kHeight = 3.0f;

// A door between rooms (i0, j0) and (i1, j1) of a grid on XZ, 1 m wide and 2 m high, its
// centre `offset` metres along the shared wall from the wall's middle.
struct Door {
  int i0, j0, i1, j1;
  float offset = 0.0f;
};

// Rooms of kRoom x kHeight x kRoom on a grid of (i, j) positions, each one cell: walls 0.1 m
// inside the cell's box facing inwards, with holes for the doors, a floor, a ceiling and a
// small crate in its middle. A door's jambs (closing the wall between two rooms around the
// hole) belong to both rooms' cells; the portal is the hole's section on the cells' boundary.
struct Rooms {
  Scene scene;
  std::vector<uint32_t> crates;  // per room
};

// One quad p0 p1 p2 p3 facing the side where `inside` lies.
void quad_facing(SceneBuilder& b, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3,
                 const glm::vec3& inside) {
  glm::vec3 n = glm::normalize(glm::cross(p1 - p0, p3 - p0));
  if (glm::dot(n, inside - p0) < 0.0f) {
    std::swap(p1, p3);
    n = -n;
  }
  const uint32_t white = pack_color({1, 1, 1, 1});
  const uint32_t v0 = b.add_vertex(p0, n, white), v1 = b.add_vertex(p1, n, white),
                 v2 = b.add_vertex(p2, n, white), v3 = b.add_vertex(p3, n, white);
  b.add_triangle(v0, v1, v2);
  b.add_triangle(v0, v2, v3);
}

Rooms make_rooms(const std::vector<std::pair<int, int>>& grid, const std::vector<Door>& doors) {
  constexpr float t = 0.1f, kDoorHeight = 2.0f;
  Rooms r;
  SceneBuilder b(r.scene);
  const uint32_t wall = b.add_material({.base_color = {0.8f, 0.8f, 0.7f, 1.0f}});
  const uint32_t crate = b.add_material({.base_color = {0.7f, 0.3f, 0.1f, 1.0f}});
  std::vector<std::vector<uint32_t>> cell_objects(grid.size());
  auto room_of = [&](int i, int j) {
    return uint32_t(std::find(grid.begin(), grid.end(), std::pair(i, j)) - grid.begin());
  };
  auto lo_of = [&](uint32_t room) {
    return glm::vec3(grid[room].first * kRoom, 0.0f, grid[room].second * kRoom);
  };
  // A door's opening: its centre on the shared boundary and the unit vector along the wall.
  struct Opening {
    uint32_t c0, c1;
    glm::vec3 centre, along, across;  // across: from c0 to c1
  };
  std::vector<Opening> openings;
  for (const Door& d : doors) {
    Opening o{room_of(d.i0, d.j0), room_of(d.i1, d.j1), {}, {}, {}};
    const glm::vec3 m0 = lo_of(o.c0) + glm::vec3(kRoom / 2, 0, kRoom / 2);
    const glm::vec3 m1 = lo_of(o.c1) + glm::vec3(kRoom / 2, 0, kRoom / 2);
    o.across = glm::normalize(m1 - m0);
    o.along = glm::vec3(-o.across.z, 0.0f, o.across.x);
    o.centre = (m0 + m1) * 0.5f + o.along * d.offset;
    openings.push_back(o);
  }
  for (uint32_t room = 0; room < grid.size(); ++room) {
    const glm::vec3 lo = lo_of(room), hi = lo + glm::vec3(kRoom, kHeight, kRoom);
    const glm::vec3 centre = (lo + hi) * 0.5f;
    const glm::vec3 in_lo = lo + glm::vec3(t, 0, t), in_hi = hi - glm::vec3(t, 0, t);
    const glm::vec3 corners[4] = {
        in_lo, {in_hi.x, 0, in_lo.z}, {in_hi.x, 0, in_hi.z}, {in_lo.x, 0, in_hi.z}};
    b.begin_object("walls", ObjectKind::mesh, wall);
    for (int side = 0; side < 4; ++side) {
      const glm::vec3 a = corners[side], c = corners[(side + 1) % 4];
      const glm::vec3 along = glm::normalize(c - a);
      const float length = glm::length(c - a);
      std::vector<std::pair<float, float>> holes;  // along the wall, metres from a
      for (const Opening& o : openings) {
        if (o.c0 != room && o.c1 != room) continue;
        const glm::vec3 out = o.c0 == room ? o.across : -o.across;
        const glm::vec3 mid = (a + c) * 0.5f;
        if (glm::dot(glm::normalize(glm::vec3(mid.x - centre.x, 0, mid.z - centre.z)), out) < 0.5f)
          continue;
        const float s = glm::dot(o.centre - a, along);
        holes.push_back({s - 0.5f, s + 0.5f});
      }
      std::sort(holes.begin(), holes.end());
      auto piece = [&](float s0, float s1, float y0, float y1) {
        const glm::vec3 up(0, 1, 0);
        quad_facing(b, a + along * s0 + up * y0, a + along * s1 + up * y0, a + along * s1 + up * y1,
                    a + along * s0 + up * y1, centre);
      };
      float s = 0.0f;
      for (const auto& [h0, h1] : holes) {
        piece(s, h0, 0.0f, kHeight);
        piece(h0, h1, kDoorHeight, kHeight);
        s = h1;
      }
      piece(s, length, 0.0f, kHeight);
    }
    b.end_object();
    cell_objects[room].push_back(uint32_t(r.scene.objects.size() - 1));
    b.begin_object("floor and ceiling", ObjectKind::mesh, wall);
    test::add_cuboid(b, lo - glm::vec3(0, 0.1f, 0), glm::vec3(hi.x, 0.0f, hi.z));
    test::add_cuboid(b, glm::vec3(lo.x, kHeight, lo.z), hi + glm::vec3(0, 0.1f, 0));
    b.end_object();
    cell_objects[room].push_back(uint32_t(r.scene.objects.size() - 1));
    b.begin_object("crate", ObjectKind::mesh, crate);
    test::add_cuboid(b, glm::vec3(centre.x - 0.3f, 0.0f, centre.z - 0.3f),
                     glm::vec3(centre.x + 0.3f, 0.6f, centre.z + 0.3f));
    b.end_object();
    r.crates.push_back(uint32_t(r.scene.objects.size() - 1));
    cell_objects[room].push_back(r.crates.back());
  }
  Scene& s = r.scene;
  for (const Opening& o : openings) {
    // The jambs and the head, closing the wall's thickness around the hole.
    b.begin_object("jambs", ObjectKind::mesh, wall);
    const glm::vec3 d = o.across * t, w = o.along * 0.5f, up(0, kDoorHeight, 0);
    const glm::vec3 c = o.centre;
    quad_facing(b, c - w - d, c - w + d, c - w + d + up, c - w - d + up, c);
    quad_facing(b, c + w - d, c + w + d, c + w + d + up, c + w - d + up, c);
    quad_facing(b, c - w - d + up, c + w - d + up, c + w + d + up, c - w + d + up, c);
    b.end_object();
    for (uint32_t cell : {o.c0, o.c1}) cell_objects[cell].push_back(uint32_t(s.objects.size() - 1));
  }
  for (uint32_t room = 0; room < grid.size(); ++room) {
    Cell c;
    c.bounds.min = lo_of(room);
    c.bounds.max = c.bounds.min + glm::vec3(kRoom, kHeight, kRoom);
    c.first_object = uint32_t(s.cell_objects.size());
    c.object_count = uint32_t(cell_objects[room].size());
    s.cell_objects.insert(s.cell_objects.end(), cell_objects[room].begin(),
                          cell_objects[room].end());
    s.cells.push_back(c);
  }
  for (const Opening& o : openings) {
    const glm::vec3 w = o.along * 0.5f, up(0, kDoorHeight, 0);
    std::vector<glm::vec3> q = {o.centre - w, o.centre + w, o.centre + w + up, o.centre - w + up};
    // Counter-clockwise seen from cells[0]: the normal points back into c0.
    if (glm::dot(glm::cross(q[1] - q[0], q[2] - q[0]), o.across) > 0)
      std::reverse(q.begin(), q.end());
    s.portals.push_back({{o.c0, o.c1}, uint32_t(s.portal_points.size()), 4});
    s.portal_points.insert(s.portal_points.end(), q.begin(), q.end());
  }
  return r;
}

View view_at(const glm::vec3& eye, float yaw_deg, float pitch_deg = 0.0f) {
  View v;
  v.width = 256;
  v.height = 192;
  v.pose = {eye, yaw_deg, pitch_deg};
  return v;
}

std::set<uint32_t> cells_seen(const Scene& scene, const View& view, PortalClip clip) {
  PortalWalk walk(scene, {.clip = clip});
  std::vector<CellVisit> visits;
  walk.walk(view, *cell_containing(scene, view.pose.position), visits);
  std::set<uint32_t> cells;
  for (const CellVisit& v : visits) cells.insert(v.cell);
  return cells;
}

TEST(PortalWalk, ACorridorOfRoomsIsSeenThroughItsDoorsOnlyAhead) {
  // Five rooms in a row along X, doors in the middle of each shared wall.
  Rooms r = make_rooms({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}},
                       {{0, 0, 1, 0}, {1, 0, 2, 0}, {2, 0, 3, 0}, {3, 0, 4, 0}});
  ASSERT_EQ(validate_scene(r.scene), "");
  const glm::vec3 eye(1.0f, 1.0f, 2.0f);  // room 0, on the doors' line
  for (PortalClip clip : {PortalClip::exact, PortalClip::rectangles}) {
    EXPECT_EQ(cells_seen(r.scene, view_at(eye, 0.0f), clip), (std::set<uint32_t>{0, 1, 2, 3, 4}));
    // Looking back (-X) the doors are behind the eye; looking at a side wall, out of view.
    EXPECT_EQ(cells_seen(r.scene, view_at(eye, 180.0f), clip), (std::set<uint32_t>{0}));
  }
  // Doors off the line: from room 0's corner the far rooms hide behind the walls.
  Rooms zig = make_rooms({{0, 0}, {1, 0}, {2, 0}, {3, 0}},
                         {{0, 0, 1, 0, 1.4f}, {1, 0, 2, 0, -1.4f}, {2, 0, 3, 0, 1.4f}});
  const View corner = view_at({0.3f, 1.0f, 0.3f}, 20.0f);
  const auto exact = cells_seen(zig.scene, corner, PortalClip::exact);
  const auto rects = cells_seen(zig.scene, corner, PortalClip::rectangles);
  EXPECT_TRUE(exact.count(1));
  EXPECT_FALSE(exact.count(3));
  EXPECT_LE(exact.size(), rects.size());
  EXPECT_TRUE(std::includes(rects.begin(), rects.end(), exact.begin(), exact.end()));
}

TEST(PortalWalk, ALoopOfRoomsEnds) {
  // Four rooms in a ring, each door seen from the next room.
  Rooms r = make_rooms({{0, 0}, {1, 0}, {1, 1}, {0, 1}},
                       {{0, 0, 1, 0}, {1, 0, 1, 1}, {1, 1, 0, 1}, {0, 1, 0, 0}});
  ASSERT_EQ(validate_scene(r.scene), "");
  PortalWalk walk(r.scene, {.clip = PortalClip::rectangles});
  std::vector<CellVisit> visits;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> at(0.2f, 3.8f), yaw(0.0f, 360.0f);
  for (int i = 0; i < 200; ++i) {
    const View v = view_at({at(rng), 1.5f, at(rng)}, yaw(rng));
    walk.walk(v, 0, visits);
    EXPECT_LE(visits.size(), 16u);  // no chain passes a portal twice: at most 4 deep
    for (const CellVisit& visit : visits) EXPECT_FALSE(visit.beyond_limits);
  }
}

TEST(PortalWalk, APortalSeenEdgeOnShowsNothingAndADoorwayShowsBothSides) {
  Rooms r = make_rooms({{0, 0}, {1, 0}}, {{0, 0, 1, 0}});
  // The eye in the door's plane beside its opening, looking along the wall: edge-on.
  PortalWalk walk(r.scene, {});
  std::vector<CellVisit> visits;
  walk.walk(view_at({4.0f, 1.0f, 0.5f}, 90.0f), 0, visits);
  ASSERT_EQ(visits.size(), 1u);
  // Standing in the doorway looking into room 0: room 1 behind is in view at the sides.
  walk.walk(view_at({4.0f, 1.0f, 2.0f}, 180.0f), 0, visits);
  ASSERT_EQ(visits.size(), 2u);
  EXPECT_EQ(visits[1].cell, 1u);
  EXPECT_EQ(visits[1].volume.planes().size(), visits[0].volume.planes().size());  // unnarrowed
}

// Every object that a ray from the eye through the view meets first (beyond the near plane)
// is drawn: the walk never hides what is seen.
void expect_conservative(const Rooms& r, const char* clip) {
  auto portal = make_technique(clip);
  ASSERT_TRUE(portal) << portal.error().message;
  ASSERT_TRUE(test::load_technique(**portal, r.scene));
  RayCaster caster(r.scene);
  std::mt19937 rng(11);
  // Eyes inside the rooms' walls, never within them.
  std::uniform_real_distribution<float> in_room(0.15f, kRoom - 0.15f), y(0.3f, 2.7f),
      yaw(0.0f, 360.0f), pitch(-30.0f, 30.0f), unit(-1.0f, 1.0f);
  std::uniform_int_distribution<uint32_t> room(0, uint32_t(r.scene.cells.size() - 1));
  DrawList list;
  int hits = 0, crates_far = 0;
  for (int i = 0; i < 150; ++i) {
    const glm::vec3 lo = r.scene.cells[room(rng)].bounds.min;
    const View view =
        view_at({lo.x + in_room(rng), y(rng), lo.z + in_room(rng)}, yaw(rng), pitch(rng));
    test::select_view(**portal, view, list);
    std::vector<bool> drawn(r.scene.objects.size(), false);
    for (const DrawRange& range : list.opaque)
      for (uint32_t o = 0; o < r.scene.objects.size(); ++o)
        if (r.scene.objects[o].first_index >= range.first_index &&
            r.scene.objects[o].first_index < range.first_index + range.index_count)
          drawn[o] = true;
    const glm::mat4 inverse = glm::inverse(view.view_projection());
    for (int k = 0; k < 200; ++k) {
      const glm::vec4 p = inverse * glm::vec4(unit(rng), unit(rng), 0.5f, 1.0f);
      const glm::vec3 dir = glm::normalize(glm::vec3(p) / p.w - view.pose.position);
      const auto hit = caster.cast(view.pose.position, dir, 1e4f);
      if (!hit || hit->distance * glm::dot(dir, view.pose.forward()) < view.near_m) continue;
      ++hits;
      EXPECT_TRUE(drawn[hit->object])
          << clip << " view " << i << " misses object " << hit->object << " at " << hit->distance
          << " m, eye (" << view.pose.position.x << ", " << view.pose.position.y << ", "
          << view.pose.position.z << ") yaw " << view.pose.yaw_deg << " pitch "
          << view.pose.pitch_deg;
      crates_far +=
          std::count(r.crates.begin(), r.crates.end(), hit->object) > 0 && hit->distance > kRoom;
    }
  }
  EXPECT_GT(hits, 10000);
  EXPECT_GT(crates_far, 20);  // rays reached crates of other rooms: the portals were tested
}

TEST(PortalTechnique, DrawsEverythingARayFromTheEyeMeets) {
  // A 3 x 3 block of rooms, doors off-centre, one loop.
  Rooms r = make_rooms({{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}, {0, 2}, {1, 2}, {2, 2}},
                       {{0, 0, 1, 0, 0.8f},
                        {1, 0, 2, 0, -0.9f},
                        {0, 0, 0, 1},
                        {1, 0, 1, 1, 1.2f},
                        {0, 1, 1, 1, -0.6f},
                        {1, 1, 2, 1},
                        {2, 1, 2, 2, 0.4f},
                        {1, 1, 1, 2},
                        {0, 2, 1, 2, 1.3f},
                        {2, 0, 2, 1}});
  ASSERT_EQ(validate_scene(r.scene), "");
  expect_conservative(r, "portal");
  expect_conservative(r, "portal-paper");
}

TEST(PortalTechnique, FallsBackToFrustumCullingOutsideTheCells) {
  auto portal = make_technique("portal");
  ASSERT_TRUE(portal);
  const Scene boxes = test::make_box_row(3);
  ASSERT_TRUE(test::load_technique(**portal, boxes));
  EXPECT_NE((*portal)->describe().find("no cells"), std::string::npos);
  DrawList all;
  test::select_view(**portal, view_at({-3.0f, 0.5f, 0.5f}, 0.0f), all);
  EXPECT_EQ(all.triangle_count(), boxes.triangle_count());
  EXPECT_EQ((*portal)->fallback_frames(), 1u);

  Rooms r = make_rooms({{0, 0}, {1, 0}}, {{0, 0, 1, 0}});
  auto fresh = make_technique("portal");
  ASSERT_TRUE(test::load_technique(**fresh, r.scene));
  DrawList list;
  test::select_view(**fresh, view_at({-5.0f, 1.5f, 2.0f}, 0.0f), list);  // outside both rooms
  EXPECT_EQ((*fresh)->fallback_frames(), 1u);
  EXPECT_GT(list.triangle_count(), 0u);
}

TEST(Cells, BadCellsAndPortalsAreNamed) {
  Rooms r = make_rooms({{0, 0}, {1, 0}}, {{0, 0, 1, 0}});
  auto problem_with = [&](auto change) {
    Scene s = r.scene;
    change(s);
    return validate_scene(s);
  };
  EXPECT_NE(problem_with([](Scene& s) { s.portals[0].cells[1] = 7; }).find("names cell 7"),
            std::string::npos);
  EXPECT_NE(problem_with([](Scene& s) { s.portal_points[2].x += 0.5f; }).find("not planar"),
            std::string::npos);
  EXPECT_NE(problem_with([](Scene& s) {  // a dart: its third point pulled in past the diagonal
              s.portal_points[2] = 0.7f * s.portal_points[0] + 0.3f * s.portal_points[2];
            })
                .find("not convex"),
            std::string::npos);
  EXPECT_NE(problem_with([](Scene& s) { s.cell_objects[0] = 999; }).find("names object 999"),
            std::string::npos);
  EXPECT_NE(problem_with([](Scene& s) { s.portals[0].cells[1] = 0; }).find("to itself"),
            std::string::npos);
  // Cells and portals survive the file, and a file whose portal is broken is refused.
  test::TempDir dir;
  ASSERT_TRUE(write_scene(r.scene, dir.file("rooms.ffscene")));
  SceneFileInfo info;
  auto read = read_scene(dir.file("rooms.ffscene"), &info);
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(info.version, 3u);
  EXPECT_EQ(read->cells.size(), 2u);
  EXPECT_EQ(read->portals.size(), 1u);
  EXPECT_EQ(scene_fingerprint(*read), scene_fingerprint(r.scene));
  Scene broken = r.scene;
  broken.portals[0].cells[0] = 5;
  EXPECT_FALSE(write_scene(broken, dir.file("broken.ffscene")));
}

}  // namespace
}  // namespace farfield
