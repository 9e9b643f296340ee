// The stratified bake (paper 000, Sec. 3.1): viewcells in kd order, far fields rendered onto
// box sides with the GL on this thread while a second thread encodes and writes the previous
// viewcell (one transaction each, so a killed bake resumes where it stopped).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <set>

#include <glm/geometric.hpp>

#include "farfield/core/camera_path.hpp"
#include "farfield/core/assert.hpp"
#include "farfield/core/text.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/object_set.hpp"
#include "farfield/techniques/stratified/box_faces.hpp"
#include "cell_writer.hpp"
#include "stratified_technique.hpp"

namespace farfield {

using namespace stratified;

namespace {

// A bake of more viewcells than this is refused: limit it to a path or a region.
constexpr uint64_t kMaxViewcells = 2'000'000;

// Whether a box meets the pyramid from `centre` through a side (apex at the centre).
bool in_face_pyramid(const Bounds3& b, const glm::vec3& centre, const FaceFrame& f) {
  const glm::vec3 planes[4] = {f.normal + f.right, f.normal - f.right, f.normal + f.up,
                               f.normal - f.up};
  for (const glm::vec3& n : planes) {
    // The box corner farthest along n; outside when even it is behind the plane.
    const glm::vec3 far{n.x > 0 ? b.max.x : b.min.x, n.y > 0 ? b.max.y : b.min.y,
                        n.z > 0 ? b.max.z : b.min.z};
    if (glm::dot(far - centre, n) < 0.0f) return false;
  }
  return true;
}

// The shells' boxes and viewcells: the strict 3D bound, or Eq. 2.2 for one shell and Eq. 4.1
// for several (paper sizing).
Result<std::vector<ShellParams>> plan_shells(const StratifiedOptions& o, double model,
                                             double height) {
  auto strict = [&](double box) -> Result<double> {
    auto v = strict_viewcell_length(o.alpha_deg, box, height);
    if (!v) return make_error("stratified: ", v.error().message);
    return v;
  };
  if (o.shells == 1) {
    if (o.viewcell > 0) return std::vector<ShellParams>{{o.box, o.viewcell}};
    auto v = o.paper_sizing ? viewcell_length(o.alpha_deg, o.box, model) : strict(o.box);
    if (!v) return make_error("stratified: ", v.error().message);
    return std::vector<ShellParams>{{o.box, *v}};
  }
  if (o.viewcell > 0)
    return make_error(
        "--set stratified.viewcell applies to one shell; with shells the viewcells "
        "follow from alpha and each box");
  auto boxes = box_series(o.spacing, o.box, o.factor, model, o.shells);
  if (!boxes) return make_error("stratified: ", boxes.error().message);
  std::vector<ShellParams> out;
  if (o.paper_sizing) {
    auto shells = shell_viewcells(o.alpha_deg, *boxes, model);
    if (!shells) return make_error("stratified: ", shells.error().message);
    for (const Shell& s : *shells) out.push_back({s.box, s.viewcell});
    return out;
  }
  for (double box : *boxes) {
    auto v = strict(box);
    if (!v) return v.error();
    out.push_back({box, *v});
  }
  return out;
}

// The viewcells of each shell that the bake covers: every one, or those a camera path passes
// through and those meeting a limit box.
Result<std::vector<std::optional<std::vector<CellKey>>>> wanted_cells(
    const StratifiedOptions& o, const std::optional<CameraPath>& path,
    const std::vector<ViewcellTree>& trees) {
  std::vector<std::optional<std::vector<CellKey>>> wanted(trees.size());
  if (!path && !o.limit) return wanted;
  for (size_t s = 0; s < trees.size(); ++s) {
    const ViewcellTree& tree = trees[s];
    std::set<CellKey> cells;
    if (path) {
      // Every viewcell the path's segments pass through, sampled at a quarter viewcell.
      const auto& frames = path->frames;
      for (size_t i = 0; i < frames.size(); ++i) {
        const glm::vec3 a = frames[i].position;
        const glm::vec3 b = i + 1 < frames.size() ? frames[i + 1].position : a;
        const int steps = 1 + int(glm::length(b - a) / (0.25f * float(tree.viewcell())));
        for (int k = 0; k <= steps; ++k)
          if (auto key = tree.locate(a + (b - a) * (float(k) / float(steps)))) cells.insert(*key);
      }
      if (cells.empty() && s == 0)
        return make_error(o.path, ": the path never enters the navigable region (stratified.band)");
    }
    if (o.limit) {
      Bounds3 limit = *o.limit;
      limit.min.y = tree.region().min.y;
      limit.max.y = tree.region().max.y;
      const std::vector<CellKey> meeting = tree.cells_meeting(limit);
      if (meeting.empty() && s == 0) {
        const Bounds3& r = tree.region();
        char extent[160];
        std::snprintf(extent, sizeof extent, "x %.1f to %.1f, z %.1f to %.1f", r.min.x, r.max.x,
                      r.min.z, r.max.z);
        return make_error(
            "--set stratified.limit: the rectangle meets no viewcell of the "
            "navigable region (",
            extent, ")");
      }
      cells.insert(meeting.begin(), meeting.end());
    }
    wanted[s] = std::vector<CellKey>(cells.begin(), cells.end());
  }
  return wanted;
}

// What the bake covers when band is auto (docs/techniques/stratified.md, "Defaults from the
// scene"): the street band where the scene has streets and the path, if any, stays in it;
// else the path's heights, 1.5 m either side; else every height. Across, the scene and the
// path (an orbit leaves the scene's box).
Result<Bounds3> bake_region(const StratifiedOptions& o, const Scene& scene,
                            const std::optional<CameraPath>& path) {
  Bounds3 across = scene.bounds;
  Bounds3 walked;
  if (path)
    for (const CameraPose& p : path->frames) walked.expand(p.position);
  across.expand(walked);
  if (o.band != "auto") return navigable_region(o.band, across);
  const bool streets =
      std::any_of(scene.objects.begin(), scene.objects.end(),
                  [](const Object& obj) { return obj.kind == ObjectKind::street; });
  auto street = navigable_region("street", across);
  if (!street) return street;
  const bool path_in_street =
      !path || (walked.min.y >= street->min.y && walked.max.y <= street->max.y);
  if (streets && path_in_street) return street;
  if (!path && !o.limit)
    return make_error(
        "stratified: this scene has no streets, so there is no navigable region to derive; "
        "bake along a camera path (--set stratified.path=PATH.json, e.g. from farfield path "
        "--kind orbit) or name the heights (stratified.band=all or Y0,Y1)");
  Bounds3 region = across;
  if (path) {
    region.min.y = walked.min.y - 1.5f;
    region.max.y = walked.max.y + 1.5f;
  }
  return region;
}

// paper 000 sized its 240 m box from throughput (Sec. 2.4.2): the box whose near triangles
// in view fill one frame, p = b^2 rho tan(h/2) / 4 at a density rho over the ground. With p
// given (near_triangles) and rho the scene's mean over its ground area, b follows; kept
// within 1/64 of the scene and the scene itself.
double derived_box(const Scene& scene, int near_triangles) {
  const glm::vec3 size = scene.bounds.size();
  const double extent = std::max({double(size.x), double(size.z), 1e-3});
  const double area = std::max(double(size.x) * double(size.z), extent * extent * 1e-6);
  const double density = double(scene.triangle_count()) / area;
  auto box = box_from_throughput({.triangles_per_second = double(near_triangles),
                                  .frame_ms = 1000.0,
                                  .density = density,
                                  .unit = DensityUnit::per_square_metre});
  const double b = box ? box->box : extent;
  return std::clamp(b, extent / 64.0, extent);
}

// The share of the scene's triangles in the far fields (objects wholly outside the box),
// averaged over up to 32 of the viewcells to bake, spread over them.
double far_share(const Scene& scene, const ViewcellTree& tree, const std::vector<CellKey>& cells) {
  if (cells.empty() || scene.triangle_count() == 0) return 0.0;
  const size_t samples = std::min<size_t>(32, cells.size());
  double sum = 0.0;
  for (size_t i = 0; i < samples; ++i) {
    const Bounds3 box = tree.box_bounds(cells[i * cells.size() / samples]);
    uint64_t far = 0;
    for (const Object& o : scene.objects)
      if (!meet(o.bounds, box)) far += o.triangle_count();
    sum += double(far) / double(scene.triangle_count());
  }
  return sum / double(samples);
}

}  // namespace

Result<void> StratifiedTechnique::bake(const BakeContext& context) {
  const Scene& scene = context.scene;
  Store& store = context.store;
  Progress& progress = context.progress;
  FF_ASSERT(bool(context.renderer), "the stratified bake renders: it needs a renderer");
  auto made_renderer = context.renderer();
  if (!made_renderer) return made_renderer.error();
  gpu::Renderer& renderer = **made_renderer;
  const auto start = std::chrono::steady_clock::now();
  std::optional<CameraPath> path;
  if (!options_.path.empty()) {
    auto read = read_camera_path(options_.path);
    if (!read) return read.error();
    path = std::move(*read);
  }
  auto region = bake_region(options_, scene, path);
  if (!region) return region.error();
  StratifiedOptions o = options_;
  if (o.box == 0) {
    o.box = derived_box(scene, o.near_triangles);
    const glm::vec3 size = scene.bounds.size();
    if (o.box >= std::max(size.x, size.z))
      return make_error("stratified: the whole scene (", std::to_string(scene.triangle_count()),
                        " triangles, ", number_text(size.x), " x ", number_text(size.z),
                        " m) fits in the box its density asks for (stratified.near_triangles=",
                        std::to_string(o.near_triangles),
                        " in view): there is nothing far to bake; octree draws it as it is "
                        "(or set stratified.box)");
  }
  // The largest distance from a viewpoint to a far point: the diagonal of the scene and the
  // region (a path may leave the scene). Eq. 2.2's error grows with it, so this bounds the
  // error for every far point (the paper's l is the model's length, which a point in the
  // opposite corner exceeds).
  Bounds3 reach = scene.bounds;
  reach.expand(*region);
  const double model = glm::length(reach.size());
  auto shells = plan_shells(o, model, double(region->size().y));
  if (!shells) return shells.error();

  BakeParams params;
  params.scene = scene_fingerprint(scene);
  params.alpha_deg = o.alpha_deg;
  params.region = *region;
  params.shells = *shells;
  params.resolution = options_.resolution;
  params.codec = options_.codec;
  params.delta = options_.delta;
  const std::string text = to_text(params);
  auto existing = store.get_meta(kParamsKey);
  if (!existing) return existing.error();
  if (*existing && **existing != text)
    return make_error(store.path(),
                      " holds a stratified bake with other settings or of another "
                      "scene; bake into a new pack (its settings:\n",
                      **existing, ")");

  std::vector<ViewcellTree> trees;
  for (const ShellParams& s : params.shells) {
    auto tree = ViewcellTree::create(*region, s.viewcell, s.box);
    if (!tree) return tree.error();
    trees.push_back(std::move(*tree));
  }
  auto wanted = wanted_cells(options_, path, trees);
  if (!wanted) return wanted.error();
  uint64_t total = 0;
  std::vector<std::vector<uint64_t>> done(trees.size());
  for (size_t s = 0; s < trees.size(); ++s) {
    total += (*wanted)[s] ? (*wanted)[s]->size() : trees[s].cell_count();
    auto cells = baked_cells(store, int(s));
    if (!cells) return cells.error();
    for (const CellKey& k : *cells) done[s].push_back(k.packed());
    std::sort(done[s].begin(), done[s].end());
  }
  if (total > kMaxViewcells)
    return make_error("stratified: ", std::to_string(total), " viewcells (v ",
                      std::to_string(params.shells[0].viewcell), " m) are more than ",
                      std::to_string(kMaxViewcells),
                      " to bake; limit the bake with --set "
                      "stratified.path=PATH.json or stratified.limit=X0,Z0,X1,Z1, or raise alpha");
  // A bake whose far fields would be (nearly) empty only slows the walk: say so, before
  // anything is written.
  const double share = far_share(
      scene, trees[0], (*wanted)[0] ? *(*wanted)[0] : trees[0].cells_meeting(trees[0].region()));
  if (share < o.far_share) {
    const glm::vec3 size = scene.bounds.size();
    char why[400];
    std::snprintf(why, sizeof why,
                  "stratified: the far fields would hold %.1f%% of the scene's triangles (the "
                  "objects wholly outside a %.1f m box around a viewcell, in a scene %.1f x %.1f m "
                  "across): nothing worth baking. A smaller stratified.box, or another technique "
                  "(octree, colorcube) may suit this scene; stratified.far_share=0 bakes anyway",
                  100.0 * share, params.shells[0].box, size.x, size.z);
    return make_error(why);
  }
  if (!*existing)
    if (auto ok = store.set_meta(kParamsKey, text); !ok) return ok;
  uint64_t already = 0;
  for (size_t s = 0; s < trees.size(); ++s) {
    if (!(*wanted)[s]) {
      already += done[s].size();
      continue;
    }
    for (const CellKey& k : *(*wanted)[s])
      already += std::binary_search(done[s].begin(), done[s].end(), k.packed());
  }
  if (already > 0)
    std::fprintf(stderr, "stratified: %llu of %llu viewcells already baked; continuing\n",
                 (unsigned long long)already, (unsigned long long)total);

  const int resolution = params.resolution;
  renderer.set_offscreen(resolution, resolution);

  std::vector<Bounds3> bounds(scene.objects.size());
  for (size_t i = 0; i < bounds.size(); ++i) bounds[i] = scene.objects[i].bounds;
  ObjectSet far(scene);
  DrawList list;
  std::vector<uint8_t> near_flags(scene.objects.size());
  std::vector<uint32_t> far_objects;
  CellWriter writer(store, params, uint32_t(scene.objects.size()));
  std::string error;
  progress.start("bake stratified", total - already);

  for (size_t s = 0; s < trees.size() && error.empty(); ++s) {
    const ViewcellTree& tree = trees[s];
    const bool outermost = s + 1 == trees.size();
    renderer.set_clear_alpha(outermost ? 1.0f : 0.0f);
    const std::vector<CellKey>* want = (*wanted)[s] ? &*(*wanted)[s] : nullptr;
    tree.visit(bounds, want, [&](const CellKey& key, std::span<const uint32_t> near) {
      if (std::binary_search(done[s].begin(), done[s].end(), key.packed())) return true;
      if (std::string e = writer.error(); !e.empty()) {
        error = e;
        return false;
      }
      CellJob job{int(s), key, {}};
      if (s == 0) job.record.near.assign(near.begin(), near.end());
      for (uint32_t i : near) near_flags[i] = 1;
      // Shell s's far field ends where shell s+1's box may be: the union of the boxes of the
      // outer viewcells that overlap this one (Ch. 4); the outermost's is the rest of the model.
      Bounds3 reach = scene.bounds;
      if (!outermost) {
        reach = Bounds3{};
        for (const CellKey& k : trees[s + 1].cells_meeting(tree.cell_bounds(key)))
          reach.expand(trees[s + 1].box_bounds(k));
      }
      const glm::vec3 centre = tree.centre(key);
      // The viewcell's far objects, once; each side then keeps those in its pyramid.
      far_objects.clear();
      for (uint32_t i = 0; i < bounds.size(); ++i)
        if (!near_flags[i] && meet(bounds[i], reach)) far_objects.push_back(i);
      for (int f = 0; f < kFaces; ++f) {
        const FaceFrame frame = face_frame(f);
        far.clear();
        bool any = false;
        for (uint32_t i : far_objects)
          if (in_face_pyramid(bounds[i], centre, frame)) {
            far.insert(i);
            any = true;
          }
        // A side with nothing behind it stays empty: the sky shows through (for a city lower
        // than the box, the top and bottom: the paper's four vertical sides).
        if (!any) continue;
        list.clear();
        far.emit(list);
        renderer.draw_with(face_view_projection(centre, float(tree.box()), f), resolution,
                           resolution, list);
        Image image = renderer.capture();
        FaceImage& face = job.record.faces[size_t(f)];
        face.width = face.height = resolution;
        if (outermost) {
          face.channels = 3;
          face.pixels = std::move(image.rgb);
        } else {
          const std::vector<uint8_t> alpha = renderer.capture_alpha();
          face.channels = 4;
          face.pixels.resize(alpha.size() * 4);
          for (size_t p = 0; p < alpha.size(); ++p) {
            std::copy_n(&image.rgb[3 * p], 3, &face.pixels[4 * p]);
            face.pixels[4 * p + 3] = alpha[p];
          }
        }
      }
      for (uint32_t i : near) near_flags[i] = 0;
      writer.push(std::move(job));
      progress.advance();
      return true;
    });
  }
  writer.finish();
  progress.finish();
  if (error.empty()) error = writer.error();
  if (!error.empty()) return make_error(error);
  bake_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fprintf(stderr, "stratified: baked %llu viewcells (v %.3g m, box %.3g m) in %.1f s\n",
               (unsigned long long)writer.written(), params.shells[0].viewcell,
               params.shells[0].box, bake_s_);
  char summary[200];
  std::snprintf(summary, sizeof summary,
                "%llu viewcells baked now, %llu in the pack; v %.3g m, box %.3g m, alpha %.2f deg, "
                "%d px %s, %zu shell(s)",
                (unsigned long long)writer.written(),
                (unsigned long long)(already + writer.written()), params.shells[0].viewcell,
                params.shells[0].box, params.alpha_deg, params.resolution,
                codec_name(params.codec.codec), params.shells.size());
  bake_summary_ = summary;
  return {};
}

}  // namespace farfield
