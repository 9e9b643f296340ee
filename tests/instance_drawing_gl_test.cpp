// Instances drawn instanced (gpu::InstanceDrawing): the renderer uploads a prototype's geometry
// once and draws each instance from it with its placement; every way of drawing the scene
// gives what the expanded upload gives (translated copies pixel for pixel), in less memory.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include <nlohmann/json.hpp>

#include "farfield/core/assert.hpp"
#include "farfield/gpu/context.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/scene/instances.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using gpu::InstanceDrawing;

// The box row (opaque boxes 0 and 2, glass 1 and 3) and a second row above it: copies of
// boxes 0, 2 and 1, moved up; with `turned`, also a copy of box 0 turned and shrunk.
Scene copied_row(bool turned) {
  Scene s = test::make_box_row(4);
  SceneBuilder b(s);
  const glm::vec3 up(0.0f, 1.5f, 0.0f);
  b.add_instance("lifted 0", ObjectKind::mesh, 0, glm::mat3(1.0f), up);
  b.add_instance("lifted 2", ObjectKind::mesh, 2, glm::mat3(1.0f), up + glm::vec3(0, 0, 0.5f));
  b.add_instance("lifted glass", ObjectKind::mesh, 1, glm::mat3(1.0f), up);
  if (turned) {
    const glm::mat3 turn =
        glm::mat3(glm::rotate(glm::mat4(1.0f), 0.5f, glm::vec3(0, 1, 0))) * 0.6f;
    b.add_instance("turned", ObjectKind::mesh, 0, turn, {6.3f, 1.6f, 0.2f});
  }
  return s;
}

using test::look_at;

// Every object a range, by its material's pass.
DrawList all_objects(const Scene& scene) {
  DrawList list;
  for (const Object& o : scene.objects)
    (scene.materials[o.material].transparent() ? list.transparent : list.opaque)
        .push_back({o.first_index, o.index_count, o.material});
  return list;
}

class InstanceDrawingGL : public ::testing::Test {
 protected:
  void SetUp() override {
    auto context = gpu::create_headless_context();
    if (!context) GTEST_SKIP() << context.error().message;
    context_ = std::move(context).value();
  }
  // A renderer of `scene` drawing its instances each way.
  void make(const Scene& scene, uint64_t chunk_bytes = gpu::kSceneChunkBytes) {
    auto placed = gpu::Renderer::create(scene, chunk_bytes, InstanceDrawing::placed);
    ASSERT_TRUE(placed) << placed.error().message;
    auto expanded = gpu::Renderer::create(scene, chunk_bytes, InstanceDrawing::expanded);
    ASSERT_TRUE(expanded) << expanded.error().message;
    placed_ = std::move(*placed);
    expanded_ = std::move(*expanded);
  }
  Image render(gpu::Renderer& renderer, const View& view, const DrawList& list) {
    renderer.set_offscreen(view.width, view.height);
    renderer.draw(view, list);
    Image image = renderer.capture();
    // FARFIELD_TEST_IMAGES=DIR keeps what the tests rendered, to look at.
    if (const char* dir = std::getenv("FARFIELD_TEST_IMAGES"))
      (void)write_png(image, std::string(dir) + "/" +
                                 ::testing::UnitTest::GetInstance()->current_test_info()->name() +
                                 "_" + std::to_string(saved_++) + ".png");
    return image;
  }
  // Pixels of the two frames that differ.
  static size_t differing(const Image& a, const Image& b) {
    EXPECT_EQ(a.rgb.size(), b.rgb.size());
    size_t n = 0;
    for (size_t i = 0; i < a.rgb.size(); i += 3)
      n += a.rgb[i] != b.rgb[i] || a.rgb[i + 1] != b.rgb[i + 1] || a.rgb[i + 2] != b.rgb[i + 2];
    return n;
  }
  static size_t not_sky(const Image& image) {
    size_t n = 0;
    for (size_t i = 0; i < image.rgb.size(); i += 3)
      n += image.rgb[i] != image.rgb[0] || image.rgb[i + 1] != image.rgb[1] ||
           image.rgb[i + 2] != image.rgb[2];
    return n;
  }

  std::unique_ptr<gpu::Context> context_;  // destroyed last
  std::unique_ptr<gpu::Renderer> placed_, expanded_;
  int saved_ = 0;
  View view_ = look_at({3.5f, 1.8f, -4.5f}, {3.5f, 1.2f, 0.0f});
};

TEST_F(InstanceDrawingGL, TranslatedCopiesDrawPixelForPixelInLessMemory) {
  const Scene scene = copied_row(false);
  make(scene);
  EXPECT_TRUE(placed_->draws_instanced());
  EXPECT_FALSE(expanded_->draws_instanced());
  const StoredGeometry stored = stored_geometry(scene);
  EXPECT_EQ(placed_->scene_geometry_bytes(),
            stored.vertices * sizeof(Vertex) + stored.indices * sizeof(uint32_t));
  EXPECT_EQ(expanded_->scene_geometry_bytes(),
            scene.vertices.size() * sizeof(Vertex) + scene.indices.size() * sizeof(uint32_t));
  const DrawList list = all_objects(scene);
  const Image expanded = render(*expanded_, view_, list);
  EXPECT_GT(not_sky(expanded), size_t(expanded.width * expanded.height / 10));
  EXPECT_EQ(render(*placed_, view_, list).rgb, expanded.rgb);
  // One range over both opaque copies (objects 4 and 5, one material) is split in two
  // commands, as it crosses from one instance to the next.
  DrawList crossing;
  const Object &a = scene.objects[4], &b = scene.objects[5];
  ASSERT_EQ(a.material, b.material);
  crossing.opaque.push_back({a.first_index, a.index_count + b.index_count, a.material});
  EXPECT_EQ(render(*placed_, view_, crossing).rgb, render(*expanded_, view_, crossing).rgb);
  EXPECT_EQ(placed_->draw(view_, crossing).draw_calls, 2u);
  // A faded instance and the raw bound.
  DrawList faded;
  faded.faded.push_back({{a.first_index, a.index_count, a.material}, 0.5f});
  EXPECT_EQ(render(*placed_, view_, faded).rgb, render(*expanded_, view_, faded).rgb);
  placed_->set_offscreen(view_.width, view_.height);
  const gpu::FrameStats raw = placed_->draw_everything_at_once(view_);
  EXPECT_EQ(raw.triangles, scene.triangle_count());
  const Image placed_raw = placed_->capture();
  expanded_->set_offscreen(view_.width, view_.height);
  expanded_->draw_everything_at_once(view_);
  EXPECT_EQ(placed_raw.rgb, expanded_->capture().rgb);
}

TEST_F(InstanceDrawingGL, TurnedCopiesDrawAsTheHeldGeometry) {
  const Scene scene = copied_row(true);
  make(scene);
  const DrawList list = all_objects(scene);
  const Image placed = render(*placed_, view_, list);
  const Image expanded = render(*expanded_, view_, list);
  // The placement is computed on the GPU, the held copy on the CPU: edges may round apart.
  EXPECT_LE(differing(placed, expanded), size_t(placed.width * placed.height / 200));
  DrawList turned;  // the turned copy alone is drawn
  const Object& t = scene.objects.back();
  turned.opaque.push_back({t.first_index, t.index_count, t.material});
  const Image alone = render(*placed_, view_, turned);
  EXPECT_GT(not_sky(alone), 20u);
  EXPECT_LE(differing(alone, render(*expanded_, view_, turned)), 4u);
}

TEST_F(InstanceDrawingGL, VisibleTrianglesAndPicksNameTheHeldTriangles) {
  const Scene scene = copied_row(true);
  make(scene);
  const DrawList list = all_objects(scene);
  placed_->set_offscreen(view_.width, view_.height);
  expanded_->set_offscreen(view_.width, view_.height);
  const std::vector<uint32_t> placed = placed_->visible_triangles(view_, list);
  const std::vector<uint32_t> expanded = expanded_->visible_triangles(view_, list);
  // Instances' triangles are numbered as held: some are visible, and the sets agree but
  // for what a rounding at an edge can change.
  const uint64_t first_instance_triangle = scene.objects[4].first_index / 3;
  EXPECT_TRUE(std::any_of(placed.begin(), placed.end(),
                          [&](uint32_t t) { return t >= first_instance_triangle; }));
  size_t common = 0;
  for (uint32_t t : placed) common += std::binary_search(expanded.begin(), expanded.end(), t);
  EXPECT_GE(common + 2, std::max(placed.size(), expanded.size()));
  // The middle of the lifted copy of box 0 (x 0..1, y 1.5..2.5, its face at z 0).
  const glm::vec4 clip = view_.view_projection() * glm::vec4(0.5f, 2.0f, 0.0f, 1.0f);
  const int x = int((clip.x / clip.w * 0.5f + 0.5f) * float(view_.width));
  const int y = int((0.5f - clip.y / clip.w * 0.5f) * float(view_.height));
  const auto picked = placed_->pick(scene, view_, list, x, y);
  ASSERT_TRUE(picked);
  EXPECT_EQ(object_of_triangle(scene, *picked), 4u);
}

TEST_F(InstanceDrawingGL, IndexedRunsOverInstancesDrawAsTheirRanges) {
  const Scene scene = copied_row(false);
  make(scene);
  // The opaque objects' triangles gathered into the list's own indices (as hybrid's visible
  // sets are), one run of the one material, across copies and the objects they copy.
  DrawList gathered, ranges;
  uint32_t material = scene.objects[0].material;
  for (uint32_t i : {0u, 4u, 2u, 5u}) {
    const Object& o = scene.objects[i];
    ASSERT_EQ(o.material, material);
    ranges.opaque.push_back({o.first_index, o.index_count, o.material});
    for (uint32_t k = o.first_index; k < o.first_index + o.index_count; ++k) {
      gathered.scene_indices.push_back(scene.indices[k]);
      if (k % 3 == 0) gathered.scene_triangles.push_back(k / 3);
    }
  }
  gathered.indexed_opaque.push_back({0, uint32_t(gathered.scene_indices.size()), material});
  const Image expected = render(*expanded_, view_, ranges);
  EXPECT_EQ(render(*placed_, view_, gathered).rgb, expected.rgb);
  EXPECT_EQ(render(*expanded_, view_, gathered).rgb, expected.rgb);
  EXPECT_EQ(placed_->draw(view_, gathered).draw_calls, 4u);  // split at each instance
}

TEST_F(InstanceDrawingGL, ChunkedScenesMeshesAndTexturesToo) {
  // One box a chunk: an instance's draws read its prototype's chunk.
  const Scene scene = copied_row(false);
  make(scene, 500);
  const DrawList list = all_objects(scene);
  EXPECT_EQ(render(*placed_, view_, list).rgb, render(*expanded_, view_, list).rgb);
  // A scene mesh (as the LODs are) in a placed scene is drawn where it is.
  const Object& o = scene.objects[2];
  std::vector<Vertex> vertices(scene.vertices.begin() + o.first_vertex,
                               scene.vertices.begin() + o.first_vertex + o.vertex_count);
  std::vector<uint32_t> indices;
  for (uint32_t k = o.first_index; k < o.first_index + o.index_count; ++k)
    indices.push_back(scene.indices[k] - o.first_vertex);
  Image mesh_frames[2];
  int k = 0;
  for (gpu::Renderer* r : {placed_.get(), expanded_.get()}) {
    auto mesh = r->create_scene_mesh(vertices, {}, indices);
    ASSERT_TRUE(mesh) << mesh.error().message;
    DrawList with_mesh;
    with_mesh.opaque = {{0, uint32_t(indices.size()), o.material, *mesh}};
    mesh_frames[k] = render(*r, view_, with_mesh);
    EXPECT_GT(not_sky(mesh_frames[k++]), 20u);
  }
  EXPECT_EQ(mesh_frames[0].rgb, mesh_frames[1].rgb);

  // A textured quad and a copy of it, moved.
  Scene textured = test::make_textured_scene();
  SceneBuilder b(textured);
  b.add_instance("quad copy", ObjectKind::mesh, uint32_t(textured.objects.size() - 1),
                 glm::mat3(1.0f), {2.5f, 0.0f, 0.0f});
  make(textured);
  EXPECT_TRUE(placed_->draws_instanced());
  const View behind = look_at({1.25f, 1.0f, 7.0f}, {1.25f, 1.0f, 3.0f});  // the quads face +z
  const DrawList both = all_objects(textured);
  const Image placed = render(*placed_, behind, both);
  EXPECT_EQ(placed.rgb, render(*expanded_, behind, both).rgb);
  DrawList copy_only;
  const Object& copy = textured.objects.back();
  copy_only.opaque.push_back({copy.first_index, copy.index_count, copy.material});
  const Image copied = render(*placed_, behind, copy_only);
  EXPECT_GT(not_sky(copied), size_t(copied.width * copied.height / 20));
  // The checker shows: both of its colours are there.
  size_t dark = 0, light = 0;
  for (size_t i = 0; i < copied.rgb.size(); i += 3) {
    dark += copied.rgb[i] < 40 && copied.rgb[i + 1] < 40;
    light += copied.rgb[i] > 150 && copied.rgb[i + 1] > 150 && copied.rgb[i + 2] > 150;
  }
  EXPECT_GT(dark, 50u);
  EXPECT_GT(light, 50u);
}

// A scene mesh holding a prototype's geometry, its range naming an instance (DrawRange::
// instance, as a clusters level stored once): drawn as the copy's own range is, however the
// scene was uploaded.
TEST_F(InstanceDrawingGL, AMeshRangeNamingAnInstanceDrawsTheCopy) {
  const Scene scene = copied_row(true);
  make(scene);
  const uint32_t k = uint32_t(scene.instances.size() - 1);  // the turned and shrunk copy
  const Object& copy = scene.objects[scene.instances[k].object];
  const Object& prototype = scene.objects[scene.instances[k].prototype];
  std::vector<Vertex> vertices(scene.vertices.begin() + prototype.first_vertex,
                               scene.vertices.begin() + prototype.first_vertex +
                                   prototype.vertex_count);
  std::vector<uint32_t> indices;
  for (uint32_t i = prototype.first_index; i < prototype.first_index + prototype.index_count; ++i)
    indices.push_back(scene.indices[i] - prototype.first_vertex);
  DrawList own;
  own.opaque.push_back({copy.first_index, copy.index_count, copy.material});
  for (gpu::Renderer* r : {placed_.get(), expanded_.get()}) {
    auto mesh = r->create_scene_mesh(vertices, {}, indices);
    ASSERT_TRUE(mesh) << mesh.error().message;
    DrawList placed, unplaced, faded;
    placed.opaque.push_back({0, uint32_t(indices.size()), copy.material, *mesh, k});
    unplaced.opaque.push_back({0, uint32_t(indices.size()), copy.material, *mesh});
    faded.faded.push_back({placed.opaque[0], 1.0f});
    const Image expected = render(*r, view_, own);
    const Image drawn = render(*r, view_, placed);
    EXPECT_GT(not_sky(drawn), 20u);
    EXPECT_LE(differing(drawn, expected), 4u);
    EXPECT_LE(differing(render(*r, view_, faded), expected), 4u);
    // Not placed, the prototype's geometry is drawn where the prototype is.
    EXPECT_GT(differing(render(*r, view_, unplaced), expected), 20u);
  }
}

// A prototype's mesh range for several of its instances, the ranges side by side: one
// instanced command (records made for the frame) that draws what the copies' own ranges do;
// textured copies too.
TEST_F(InstanceDrawingGL, CopiesOfOneMeshRangeAreOneInstancedCommand) {
  // Held geometry of `object` as a scene mesh of `r`, drawn for `instances`.
  auto copies_of = [](const Scene& scene, gpu::Renderer& r, uint32_t object,
                      std::initializer_list<uint32_t> instances) {
    const Object& o = scene.objects[object];
    std::vector<Vertex> vertices(scene.vertices.begin() + o.first_vertex,
                                 scene.vertices.begin() + o.first_vertex + o.vertex_count);
    std::vector<glm::vec2> uvs;
    if (!scene.uvs.empty())
      uvs.assign(scene.uvs.begin() + o.first_uv, scene.uvs.begin() + o.first_uv + o.vertex_count);
    std::vector<uint32_t> indices;
    for (uint32_t i = o.first_index; i < o.first_index + o.index_count; ++i)
      indices.push_back(scene.indices[i] - o.first_vertex);
    auto mesh = r.create_scene_mesh(vertices, uvs, indices);
    FF_ASSERT(mesh.ok(), "mesh");
    DrawList list;
    for (uint32_t k : instances)
      list.opaque.push_back({0, uint32_t(indices.size()), o.material, *mesh, k});
    return list;
  };
  auto own_ranges = [](const Scene& scene, std::initializer_list<uint32_t> instances) {
    DrawList list;
    for (uint32_t k : instances) {
      const Object& o = scene.objects[scene.instances[k].object];
      list.opaque.push_back({o.first_index, o.index_count, o.material});
    }
    return list;
  };
  // Instances 0 ("lifted 0", moved) and 3 ("turned"), both of object 0.
  const Scene scene = copied_row(true);
  make(scene);
  ASSERT_EQ(scene.instances[0].prototype, scene.instances[3].prototype);
  for (gpu::Renderer* r : {placed_.get(), expanded_.get()}) {
    const DrawList both = copies_of(scene, *r, scene.instances[0].prototype, {0, 3});
    r->set_offscreen(view_.width, view_.height);
    EXPECT_EQ(r->draw(view_, both).draw_calls, 1u);
    const Image drawn = render(*r, view_, both);
    EXPECT_GT(not_sky(drawn), 100u);
    EXPECT_LE(differing(drawn, render(*r, view_, own_ranges(scene, {0, 3}))), 4u);
  }

  // A textured quad and two moved copies: exact.
  Scene textured = test::make_textured_scene();
  const uint32_t quad = uint32_t(textured.objects.size() - 1);
  SceneBuilder b(textured);
  b.add_instance("quad copy", ObjectKind::mesh, quad, glm::mat3(1.0f), {2.5f, 0.0f, 0.0f});
  b.add_instance("quad copy 2", ObjectKind::mesh, quad, glm::mat3(1.0f), {-2.5f, 0.0f, 0.0f});
  make(textured);
  const View behind = look_at({0.5f, 1.0f, 9.0f}, {0.5f, 1.0f, 3.0f});
  const DrawList pair = copies_of(textured, *placed_, quad, {0, 1});
  placed_->set_offscreen(behind.width, behind.height);
  EXPECT_EQ(placed_->draw(behind, pair).draw_calls, 1u);
  const Image drawn = render(*placed_, behind, pair);
  EXPECT_GT(not_sky(drawn), size_t(drawn.width * drawn.height / 20));
  EXPECT_EQ(drawn.rgb, render(*placed_, behind, own_ranges(textured, {0, 1})).rgb);
}

TEST(InstanceDrawingCli, BenchReportsTheGeometryItUploads) {
  if (auto context = gpu::create_headless_context(); !context)
    GTEST_SKIP() << context.error().message;
  test::TempDir dir;
  const std::string tree = dir.file("tree.ffscene"), field = dir.file("field.ffscene");
  ASSERT_EQ(test::run_farfield("generate tree --iterations 3 -q --out " + tree).exit_status, 0);
  ASSERT_EQ(test::run_farfield("generate field --mesh " + tree + " --count 4 -q --out " + field)
                .exit_status,
            0);
  ASSERT_EQ(test::run_farfield("path " + field + " --kind orbit --frames 3 --out " +
                               dir.file("orbit.json"))
                .exit_status,
            0);
  uint64_t bytes[2] = {0, 0};
  for (int expand = 0; expand < 2; ++expand) {
    const std::string out = dir.file(expand ? "expanded" : "placed");
    const auto r = test::run_farfield("bench " + field + " --path " + dir.file("orbit.json") +
                                      " --technique brute --width 64 --height 48 --no-plot" +
                                      (expand ? " --expand-instances" : "") + " --out " + out);
    ASSERT_EQ(r.exit_status, 0) << r.output;
    const auto json = nlohmann::json::parse(test::read_file(out + "/bench.json"));
    EXPECT_EQ(json["scene"]["instances_placed"], expand ? 0 : 3) << r.output;
    bytes[expand] = json["scene"]["geometry_gpu_bytes"];
  }
  // Four copies of one tree: a quarter of the geometry uploaded.
  EXPECT_EQ(bytes[0] * 4, bytes[1]);
}

}  // namespace
}  // namespace farfield
