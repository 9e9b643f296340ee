// The import convention for cells and portals (docs/techniques/portal.md) on the hand-made
// example tests/data/two_rooms.gltf: a hall and a kitchen joined by a door, a lawn outside
// both; and every broken variant refused with a message naming the node.
#include <gtest/gtest.h>

#include <algorithm>

#include "farfield/scene/import.hpp"
#include "farfield/spatial/portal_walk.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

const std::string kExample = std::string(FARFIELD_SOURCE_DIR) + "/tests/data/two_rooms.gltf";

std::vector<std::string> object_names(const Scene& s, const Cell& c) {
  std::vector<std::string> names;
  for (uint32_t o : s.objects_of(c)) names.emplace_back(s.object_name(s.objects[o]));
  std::sort(names.begin(), names.end());
  return names;
}

TEST(CellImport, NodesNamedByTheConventionBecomeCellsAndPortals) {
  Scene scene;
  ASSERT_TRUE(import_model(kExample, scene));
  EXPECT_EQ(validate_scene(scene), "");
  ASSERT_EQ(scene.cells.size(), 2u);
  EXPECT_EQ(scene.cell_name(scene.cells[0]), "hall");
  EXPECT_EQ(scene.cell_name(scene.cells[1]), "kitchen");
  // The lawn lies in no cell: seen from both. Portal and bound meshes are not drawn.
  EXPECT_EQ(object_names(scene, scene.cells[0]),
            (std::vector<std::string>{"bent sign", "ell sign", "garden/lawn", "hall walls"}));
  EXPECT_EQ(object_names(scene, scene.cells[1]),
            (std::vector<std::string>{"garden/lawn", "kitchen walls", "table"}));
  EXPECT_EQ(scene.objects.size(), 6u);
  // The kitchen's box is its -bound node's; the hall's, its objects'.
  EXPECT_EQ(scene.cells[1].bounds.min, glm::vec3(4, 0, 0));
  EXPECT_EQ(scene.cells[1].bounds.max, glm::vec3(8, 3, 4));
  ASSERT_EQ(scene.portals.size(), 1u);
  const Portal& door = scene.portals[0];
  EXPECT_EQ(door.cells[0], 0u);
  EXPECT_EQ(door.cells[1], 1u);
  // Counter-clockwise seen from the hall: the normal points into it (-X).
  EXPECT_LT(portal_plane(scene.points_of(door))->normal.x, -0.99f);

  // Through the door the kitchen is seen, looking away it is not.
  PortalWalk walk(scene, {});
  std::vector<CellVisit> visits;
  View view;
  view.pose = {{1.0f, 1.0f, 2.0f}, 0.0f, 0.0f};
  walk.walk(view, 0, visits);
  ASSERT_EQ(visits.size(), 2u);
  EXPECT_EQ(visits[1].cell, 1u);
  view.pose.yaw_deg = 180.0f;
  walk.walk(view, 0, visits);
  EXPECT_EQ(visits.size(), 1u);
}

TEST(CellImport, BrokenCellsAndPortalsAreRefusedNamingTheNode) {
  const std::string text = test::read_file(kExample);
  test::TempDir dir;
  auto import_with = [&](const std::string& from, const std::string& to) {
    std::string changed = text;
    const size_t at = changed.find("\"" + from + "\"");
    EXPECT_NE(at, std::string::npos) << from;
    changed.replace(at, from.size() + 2, "\"" + to + "\"");
    test::write_file(dir.file("broken.gltf"), changed);
    Scene scene;
    auto r = import_model(dir.file("broken.gltf"), scene);
    EXPECT_TRUE(scene.objects.empty() && scene.cells.empty());  // nothing half-imported
    return r ? std::string() : r.error().message;
  };
  EXPECT_NE(import_with("kitchen-portal", "cellar-portal").find("names cell 'cellar'"),
            std::string::npos);
  EXPECT_NE(import_with("bent sign", "kitchen-portal").find("is not planar"), std::string::npos);
  EXPECT_NE(import_with("ell sign", "kitchen-portal").find("is not convex"), std::string::npos);
  EXPECT_NE(import_with("garden", "kitchen-portal").find("not inside a cell"), std::string::npos);
  EXPECT_NE(import_with("kitchen-portal", "hall-portal").find("to itself"), std::string::npos);
}

TEST(CellImport, ThePortalTechniqueDrawsTheKitchenThroughTheDoor) {
  Scene scene;
  ASSERT_TRUE(import_model(kExample, scene));
  auto portal = make_technique("portal");
  ASSERT_TRUE(test::load_technique(**portal, scene));
  DrawList list;
  View view;
  view.pose = {{1.0f, 1.0f, 2.0f}, 0.0f, 0.0f};
  test::select_view(**portal, view, list);
  uint32_t table = 0;
  while (table < scene.objects.size() && scene.object_name(scene.objects[table]) != "table")
    ++table;
  ASSERT_LT(table, scene.objects.size());
  bool drawn = false;
  for (const DrawRange& r : list.opaque)
    drawn = drawn || (scene.objects[table].first_index >= r.first_index &&
                      scene.objects[table].first_index < r.first_index + r.index_count);
  EXPECT_TRUE(drawn);
}

}  // namespace
}  // namespace farfield
