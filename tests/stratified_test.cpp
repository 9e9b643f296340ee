// Stratified rendering (paper 000), the CPU parts: box sides as image planes, the viewcell
// k-d tree and its near objects, the angular error bound, settings and the pack records.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/techniques/stratified/box_faces.hpp"
#include "farfield/techniques/stratified/stratified_options.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "farfield/techniques/stratified/stratified_pack.hpp"
#include "farfield/techniques/stratified/viewcell_analysis.hpp"
#include "farfield/spatial/viewcell_tree.hpp"
#include "test_util.hpp"

namespace farfield::stratified {
namespace {

TEST(BoxFaces, TexelsMapToTheFaceAndBack) {
  const glm::vec3 centre{10, 2, -5};
  const float box = 40;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> d(-1, 1);
  for (int i = 0; i < 1000; ++i) {
    const glm::vec3 dir{d(rng), d(rng), d(rng)};
    if (glm::length(dir) < 1e-3f) continue;
    const FaceHit hit = project_to_box(dir);
    ASSERT_GE(hit.uv.x, 0.0f);
    ASSERT_LE(hit.uv.x, 1.0f);
    ASSERT_GE(hit.uv.y, 0.0f);
    ASSERT_LE(hit.uv.y, 1.0f);
    // The face point lies on the ray and on the box.
    const glm::vec3 p = face_point(centre, box, hit.face, hit.uv);
    EXPECT_NEAR(glm::dot(glm::normalize(p - centre), glm::normalize(dir)), 1.0f, 1e-5f);
    const glm::vec3 q = glm::abs(p - centre);
    EXPECT_NEAR(std::max({q.x, q.y, q.z}), box / 2, 1e-3f);
  }
}

TEST(BoxFaces, ProjectionPutsTheCornersOnTheImageCorners) {
  const glm::vec3 centre{1, 2, 3};
  for (int f = 0; f < kFaces; ++f) {
    const glm::mat4 m = face_view_projection(centre, 8.0f, f);
    const auto corners = face_corners(centre, 8.0f, f);
    const glm::vec2 ndc[4] = {{-1, 1}, {1, 1}, {1, -1}, {-1, -1}};  // top-left first
    for (int c = 0; c < 4; ++c) {
      const glm::vec4 clip = m * glm::vec4(corners[size_t(c)], 1.0f);
      EXPECT_NEAR(clip.x / clip.w, ndc[c].x, 1e-5f) << "face " << f << " corner " << c;
      EXPECT_NEAR(clip.y / clip.w, ndc[c].y, 1e-5f) << "face " << f << " corner " << c;
      EXPECT_GT(clip.z / clip.w, 0.0f);  // in front of the near plane (reversed-Z)
      EXPECT_LT(clip.z / clip.w, 1.0f);
    }
  }
}

Bounds3 box(glm::vec3 lo, glm::vec3 hi) {
  return Bounds3{lo, hi};
}

TEST(ViewcellTree, LocatesLikeTheGridAndCountsCells) {
  auto tree = ViewcellTree::create(box({0, 0, 0}, {100, 3, 47}), 5.0, 40.0);
  ASSERT_TRUE(tree);
  EXPECT_EQ(tree->cells(), (std::array<uint32_t, 3>{20, 1, 10}));
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> x(0, 100), y(0, 3), z(0, 47);
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 p{x(rng), y(rng), z(rng)};
    const auto key = tree->locate(p);
    ASSERT_TRUE(key);
    EXPECT_EQ(key->at[0], std::min(19u, uint32_t(p.x / 5)));
    EXPECT_EQ(key->at[2], std::min(9u, uint32_t(p.z / 5)));
    EXPECT_TRUE(tree->cell_bounds(*key).contains(p));
  }
  EXPECT_FALSE(tree->locate({-1, 1, 1}));
  EXPECT_FALSE(tree->locate({50, 4, 1}));
  // The last cell of an axis is cut at the region (47 m = 9 x 5 m + 2 m).
  EXPECT_FLOAT_EQ(tree->cell_bounds({{0, 0, 9}}).max.z, 47.0f);
}

TEST(ViewcellTree, RefusesBadSizes) {
  EXPECT_FALSE(ViewcellTree::create(box({0, 0, 0}, {10, 10, 10}), 0.0, 5.0));
  EXPECT_FALSE(ViewcellTree::create(box({0, 0, 0}, {10, 10, 10}), 6.0, 5.0));
  EXPECT_FALSE(ViewcellTree::create(Bounds3{}, 1.0, 5.0));
  EXPECT_FALSE(ViewcellTree::create(box({0, 0, 0}, {1e7f, 1, 1}), 1.0, 5.0));
}

// The k-d tree's near lists (object boundaries filtered down the tree) equal a direct test of
// every object against every viewcell's box; touching counts as near.
TEST(ViewcellTree, NearObjectsEqualADirectTest) {
  auto tree = ViewcellTree::create(box({0, 0, 0}, {64, 2, 48}), 4.0, 20.0);
  ASSERT_TRUE(tree);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> at(-20, 90), size(0.1f, 12);
  std::vector<Bounds3> objects;
  for (int i = 0; i < 400; ++i) {
    const glm::vec3 lo{at(rng), at(rng) * 0.1f, at(rng)};
    objects.push_back(box(lo, lo + glm::vec3(size(rng), size(rng), size(rng))));
  }
  // One object exactly touching the first viewcell's box from outside.
  const Bounds3 first = tree->box_bounds({{0, 0, 0}});
  objects.push_back(box({first.max.x, 0, 0}, {first.max.x + 1, 1, 1}));
  uint64_t visited = 0;
  const KdStats stats = tree->visit(objects, nullptr, [&](const CellKey& key, auto near) {
    ++visited;
    std::vector<uint32_t> direct;
    for (uint32_t i = 0; i < objects.size(); ++i)
      if (meet(objects[i], tree->box_bounds(key))) direct.push_back(i);
    EXPECT_EQ(std::vector<uint32_t>(near.begin(), near.end()), direct) << key.name();
    return true;
  });
  EXPECT_EQ(visited, tree->cell_count());
  EXPECT_EQ(stats.nodes, 2 * tree->cell_count() - 1);  // a binary tree with n leaves
  // Only the wanted cells, in kd order, with the same lists.
  const std::vector<CellKey> wanted{{{0, 0, 0}}, {{3, 0, 7}}, {{15, 0, 11}}};
  std::vector<CellKey> seen;
  tree->visit(objects, &wanted, [&](const CellKey& key, auto near) {
    seen.push_back(key);
    if (key == CellKey{{0, 0, 0}}) {
      EXPECT_TRUE(std::find(near.begin(), near.end(), uint32_t(objects.size() - 1)) != near.end());
    }
    return true;
  });
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(seen, wanted);
}

// The worst angle, in degrees, between far points and their texels seen from eye points in
// viewcells of length v (box b, 3 m band, 1000 x 60 x 1000 m model), less alpha_max plus the
// texel's own angular size: <= 0 when the bound holds. Eye points include the viewcells'
// corners (the worst, Fig. 2-4), far points the model's corners, points just outside each
// side and random points outside the box.
struct BoundCheck {
  double worst_excess = -1e9, worst_angle = 0;
};
BoundCheck check_error_bound(double alpha, double v, double b) {
  const Bounds3 model = box({0, 0, 0}, {1000, 60, 1000});
  auto tree = ViewcellTree::create(box({0, 0, 0}, {1000, 3, 1000}), v, b);
  EXPECT_TRUE(tree);
  const int resolution = 1024;
  std::mt19937 rng(4);
  std::uniform_int_distribution<uint32_t> cx(0, tree->cells()[0] - 1), cz(0, tree->cells()[2] - 1);
  std::uniform_real_distribution<float> unit(0, 1);
  BoundCheck r;
  for (int c = 0; c < 300; ++c) {
    const CellKey key{{cx(rng), 0, cz(rng)}};
    const Bounds3 cell = tree->cell_bounds(key), bbox = tree->box_bounds(key);
    const glm::vec3 centre = tree->centre(key);
    std::vector<glm::vec3> eyes;
    for (int i = 0; i < 8; ++i)
      eyes.push_back({i & 1 ? cell.max.x : cell.min.x, i & 2 ? cell.max.y : cell.min.y,
                      i & 4 ? cell.max.z : cell.min.z});
    for (int i = 0; i < 4; ++i)
      eyes.push_back(cell.min + (cell.max - cell.min) * glm::vec3(unit(rng), unit(rng), unit(rng)));
    std::vector<glm::vec3> points;
    for (int i = 0; i < 8; ++i)
      points.push_back({i & 1 ? model.max.x : model.min.x, i & 2 ? model.max.y : model.min.y,
                        i & 4 ? model.max.z : model.min.z});
    while (points.size() < 60) {
      const glm::vec3 p = model.min + model.size() * glm::vec3(unit(rng), unit(rng), unit(rng));
      if (!bbox.contains(p)) points.push_back(p);
    }
    for (int f = 0; f < kFaces; ++f)
      for (float across : {-0.3f, 0.0f, 0.3f}) {
        if (!vertical_face(f)) continue;
        const FaceFrame frame = face_frame(f);
        const glm::vec3 p =
            centre + (frame.normal * 1.001f + frame.right * across) * float(b * 0.5);
        points.push_back(p);
        points.push_back(centre + (p - centre) * 10.0f);  // and far beyond, the same way
      }
    for (const glm::vec3& p : points) {
      if (bbox.contains(p)) continue;
      const FaceHit hit = project_to_box(p - centre);
      // The texel the far point lands in, at its centre.
      const glm::vec2 texel = (glm::floor(hit.uv * float(resolution)) + 0.5f) / float(resolution);
      const glm::vec3 q = face_point(centre, float(b), hit.face, glm::min(texel, glm::vec2(1)));
      for (const glm::vec3& e : eyes) {
        const double angle = glm::degrees(std::acos(
            std::clamp(double(glm::dot(glm::normalize(p - e), glm::normalize(q - e))), -1.0, 1.0)));
        // Half the texel's diagonal as seen from the eye, at the worst (face-on) angle.
        const double texel_deg =
            glm::degrees(std::atan(std::sqrt(0.5) * b / resolution / glm::length(q - e)));
        r.worst_angle = std::max(r.worst_angle, angle);
        r.worst_excess = std::max(r.worst_excess, angle - (alpha + texel_deg));
      }
    }
  }
  return r;
}

// paper 000, Sec. 2.3: with the strict viewcell length (the bake's default) the bound holds.
TEST(StratifiedErrorBound, TexelDirectionsStayWithinAlphaMax) {
  for (const double alpha : {1.0, 2.0, 7.5}) {
    const double b = 120.0;
    auto v = strict_viewcell_length(alpha, b, 3.0);
    ASSERT_TRUE(v);
    const BoundCheck r = check_error_bound(alpha, *v, b);
    std::printf(
        "strict: alpha %.1f, v %.3f m: worst angle %.4f deg, excess over alpha + texel %.4f\n",
        alpha, *v, r.worst_angle, r.worst_excess);
    EXPECT_LE(r.worst_excess, 0.0) << "alpha " << alpha << ": worst angle " << r.worst_angle;
    EXPECT_GT(r.worst_angle, 0.8 * alpha) << "the samples should come near the bound";
  }
}

// Eq. 2.2's viewcell (stratified.sizing=paper) is longer: its planar worst case misses eye points
// at a viewcell's corner looking past the middle of a side, which err a little more.
TEST(StratifiedErrorBound, PaperSizingExceedsAlphaSlightlyIn3D) {
  const double alpha = 2.0, b = 120.0, l = std::sqrt(2 * 1000.0 * 1000.0 + 60.0 * 60.0);
  auto paper = viewcell_length(alpha, b, l);
  auto strict = strict_viewcell_length(alpha, b, 3.0);
  ASSERT_TRUE(paper && strict);
  EXPECT_GT(*paper, *strict);
  const BoundCheck r = check_error_bound(alpha, *paper, b);
  std::printf("paper: alpha %.1f, v %.3f m (strict %.3f m): worst angle %.4f deg\n", alpha, *paper,
              *strict, r.worst_angle);
  EXPECT_GT(r.worst_excess, 0.0);
  EXPECT_LT(r.worst_angle, 1.2 * alpha);
}

// The options from settings checked by the one parser (the stratified descriptor).
Result<StratifiedOptions> options_of(const std::vector<std::pair<std::string, std::string>>& kv) {
  TechniqueSettings settings;
  for (const auto& [key, value] : kv)
    if (auto ok = settings.add("stratified." + key + "=" + value); !ok) return ok.error();
  auto values = parse_settings(**find_technique("stratified"), settings);
  if (!values) return values.error();
  return stratified_options(*values);
}

TEST(StratifiedOptions, ParsesAndRefusesWithTheSettingsName) {
  auto o = options_of({{"alpha", "1.5"},
                       {"box", "300"},
                       {"codec", "png"},
                       {"delta", "1"},
                       {"style", "far-texture"},
                       {"resolution", "256"}});
  ASSERT_TRUE(o) << o.error().message;
  EXPECT_EQ(o->alpha_deg, 1.5);
  EXPECT_EQ(o->box, 300);
  EXPECT_EQ(o->codec.codec, Codec::kPng);
  EXPECT_TRUE(o->delta);
  EXPECT_EQ(o->style, Style::far_texture);
  for (const auto& [key, value, words] :
       std::vector<std::tuple<std::string, std::string, std::string>>{
           {"alpha", "95", "stratified.alpha"},
           {"alpha", "x", "not a number"},
           {"resolution", "3", "stratified.resolution"},
           {"resolution", "100.5", "whole number"},
           {"codec", "gif", "jpeg,png"},
           {"style", "wire", "stratified.style"},
           {"limit", "1,2,3", "4 comma-separated"},
           {"sizing", "loose", "strict,paper"},
           {"bogus", "1", "no such setting"},
       }) {
    auto bad = options_of({{key, value}});
    ASSERT_FALSE(bad) << key << "=" << value;
    EXPECT_NE(bad.error().message.find(words), std::string::npos) << bad.error().message;
  }
  auto jpeg_delta = options_of({{"delta", "1"}});
  ASSERT_FALSE(jpeg_delta);
  EXPECT_NE(jpeg_delta.error().message.find("codec=png"), std::string::npos);
}

TEST(StratifiedOptions, NavigableRegionBands) {
  const Bounds3 scene = box({0, -1, 0}, {100, 80, 50});
  EXPECT_FLOAT_EQ(navigable_region("street", scene)->max.y, 2.0f);
  EXPECT_FLOAT_EQ(navigable_region("all", scene)->max.y, 80.0f);
  auto band = navigable_region("10,20", scene);
  ASSERT_TRUE(band);
  EXPECT_FLOAT_EQ(band->min.y, 10.0f);
  EXPECT_FALSE(navigable_region("20,10", scene));
  EXPECT_FALSE(navigable_region("high", scene));
  EXPECT_FALSE(navigable_region("street", Bounds3{}));
}

BakeParams sample_params(Codec codec, bool delta) {
  BakeParams p;
  p.scene = 1234567890123ull;
  p.alpha_deg = 2;
  p.region = box({-5, 0, 1.5f}, {100, 3, 80});
  p.shells = {{56, 6.35}, {96.4, 10.0}};
  p.resolution = 16;
  p.codec = codec == Codec::kPng ? ImageCodec::png() : ImageCodec::jpeg(90);
  p.delta = delta;
  return p;
}

TEST(StratifiedPack, ParamsRoundTripAndBadTextIsRefused) {
  const BakeParams p = sample_params(Codec::kJpeg, false);
  auto back = parse_params(to_text(p));
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(to_text(*back), to_text(p));
  std::string text = to_text(p);
  EXPECT_FALSE(parse_params(text.substr(0, text.find("codec"))));  // cut
  std::string bad = text;
  bad.replace(bad.find("resolution=16"), 13, "resolution=1");
  EXPECT_FALSE(parse_params(bad));
  EXPECT_FALSE(parse_params("nonsense"));
}

CellRecord sample_record(uint8_t seed, int resolution) {
  CellRecord r;
  r.near = {1, 5, 9};
  for (int f = 0; f < 4; ++f) {
    FaceImage& face = r.faces[size_t(f)];
    face.width = face.height = resolution;
    face.channels = f == 3 ? 4 : 3;
    face.pixels.resize(size_t(resolution) * resolution * face.channels);
    for (size_t i = 0; i < face.pixels.size(); ++i)
      face.pixels[i] = uint8_t(seed + i * 7 + (i / 100) * f);
  }
  return r;
}

TEST(StratifiedPack, CellsRoundTripExactlyWithPngAndDeltaCoding) {
  test::TempDir dir;
  auto store = Store::open(dir.file("p.ffpack"), Store::Mode::kReadWrite);
  ASSERT_TRUE(store);
  const BakeParams p = sample_params(Codec::kPng, true);
  const CellRecord a = sample_record(1, 16), b = sample_record(2, 16);
  const CellKey ka{{0, 0, 0}}, kb{{1, 0, 0}};
  ASSERT_TRUE(write_cell(*store, 0, ka, a, p, nullptr, std::nullopt));
  ASSERT_TRUE(write_cell(*store, 0, kb, b, p, &a, ka));
  for (const auto& [key, want] : {std::pair{ka, &a}, std::pair{kb, &b}}) {
    auto got = read_cell(*store, 0, key, p, 10);
    ASSERT_TRUE(got) << got.error().message;
    EXPECT_EQ(got->near, want->near);
    for (int f = 0; f < kFaces; ++f) {
      EXPECT_EQ(got->faces[size_t(f)].channels, want->faces[size_t(f)].channels);
      EXPECT_TRUE(got->faces[size_t(f)].pixels == want->faces[size_t(f)].pixels) << f;
    }
  }
  EXPECT_EQ(read_cell(*store, 0, kb, p, 10)->reference, ka);
  auto cells = baked_cells(*store, 0);
  ASSERT_TRUE(cells);
  EXPECT_EQ(*cells, (std::vector<CellKey>{ka, kb}));
  // Near ids beyond the scene's objects are refused, naming the blob.
  auto small = read_cell(*store, 0, ka, p, 5);
  ASSERT_FALSE(small);
  EXPECT_NE(small.error().message.find("near"), std::string::npos);
  // A viewcell that was never baked.
  EXPECT_FALSE(read_cell(*store, 0, CellKey{{5, 0, 5}}, p, 10));
}

}  // namespace
}  // namespace farfield::stratified
