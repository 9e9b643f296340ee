// What every technique promises through the Technique interface, whichever it is.
#include <gtest/gtest.h>

#include "farfield/techniques/technique.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

// select() replaces the whole list: a bird's-eye picture's lines and quads, or another
// technique's uploads, must not leak into the next frame.
TEST(TechniqueContract, SelectClearsEverythingAPreviousFrameLeft) {
  const Scene scene = test::make_box_row(4);
  for (const char* name : {"brute", "octree", "octree-paper", "colorcube"}) {
    auto technique = make_technique(name);
    ASSERT_TRUE(technique) << name;
    ASSERT_TRUE((*technique)->load(scene)) << name;
    DrawList list;
    const uint8_t pixel[3] = {1, 2, 3};
    list.lines.push_back({{0, 0, 0}, {1, 1, 1}, 0xffffffffu});
    list.far_quads.push_back({{}, 0, 1.0f});
    list.uploads.push_back({0, 1, 1, 3, pixel});
    list.quads_in_world = true;
    View view;
    view.pose.position = {-5, 0.5f, 0.5f};
    (*technique)->select(view, {}, list);
    EXPECT_TRUE(list.lines.empty()) << name;
    EXPECT_TRUE(list.far_quads.empty()) << name;
    EXPECT_TRUE(list.uploads.empty()) << name;
    EXPECT_FALSE(list.quads_in_world) << name;
    EXPECT_GT(list.triangle_count(), 0u) << name;
  }
}

}  // namespace
}  // namespace farfield
