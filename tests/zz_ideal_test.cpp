#include <gtest/gtest.h>

#include <cstdio>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <map>

#include "farfield/core/camera_path.hpp"
#include "farfield/core/frustum.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/spatial/occluders.hpp"
#include "farfield/spatial/ray_caster.hpp"
namespace farfield {
TEST(ZZIdeal, WhyNotHidden) {
  auto scene = read_scene("/work/data/big.ffscene");
  auto path = read_camera_path("/work/data/street.json");
  ASSERT_TRUE(scene && path);
  RayCaster caster(*scene);
  Occluders occ(*scene);
  OcclusionMap map;
  for (int f : {0, 150}) {
    View view;
    view.pose = path->frames[f];
    Frustum frustum(view);
    occ.fill(map, view, frustum);
    const glm::mat4 inv = glm::inverse(view.view_projection());
    std::vector<uint8_t> seen(scene->objects.size(), 0);
    const int W = 512, H = 384;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        glm::vec4 p = inv * glm::vec4((x + 0.5f) / W * 2 - 1, (y + 0.5f) / H * 2 - 1, 0.5f, 1.0f);
        glm::vec3 d = glm::normalize(glm::vec3(p) / p.w - view.pose.position);
        auto hit = caster.cast(view.pose.position, d, 1e5f);
        if (hit) seen[hit->object] = 1;
      }
    // Objects in the frustum, not seen, not hidden: why?
    uint64_t tris_unmarked = 0, tris_far = 0, n_unmarked = 0, n_far = 0, tris_near = 0;
    const glm::mat4 vm = view.view_matrix();
    printf("frame %d: marked texels %zu of %d, occluders %u\n", f, map.marked(),
           map.width() * map.height(), map.occluders());
    for (uint32_t o = 0; o < scene->objects.size(); ++o) {
      const Bounds3& b = scene->objects[o].bounds;
      if (seen[o] || frustum.classify(b) == Visibility::none || map.hidden(b)) continue;
      // the rect texels: any unmarked?
      float nearest = 1e30f;
      glm::vec2 lo(1e30f), hi(-1e30f);
      bool behind = false;
      for (int k = 0; k < 8; ++k) {
        glm::vec3 c((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                    (k & 4) ? b.max.z : b.min.z);
        glm::vec4 clip = view.view_projection() * glm::vec4(c, 1);
        glm::vec3 pv = glm::vec3(vm * glm::vec4(c, 1));
        if (-pv.z < 0.1f) behind = true;
        nearest = std::min(nearest, -pv.z);
        glm::vec2 t((clip.x / clip.w * 0.5f + 0.5f) * map.width(),
                    (clip.y / clip.w * 0.5f + 0.5f) * map.height());
        lo = glm::min(lo, t);
        hi = glm::max(hi, t);
      }
      if (behind) {
        tris_near += scene->objects[o].triangle_count();
        continue;
      }
      int x0 = std::max(0, int(lo.x)), x1 = std::min(map.width() - 1, int(hi.x)),
          y0 = std::max(0, int(lo.y)), y1 = std::min(map.height() - 1, int(hi.y));
      int unmarked = 0, far = 0, total = 0;
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          ++total;
          float d = map.depth_at(x, y);
          if (d > 1e29f)
            ++unmarked;
          else if (!(d < nearest))
            ++far;
        }
      if (unmarked) {
        ++n_unmarked;
        tris_unmarked += scene->objects[o].triangle_count();
      } else {
        ++n_far;
        tris_far += scene->objects[o].triangle_count();
      }
    }
    printf(
        "  not seen, not hidden: %llu objects with unmarked texels (%llu tris), %llu only "
        "marked-too-far (%llu tris), crossing near %llu tris\n",
        (unsigned long long)n_unmarked, (unsigned long long)tris_unmarked,
        (unsigned long long)n_far, (unsigned long long)tris_far, (unsigned long long)tris_near);
  }
}
}  // namespace farfield
