// GL tests: headless through EGL (llvmpipe here); skipped where no context can be made.
#include "farfield/gpu/renderer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <memory>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/gpu/context.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using Rgb = std::array<int, 3>;

using test::look_at;

// The pixel (rows from the top) where `p` lands.
glm::ivec2 pixel_of(const View& view, const glm::vec3& p) {
  const glm::vec4 clip = view.view_projection() * glm::vec4(p, 1.0f);
  const float x = (clip.x / clip.w * 0.5f + 0.5f) * float(view.width);
  const float y = (0.5f - clip.y / clip.w * 0.5f) * float(view.height);
  return {int(x), int(y)};
}

Rgb at(const Image& image, glm::ivec2 p) {
  const uint8_t* q = image.pixel(p.x, p.y);
  return {q[0], q[1], q[2]};
}

// The given objects of a scene, split by their material as a technique would.
DrawList list_of(const Scene& scene, std::initializer_list<int> objects) {
  DrawList list;
  for (int i : objects) {
    const Object& o = scene.objects[size_t(i)];
    (scene.materials[o.material].transparent() ? list.transparent : list.opaque)
        .push_back({o.first_index, o.index_count, o.material});
  }
  return list;
}

// Centre of the face of box `i` (make_box_row) facing -Z, towards the front view's eye.
glm::vec3 front_face(int i) {
  return {2.0f * float(i) + 0.5f, 0.5f, 0.0f};
}

class RendererGL : public ::testing::Test {
 protected:
  void SetUp() override {
    auto context = gpu::create_headless_context();
    if (!context) GTEST_SKIP() << context.error().message;
    context_ = std::move(context).value();
    auto renderer = gpu::Renderer::create(scene_);
    ASSERT_TRUE(renderer) << renderer.error().message;
    renderer_ = std::move(renderer).value();
    front_ = look_at({3.5f, 0.5f, -5.0f}, {3.5f, 0.5f, 0.0f});
    sky_ = render(front_, DrawList{});
  }

  Image render(const View& view, const DrawList& list, gpu::Renderer* renderer = nullptr) {
    if (!renderer) renderer = renderer_.get();
    renderer->set_offscreen(view.width, view.height);
    renderer->draw(view, list);
    Image image = renderer->capture();
    // FARFIELD_TEST_IMAGES=DIR keeps what the tests rendered, to look at.
    if (const char* dir = std::getenv("FARFIELD_TEST_IMAGES"))
      (void)write_png(image, std::string(dir) + "/" +
                                 ::testing::UnitTest::GetInstance()->current_test_info()->name() +
                                 "_" + std::to_string(saved_++) + ".png");
    return image;
  }
  Rgb sky() const { return at(sky_, {0, 0}); }

  std::unique_ptr<gpu::Context> context_;  // destroyed last
  Scene scene_ = test::make_box_row(4);    // opaque red boxes 0 and 2, glass boxes 1 and 3
  std::unique_ptr<gpu::Renderer> renderer_;
  View front_;
  Image sky_;
  int saved_ = 0;
};

TEST(SceneChunks, WholeObjectsUpToTheLimitAndTooLargeOnesRefused) {
  const Scene scene = test::make_box_row(5);
  const uint64_t box = std::max<uint64_t>(scene.objects[0].vertex_count * sizeof(Vertex),
                                          scene.objects[0].index_count * sizeof(uint32_t));
  auto one = gpu::plan_scene_chunks(scene, uint64_t(1) << 30);
  ASSERT_TRUE(one);
  ASSERT_EQ(one->size(), 1u);
  EXPECT_EQ((*one)[0].index_count, scene.indices.size());
  EXPECT_EQ((*one)[0].vertex_count, scene.vertices.size());
  auto pairs = gpu::plan_scene_chunks(scene, 2 * box);
  ASSERT_TRUE(pairs);
  ASSERT_EQ(pairs->size(), 3u);  // 2 + 2 + 1 boxes
  uint32_t next = 0;
  for (const gpu::SceneChunk& c : *pairs) {
    EXPECT_EQ(c.first_index, next);
    next += c.index_count;
    EXPECT_LE(c.vertex_count * sizeof(Vertex), 2 * box);
  }
  EXPECT_EQ(next, scene.indices.size());
  EXPECT_EQ(gpu::chunk_of(*pairs, 0), 0u);
  EXPECT_EQ(gpu::chunk_of(*pairs, (*pairs)[1].first_index), 1u);
  EXPECT_EQ(gpu::chunk_of(*pairs, (*pairs)[2].first_index + 3), 2u);
  auto refused = gpu::plan_scene_chunks(scene, box - 1);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("object 0"), std::string::npos) << refused.error().message;
}

TEST(ContextGL, ReportsRendererAndVersion) {
  auto context = gpu::create_headless_context();
  if (!context) GTEST_SKIP() << context.error().message;
  EXPECT_FALSE((*context)->renderer_name().empty());
  const std::string version = (*context)->version_string();
  ASSERT_FALSE(version.empty());
  EXPECT_GE(std::atoi(version.c_str()), 4) << version;
}

TEST_F(RendererGL, BackgroundIsSkyAndBoxesAreNot) {
  // The empty frame is one light blue-grey.
  const Rgb s = sky();
  EXPECT_GT(s[2], s[0]);
  EXPECT_GT(s[0], 128);
  for (int y = 0; y < sky_.height; ++y)
    for (int x = 0; x < sky_.width; ++x) ASSERT_EQ(at(sky_, {x, y}), s) << x << "," << y;

  const Image image = render(front_, list_of(scene_, {0, 1, 2, 3}));
  EXPECT_EQ(at(image, {0, 0}), s);
  EXPECT_EQ(at(image, {image.width - 1, image.height - 1}), s);
  for (int i = 0; i < 4; ++i) EXPECT_NE(at(image, pixel_of(front_, front_face(i))), s) << i;
}

// Backdrop quads (DrawList::backdrop) fill only what geometry leaves: a quad between the eye
// and box 0 still shows only where no geometry is; placed in the world (bird's-eye) it hides
// the box. Uploads fill textures named by handle; alpha below one and opacity blend.
TEST_F(RendererGL, FarQuadsFillOnlyWhatGeometryLeaves) {
  const std::vector<uint8_t> green(4 * 4 * 3, 0), half(4 * 4 * 4, 0);
  std::vector<uint8_t> g = green, h = half;
  for (size_t i = 1; i < g.size(); i += 3) g[i] = 255;
  for (size_t i = 0; i < h.size(); i += 4) h[i + 2] = 255, h[i + 3] = 128;  // blue, half covered
  DrawList list = list_of(scene_, {0});
  const TextureHandle green_texture = renderer_->create_texture();
  const TextureHandle blue_texture = renderer_->create_texture();
  list.uploads = {{green_texture, 4, 4, 3, g.data(), nullptr},
                  {blue_texture, 4, 4, 4, h.data(), nullptr}};
  // A wide quad at z = -1, in front of box 0 (front face at z = 0), facing the eye.
  const std::array<glm::vec3, 4> wall = {glm::vec3{-20, 20, -1}, glm::vec3{20, 20, -1},
                                         glm::vec3{20, -20, -1}, glm::vec3{-20, -20, -1}};
  list.backdrop = {{wall, green_texture, 1.0f}};
  const Image backdrop = render(front_, list);
  EXPECT_EQ(at(backdrop, {0, 0}), (Rgb{0, 255, 0}));  // the quad where the sky was
  const Rgb box = at(backdrop, pixel_of(front_, front_face(0)));
  EXPECT_GT(box[0], 100);  // box 0 (red) stays in front
  EXPECT_LT(box[1], 50);

  list.backdrop_mode = BackdropMode::in_world;  // at its place: in front of the box
  const Image world = render(front_, list);
  EXPECT_EQ(at(world, pixel_of(front_, front_face(0))), (Rgb{0, 255, 0}));

  // The half-covered blue quad drawn over the green one, at half opacity: a quarter blue.
  list.backdrop_mode = BackdropMode::far;
  list.uploads.clear();  // the textures keep their images
  list.backdrop = {{wall, green_texture, 1.0f}, {wall, blue_texture, 0.5f}};
  const Rgb mixed = at(render(front_, list), {0, 0});
  EXPECT_NEAR(mixed[1], 191, 3);
  EXPECT_NEAR(mixed[2], 64, 3);
  renderer_->free(green_texture);
  renderer_->free(blue_texture);
}

// The renderer lets go of an upload's pixels once they are on the GPU: the owner is released
// then (not when the list is cleared), and the list drawn again draws the same texture.
TEST_F(RendererGL, UploadedPixelsAreLetGoOfOnceOnTheGpu) {
  auto green = std::make_shared<std::vector<uint8_t>>(4 * 4 * 3, 0);
  for (size_t i = 1; i < green->size(); i += 3) (*green)[i] = 255;
  const std::weak_ptr<std::vector<uint8_t>> watch = green;
  DrawList list = list_of(scene_, {0});
  const TextureHandle texture = renderer_->create_texture();
  list.uploads = {{texture, 4, 4, 3, green->data(), green}};
  green.reset();
  const std::array<glm::vec3, 4> wall = {glm::vec3{-20, 20, -1}, glm::vec3{20, 20, -1},
                                         glm::vec3{20, -20, -1}, glm::vec3{-20, -20, -1}};
  list.backdrop = {{wall, texture, 1.0f}};
  EXPECT_FALSE(watch.expired());
  EXPECT_EQ(at(render(front_, list), {0, 0}), (Rgb{0, 255, 0}));
  EXPECT_TRUE(watch.expired());
  EXPECT_EQ(list.uploads[0].pixels, nullptr);
  EXPECT_EQ(at(render(front_, list), {0, 0}), (Rgb{0, 255, 0}));
  renderer_->free(texture);
}

TEST_F(RendererGL, FacesTowardALightAreBrighterThanFacesTurnedAway) {
  // From below and in front of box 0: its +X face (towards the first light), its -Z face
  // (the second light at a grazing angle) and its bottom (away from both, ambient only).
  const View below = look_at({3.0f, -1.5f, -3.0f}, {0.5f, 0.5f, 0.5f});
  const Image image = render(below, list_of(scene_, {0}));
  auto brightness = [&](glm::vec3 p) {
    const Rgb c = at(image, pixel_of(below, p));
    return c[0] + c[1] + c[2];
  };
  const int plus_x = brightness({1.0f, 0.5f, 0.5f});
  const int minus_z = brightness({0.5f, 0.5f, 0.0f});
  const int bottom = brightness({0.5f, 0.0f, 0.5f});
  EXPECT_GT(plus_x, minus_z);
  EXPECT_GT(minus_z, bottom);
  EXPECT_GT(bottom, 0);  // ambient

  // The opposite light lights the -X face as the first lights the +X face.
  const View mirrored = look_at({-2.0f, -1.5f, 4.0f}, {0.5f, 0.5f, 0.5f});
  const Image other = render(mirrored, list_of(scene_, {0}));
  const Rgb minus_x = at(other, pixel_of(mirrored, {0.0f, 0.5f, 0.5f}));
  const Rgb lit = at(image, pixel_of(below, {1.0f, 0.5f, 0.5f}));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(minus_x[c], lit[c], 1);
}

// DrawList::faded: a range faded in at c and the same range faded out (complement) at c
// draw the frame the range draws whole, pixel for pixel; alone, each covers its share of the
// box's pixels (a 4 x 4 dither: exactly 4 of 16 at a quarter).
TEST_F(RendererGL, FadedRangesShareThePixelsBetweenThem) {
  const Object& o = scene_.objects[0];
  const DrawRange range{o.first_index, o.index_count, o.material};
  const Image whole = render(front_, list_of(scene_, {0}));
  for (float c : {0.25f, 0.5f, 0.8f}) {
    SCOPED_TRACE(c);
    DrawList both;
    both.faded = {{range, c, false}, {range, c, true}};
    EXPECT_EQ(render(front_, both).rgb, whole.rgb);
    int box = 0, in = 0, out = 0;
    DrawList fading_in, fading_out;
    fading_in.faded = {{range, c, false}};
    fading_out.faded = {{range, c, true}};
    const Image a = render(front_, fading_in), b = render(front_, fading_out);
    for (int y = 0; y < whole.height; ++y)
      for (int x = 0; x < whole.width; ++x) {
        if (at(whole, {x, y}) == sky()) continue;
        ++box;
        in += at(a, {x, y}) != sky();
        out += at(b, {x, y}) != sky();
      }
    ASSERT_GT(box, 100);
    EXPECT_EQ(in + out, box);
    // The pattern's share: the thresholds (k + 0.5) / 16 below c.
    const double share = std::floor(c * 16.0 - 0.5 + 1.0) / 16.0;
    EXPECT_NEAR(double(in) / box, share, 0.05);
  }
}

TEST_F(RendererGL, ObjectsLeftOutOfTheListStaySky) {
  const Image image = render(front_, list_of(scene_, {0, 2}));
  EXPECT_NE(at(image, pixel_of(front_, front_face(0))), sky());
  EXPECT_NE(at(image, pixel_of(front_, front_face(2))), sky());
  EXPECT_EQ(at(image, pixel_of(front_, front_face(1))), sky());
  EXPECT_EQ(at(image, pixel_of(front_, front_face(3))), sky());
}

TEST_F(RendererGL, SameListGivesIdenticalPixels) {
  const DrawList list = list_of(scene_, {0, 1, 2, 3});
  const Image first = render(front_, list);
  renderer_->draw_everything_at_once(front_);  // leaves no state behind
  const Image second = render(front_, list);
  EXPECT_EQ(first.rgb, second.rgb);

  // Drawing box 0 600 times (the command buffer grows) gives the pixels of drawing it once.
  DrawList repeated;
  repeated.opaque.assign(600, list_of(scene_, {0}).opaque[0]);
  EXPECT_EQ(render(front_, repeated).rgb, render(front_, list_of(scene_, {0})).rgb);
}

TEST_F(RendererGL, TransparentBoxBlendsWithTheSky) {
  const glm::ivec2 p = pixel_of(front_, front_face(1));
  const Rgb blended = at(render(front_, list_of(scene_, {1})), p);

  // The same box made opaque gives the colour being blended.
  Scene solid = scene_;
  for (Material& m : solid.materials) m.base_color.a = 1.0f;
  auto solid_renderer = gpu::Renderer::create(solid);
  ASSERT_TRUE(solid_renderer);
  const Rgb color = at(render(front_, list_of(solid, {1}), solid_renderer->get()), p);

  EXPECT_NE(blended, sky());
  EXPECT_NE(blended, color);
  for (int c = 0; c < 3; ++c) {
    EXPECT_GE(blended[c], std::min(sky()[c], color[c])) << c;
    EXPECT_LE(blended[c], std::max(sky()[c], color[c])) << c;
  }
}

TEST_F(RendererGL, EverythingAtOnceCoversTheOpaqueList) {
  DrawList opaque = list_of(scene_, {0, 1, 2, 3});
  opaque.transparent.clear();
  const Image some = render(front_, opaque);
  renderer_->draw_everything_at_once(front_);
  const Image all = renderer_->capture();
  for (int y = 0; y < some.height; ++y)
    for (int x = 0; x < some.width; ++x)
      if (at(some, {x, y}) != sky()) {
        ASSERT_NE(at(all, {x, y}), sky()) << x << "," << y;
      }
  // Glass boxes too, drawn opaque.
  EXPECT_NE(at(all, pixel_of(front_, front_face(1))), sky());
  EXPECT_EQ(at(all, pixel_of(front_, front_face(1))), at(all, pixel_of(front_, front_face(2))));
}

TEST_F(RendererGL, ChunkedBuffersDrawTheSamePixels) {
  // One box a chunk (24 vertices of 20 bytes): ranges that cross chunks are split, and every
  // chunk's draws find their vertices through the base vertex.
  auto chunked = gpu::Renderer::create(scene_, 500);
  ASSERT_TRUE(chunked) << chunked.error().message;
  DrawList crossing;  // boxes 0 to 2 in one range, box 3 on its own
  crossing.opaque.push_back({0, scene_.objects[2].first_index + scene_.objects[2].index_count, 0});
  crossing.transparent.push_back(
      {scene_.objects[3].first_index, scene_.objects[3].index_count, scene_.objects[3].material});
  for (const DrawList& list : {list_of(scene_, {0, 1, 2, 3}), crossing}) {
    const Image whole = render(front_, list);
    const Image parts = render(front_, list, chunked->get());
    EXPECT_EQ(whole.rgb, parts.rgb);
  }
  EXPECT_EQ((*chunked)->draw(front_, crossing).draw_calls, 4u);  // 3 pieces + 1
  renderer_->draw_everything_at_once(front_);
  const Image whole = renderer_->capture();
  const gpu::FrameStats raw = (*chunked)->draw_everything_at_once(front_);
  EXPECT_EQ(whole.rgb, (*chunked)->capture().rgb);
  EXPECT_EQ(raw.draw_calls, 4u);
  EXPECT_EQ(raw.triangles, scene_.triangle_count());
}

TEST_F(RendererGL, FrameStatsCountTheList) {
  renderer_->set_offscreen(front_.width, front_.height);
  const gpu::FrameStats stats = renderer_->draw(front_, list_of(scene_, {0, 1, 3}));
  EXPECT_EQ(stats.triangles, 36u);
  EXPECT_EQ(stats.draw_calls, 3u);
  EXPECT_GE(stats.gpu_ms, 0.0);
  const gpu::FrameStats all = renderer_->draw_everything_at_once(front_);
  EXPECT_EQ(all.triangles, scene_.triangle_count());
  EXPECT_EQ(all.draw_calls, 1u);
}

TEST_F(RendererGL, CaptureIsTopDown) {
  // Eye below the boxes, looking level: box 0 is in the upper half of the image.
  const View low = look_at({0.5f, -2.0f, -5.0f}, {0.5f, -2.0f, 0.0f});
  const Image image = render(low, list_of(scene_, {0}));
  const glm::ivec2 p = pixel_of(low, front_face(0));
  ASSERT_LT(p.y, image.height / 2);
  EXPECT_NE(at(image, p), sky());
  EXPECT_EQ(at(image, {p.x, image.height - 1 - p.y}), sky());
}

TEST_F(RendererGL, CaptureSavesAsPng) {
  test::TempDir dir;
  const Image image = render(front_, list_of(scene_, {0, 1, 2, 3}));
  ASSERT_TRUE(write_png(image, dir.file("frame.png")));
  auto read = read_png(dir.file("frame.png"));
  ASSERT_TRUE(read) << read.error().message;
  EXPECT_EQ(read->rgb, image.rgb);
}

}  // namespace
}  // namespace farfield
