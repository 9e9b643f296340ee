// Accuracy tables (paper 001, Sec. 3.2): the directions, image errors that order the
// representations as their images do, and the pack that keeps them.
#include "farfield/techniques/clusters/accuracy_table.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "farfield/core/assert.hpp"
#include "farfield/core/image_similarity.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/city_generator.hpp"
#include "farfield/scene/instances.hpp"
#include "farfield/store/blob_array.hpp"
#include "farfield/techniques/clusters/box_atlas.hpp"
#include "farfield/store/store.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

TEST(AccuracyTable, DirectionsSpreadOverTheSphere) {
  for (int count : {1, 5, 16, 64}) {
    const std::vector<glm::vec3> d = sphere_directions(count);
    ASSERT_EQ(d.size(), size_t(count));
    glm::vec3 sum(0.0f);
    for (const glm::vec3& v : d) {
      EXPECT_NEAR(glm::length(v), 1.0f, 1e-5f);
      sum += v;
    }
    if (count >= 16) {
      EXPECT_LT(glm::length(sum) / float(count), 0.05f);
    }
    // Every point of the sphere has a direction within the angle a cap of 4 pi / count spans
    // (twice over, for the lattice's unevenness).
    AccuracyTable t;
    t.directions = d;
    const float cap = 2.0f * std::acos(1.0f - 2.0f / float(count));
    for (const glm::vec3& probe : sphere_directions(997)) {
      const float angle = std::acos(std::clamp(glm::dot(d[t.nearest(probe)], probe), -1.0f, 1.0f));
      EXPECT_LE(angle, std::max(cap, 0.2f)) << count;
    }
  }
}

TEST(ImageSimilarity, AMaskLeavesTheSharedBackgroundOut) {
  Image a(64, 64), b(64, 64);
  std::vector<uint8_t> mask(64 * 64, 0);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const bool in = x >= 24 && x < 40 && y >= 24 && y < 40;
      std::fill_n(a.pixel(x, y), 3, uint8_t(in ? ((x + y) % 2 ? 250 : 10) : 128));
      std::fill_n(b.pixel(x, y), 3, uint8_t(in ? 130 : 128));
      mask[size_t(y) * 64 + size_t(x)] = in;
    }
  const double whole = structural_similarity(a, b), masked = structural_similarity(a, b, mask);
  EXPECT_LT(masked, whole);  // the background's windows agree and raise the whole's
  EXPECT_LT(masked, 0.2);
  EXPECT_EQ(structural_similarity(a, a, mask), 1.0);
  EXPECT_EQ(structural_similarity(a, b, std::vector<uint8_t>(64 * 64, 0)), 1.0);
}

// A city of 2 x 2 blocks with its levels, hierarchy, boxes and tables, made once.
struct Baked {
  Scene scene;
  LodSet lods;
  ClusterTree tree;
  BoxSet boxes;
  AccuracyTable table;
  std::string skip;
};
const Baked& baked() {
  static const Baked b = [] {
    Baked out;
    auto context = gpu::create_headless_context();
    if (!context) {
      out.skip = context.error().message;
      return out;
    }
    Progress quiet(true);
    CityOptions o;
    o.blocks_x = o.blocks_z = 2;
    auto scene = generate_city(o, quiet);
    FF_ASSERT(scene.ok(), "city");
    out.scene = std::move(*scene);
    auto lods = build_lod_set(out.scene, {}, quiet);
    FF_ASSERT(lods.ok(), "lods");
    out.lods = std::move(*lods);
    ClusterTreeOptions t;
    t.leaf_objects = 6;
    auto tree = build_cluster_tree(out.scene, t, quiet);
    FF_ASSERT(tree.ok(), "tree");
    out.tree = std::move(*tree);
    auto renderer = gpu::Renderer::create(out.scene);
    FF_ASSERT(renderer.ok(), "renderer");
    BoxSetOptions bo;
    bo.max_texels = 4e6;
    bo.clusters = true;
    auto boxes = bake_box_set(out.scene, out.tree, **renderer, bo, quiet);
    FF_ASSERT(boxes.ok(), "boxes");
    out.boxes = std::move(*boxes);
    AccuracyOptions ao;
    ao.directions = 8;
    auto table =
        bake_accuracy_table(out.scene, out.lods, out.tree, out.boxes, **renderer, ao, quiet);
    FF_ASSERT(table.ok(), "%s", table ? "" : table.error().message.c_str());
    out.table = std::move(*table);
    return out;
  }();
  return b;
}

// Errors are finite, within a representation's size, never smaller along a chain; coarser
// levels of the city's buildings (which lose their windows) are worse by image than by
// geometry; a box's image error is not its depth error.
TEST(AccuracyTableGL, ErrorsGrowAlongChainsAndSeeWhatGeometryMisses) {
  const Baked& b = baked();
  if (!b.skip.empty()) GTEST_SKIP() << b.skip;
  const AccuracyTable& t = b.table;
  const size_t k_count = t.directions.size();
  ASSERT_EQ(k_count, 8u);
  ASSERT_EQ(t.lod_error.size(), b.lods.lods.size() * k_count);
  int image_worse = 0, chains = 0;
  for (uint32_t o = 0; o < b.scene.objects.size(); ++o) {
    const uint32_t begin = b.lods.first_lod[o], end = b.lods.first_lod[o + 1];
    const float size = glm::length(b.scene.objects[o].bounds.size());
    for (uint32_t l = begin; l < end; ++l)
      for (uint32_t k = 0; k < k_count; ++k) {
        EXPECT_GE(t.lod(l, k), 0.0f);
        EXPECT_LE(t.lod(l, k), size * 1.001f);
        if (l > begin) {
          EXPECT_GE(t.lod(l, k), t.lod(l - 1, k));
        }
      }
    if (end > begin && b.scene.objects[o].kind == ObjectKind::building) {
      ++chains;
      float image = 0;
      for (uint32_t k = 0; k < k_count; ++k) image = std::max(image, t.lod(end - 1, k));
      image_worse += image > b.lods.lods[end - 1].error_m;
    }
  }
  ASSERT_GT(chains, 5);
  EXPECT_GT(image_worse, chains / 2);
  int differs = 0;
  for (uint32_t box = 0; box < b.boxes.boxes.size(); ++box)
    differs += t.box(box, 0) != b.boxes.boxes[box].error_m;
  EXPECT_GT(differs, int(b.boxes.boxes.size()) / 2);
}

// A level that fails at the finest comparison takes the texel where its similarity crosses
// the threshold, between the failing and the passing level's: its errors are not the powers
// of two of the finest texel that the passing level's texel alone would give.
TEST(AccuracyTableGL, ErrorsLieWhereTheSimilarityCrossesTheThreshold) {
  const Baked& b = baked();
  if (!b.skip.empty()) GTEST_SKIP() << b.skip;
  const AccuracyTable& t = b.table;
  const AccuracyOptions defaults;
  const size_t k_count = t.directions.size();
  int between = 0, powers = 0;
  for (uint32_t o = 0; o < b.scene.objects.size(); ++o) {
    const float size = glm::length(b.scene.objects[o].bounds.size());
    const float texel = size / float(defaults.resolution_px);
    for (uint32_t l = b.lods.first_lod[o]; l < b.lods.first_lod[o + 1]; ++l)
      for (uint32_t k = 0; k < k_count; ++k) {
        const float e = t.lod(l, k);
        if (e <= texel * 1.001f || e >= size * 0.999f) continue;
        ++between;
        const float steps = std::log2(e / texel);
        powers += std::abs(steps - std::round(steps)) < 1e-3f;
      }
  }
  ASSERT_GT(between, 20);
  EXPECT_LT(powers, between / 4) << powers << " of " << between << " errors are powers of two";
}

// `lods` with every instance's levels made geometry of their own (its prototype's, moved), on
// one page after the others: the set as it was before instances' levels were stored once.
LodSet with_copies_apart(const Scene& scene, LodSet lods) {
  const MeshPage page{uint32_t(lods.vertices.size()), 0, uint32_t(lods.indices.size()), 0};
  for (const Instance& instance : scene.instances) {
    const InstanceTransform move(instance);
    for (uint32_t l = lods.first_lod[instance.object]; l < lods.first_lod[instance.object + 1];
         ++l) {
      Lod& lod = lods.lods[l];
      const auto first = lods.indices.begin() + lod.first_index;
      const auto [low, high] = std::minmax_element(first, first + lod.index_count);
      const uint32_t from = *low, to = *high + 1, base = uint32_t(lods.vertices.size());
      const uint32_t at = uint32_t(lods.indices.size());
      for (uint32_t v = from; v < to; ++v) {
        lods.vertices.push_back(move(lods.vertices[v]));
        if (!lods.uvs.empty()) lods.uvs.push_back(lods.uvs[v]);
      }
      for (uint32_t i = lod.first_index; i < lod.first_index + lod.index_count; ++i)
        lods.indices.push_back(lods.indices[i] - from + base);
      lod.first_index = at;
      lods.lod_page[l] = uint32_t(lods.pages.size());
    }
  }
  lods.pages.push_back({page.first_vertex, uint32_t(lods.vertices.size()) - page.first_vertex,
                        page.first_index, uint32_t(lods.indices.size()) - page.first_index});
  lods.object_instance.clear();
  return lods;
}

// A city block's largest building and two copies of it (Scene::instances), one moved and one
// turned, baked as the clusters bake does (hierarchy, boxes, tables; the levels made once)
// twice: as it is, and with the copies plain objects of their own. The moved copy is not rendered again: its
// box and its errors are its prototype's, and they are what rendering it gives (sides of the
// same size, texels and errors alike); the turned one is rendered.
TEST(AccuracyTableGL, AMovedCopyTakesItsPrototypesBoxAndErrors) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  Progress quiet(true);
  CityOptions o;
  o.blocks_x = o.blocks_z = 1;
  auto city = generate_city(o, quiet);
  ASSERT_TRUE(city) << city.error().message;
  Scene scene = std::move(*city);
  uint32_t prototype = 0;
  for (uint32_t i = 1; i < scene.objects.size(); ++i)
    if (scene.objects[i].kind == ObjectKind::building &&
        !scene.materials[scene.objects[i].material].transparent() &&
        scene.objects[i].index_count > scene.objects[prototype].index_count)
      prototype = i;
  SceneBuilder builder(scene);
  const uint32_t moved =
      builder.add_instance("moved", ObjectKind::building, prototype, glm::mat3(1.0f), {300, 0, 7});
  const uint32_t turned = builder.add_instance(
      "turned", ObjectKind::building, prototype,
      glm::mat3(glm::rotate(glm::mat4(1.0f), 0.5f, glm::vec3(0, 1, 0))), {-300, 0, 0});
  struct Bake {
    LodSet lods;
    BoxSet boxes;
    AccuracyTable table;
  };
  // The levels made once, from the scene with its copies (a copy simplified on its own may
  // come out another mesh, and the tables compare their images); the plain scene's copies
  // hold them moved.
  auto lods = build_lod_set(scene, {}, quiet);
  ASSERT_TRUE(lods) << lods.error().message;
  auto bake = [&](const Scene& s) {
    Bake b;
    b.lods = s.instances.empty() ? with_copies_apart(scene, *lods) : *lods;
    auto tree = build_cluster_tree(s, {}, quiet);
    FF_ASSERT(tree.ok(), "tree");
    auto renderer = gpu::Renderer::create(s);
    FF_ASSERT(renderer.ok(), "renderer");
    BoxSetOptions bo;
    bo.min_triangles = 1;
    auto boxes = bake_box_set(s, *tree, **renderer, bo, quiet);
    FF_ASSERT(boxes.ok(), "boxes");
    b.boxes = std::move(*boxes);
    AccuracyOptions ao;
    ao.directions = 8;
    auto table = bake_accuracy_table(s, b.lods, *tree, b.boxes, **renderer, ao, quiet);
    FF_ASSERT(table.ok(), "table");
    b.table = std::move(*table);
    return b;
  };
  const Bake shared = bake(scene);
  Scene plain = scene;
  plain.instances.clear();  // the copies' geometry is held: plain objects of their own
  const Bake rendered = bake(plain);

  const size_t k_count = 8;
  for (const Bake* b : {&shared, &rendered})
    for (uint32_t object : {prototype, moved, turned})
      ASSERT_NE(b->boxes.object_box[object], BoxSet::kNone) << object;
  auto box_of = [](const Bake& b, uint32_t object) { return b.boxes.object_box[object]; };
  // Copied: the prototype's sides and texels, its errors, direction by direction.
  const TexturedBox& ours = shared.boxes.boxes[box_of(shared, moved)];
  const TexturedBox& theirs = shared.boxes.boxes[box_of(shared, prototype)];
  EXPECT_FLOAT_EQ(ours.error_m, theirs.error_m);
  // ... held once in the atlas, and in its tiles when the boxes stream.
  EXPECT_EQ(ours.page, theirs.page);
  uint64_t copy_texels = 0;
  for (int side = 0; side < 6; ++side) {
    EXPECT_EQ(ours.sides[side].x, theirs.sides[side].x);
    EXPECT_EQ(ours.sides[side].y, theirs.sides[side].y);
    copy_texels += uint64_t(ours.sides[side].w) * ours.sides[side].h;
  }
  EXPECT_EQ(shared.boxes.texels() + copy_texels, rendered.boxes.texels());
  const BoxTiling tiling = tile_boxes(shared.boxes, 128);
  ASSERT_FALSE(tiling.whole_pages);
  const TexturedBox& tiled = tiling.tiles.boxes[box_of(shared, moved)];
  const TexturedBox& tiled_prototype = tiling.tiles.boxes[box_of(shared, prototype)];
  EXPECT_EQ(tiled.page, tiled_prototype.page);
  for (int side = 0; side < 6; ++side) {
    EXPECT_EQ(tiled.sides[side].x, tiled_prototype.sides[side].x);
    EXPECT_EQ(tiled.sides[side].y, tiled_prototype.sides[side].y);
  }
  const uint32_t levels = shared.lods.first_lod[prototype + 1] - shared.lods.first_lod[prototype];
  ASSERT_GT(levels, 0u);
  for (size_t k = 0; k < k_count; ++k) {
    EXPECT_EQ(shared.table.box(box_of(shared, moved), k),
              shared.table.box(box_of(shared, prototype), k));
    for (uint32_t l = 0; l < levels; ++l)
      EXPECT_EQ(shared.table.lod(shared.lods.first_lod[moved] + l, k),
                shared.table.lod(shared.lods.first_lod[prototype] + l, k));
  }
  // What rendering the copy gives instead.
  const TexturedBox& drawn = rendered.boxes.boxes[box_of(rendered, moved)];
  EXPECT_NEAR(ours.error_m, drawn.error_m, 0.02f * drawn.error_m + 0.05f);
  uint64_t texels = 0, apart = 0;
  for (int side = 0; side < 6; ++side) {
    const BoxSide &a = ours.sides[side], &b = drawn.sides[side];
    ASSERT_EQ(a.w, b.w);
    ASSERT_EQ(a.h, b.h);
    for (int y = 0; y < a.h; ++y)
      for (int x = 0; x < a.w; ++x)
        for (int c = 0; c < 4; ++c) {
          const auto texel = [&](const BoxSet& set, const TexturedBox& box, const BoxSide& s) {
            return int(set.pages[box.page][(size_t(s.y + y) * set.page_px + s.x + x) * 4 + c]);
          };
          apart += std::abs(texel(shared.boxes, ours, a) - texel(rendered.boxes, drawn, b)) > 8;
          ++texels;
        }
  }
  ASSERT_GT(texels, 1000u);
  EXPECT_LT(double(apart), 0.001 * double(texels));
  for (size_t k = 0; k < k_count; ++k) {
    const float size = glm::length(scene.objects[moved].bounds.size()) / 64.0f;  // a texel
    EXPECT_NEAR(shared.table.box(box_of(shared, moved), k),
                rendered.table.box(box_of(rendered, moved), k), size);
    for (uint32_t l = 0; l < levels; ++l)
      EXPECT_NEAR(shared.table.lod(shared.lods.first_lod[moved] + l, k),
                  rendered.table.lod(rendered.lods.first_lod[moved] + l, k), size);
  }
  // The turned copy's box is its own: wider than its prototype's, seen along X.
  EXPECT_NE(shared.boxes.boxes[box_of(shared, turned)].sides[4].w, theirs.sides[4].w);
}

TEST(AccuracyTableGL, KeptInAPackAndRefusedWhenDamaged) {
  const Baked& b = baked();
  if (!b.skip.empty()) GTEST_SKIP() << b.skip;
  test::TempDir dir;
  auto store = Store::open(dir.file("table.ffpack"), Store::Mode::kReadWrite);
  ASSERT_TRUE(store);
  auto none = load_accuracy_table(*store, b.lods, b.tree, b.boxes);
  ASSERT_TRUE(none) << none.error().message;
  EXPECT_TRUE(none->empty());
  ASSERT_TRUE(save_accuracy_table(b.table, *store));
  auto back = load_accuracy_table(*store, b.lods, b.tree, b.boxes);
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(back->lod_error, b.table.lod_error);
  EXPECT_EQ(back->box_error, b.table.box_error);
  EXPECT_EQ(back->node_error, b.table.node_error);

  std::vector<float> short_errors(b.table.lod_error.begin(), b.table.lod_error.end() - 1);
  ASSERT_TRUE(store->put("clusters/accuracy_lods", bytes_of(short_errors)));
  auto refused = load_accuracy_table(*store, b.lods, b.tree, b.boxes);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("one error per representation"), std::string::npos);
  std::vector<float> bad = b.table.lod_error;
  bad[0] = NAN;
  ASSERT_TRUE(store->put("clusters/accuracy_lods", bytes_of(bad)));
  refused = load_accuracy_table(*store, b.lods, b.tree, b.boxes);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("not finite"), std::string::npos);
}

}  // namespace
}  // namespace farfield
