// The one interface every rendering technique implements (DESIGN.md, docs/architecture.md).
// A technique is made from its descriptor and settings (technique_descriptor.hpp), may bake
// once into a .ffpack store, loads once with a context (scene, store, a device for its render
// resources), then selects what to draw for each frame: pure CPU, no GL, no allocation in
// steady state, appending to a list that other techniques may share, so that selection can
// be tested without a GPU, timed apart from drawing, and run one frame ahead of the renderer.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "farfield/core/bounds.hpp"
#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/core/view.hpp"
#include "farfield/gpu/device.hpp"
#include "farfield/gpu/draw_list.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

class Store;
class ChunkedScene;
namespace gpu {
class Renderer;
}

// The part of the scene a frame asks a technique for.
struct Region {
  enum class Kind : uint8_t {
    all,        // the whole scene
    near,       // the objects that meet `box` (touching counts, as paper 000's near objects)
    far_field,  // only the technique's far field, beyond a box of its choosing, which
                // Technique::far_field_box() names after select()
  };
  Kind kind = Kind::all;
  Bounds3 box;  // near

  static Region everything() { return {}; }
  static Region near_box(const Bounds3& b) { return {Kind::near, b}; }
  static Region far_field() { return {Kind::far_field, {}}; }
};

// The engine's frame-time budget and what the previous frame measured (zeros before the first
// frame), so that a technique can hold a frame time.
struct FrameBudget {
  double target_ms = 0.0;  // 0: no budget
  double last_frame_ms = 0.0;
  double last_select_ms = 0.0;
  uint64_t last_triangles = 0;
  uint64_t last_draw_calls = 0;
  double last_upload_ms = 0.0;  // of last_frame_ms, taking in the list's uploads
};

struct FrameInput {
  View view;
  uint64_t frame = 0;  // counts up from 0 along a run; frame_done(frame) follows
  Region region;
  FrameBudget budget;
};

struct LoadContext {
  const Scene& scene;   // outlives the technique
  const Store* store;   // the --store pack, or null; a bake of this technique in it was
                        // checked before (eval/run_plan.hpp: this scene, this format)
  gpu::Device& device;  // outlives the technique: its meshes and textures
  Progress& progress;
  // Where the scene's geometry was left in its file (bench and view --cache-mb; only for
  // techniques whose descriptor says `streams`): `scene` is then its index (no vertices or
  // indices), and the technique reads what it draws through a cache of `cache_bytes`.
  const ChunkedScene* on_disk = nullptr;
  uint64_t cache_bytes = 0;
};

// A bake spread over the ranks of an MPI job (mpirun -n N farfield bake ...; techniques whose
// descriptor `distributes`): rank 0 bakes into the pack, rank R > 0 does its share of the work
// (batch b is rank b % N's) into a shard beside the pack, PACK.rank-R, which rank 0 takes in
// once every rank is done, then bakes the rest; shards go when the bake is saved. Each rank
// keeps its work as it goes, so a job killed and run again redoes only unfinished work.
struct BakeShards {
  int rank = 0, size = 1;
  std::string pack;  // the pack rank 0 bakes into
  std::string shard(int r) const { return pack + ".rank-" + std::to_string(r); }
  bool mine(size_t batch) const { return int(batch % size_t(size)) == rank; }
};

// A headless renderer of the scene, made when first asked for, so that a bake that works
// without one first (simplifying) does not hold the scene twice meanwhile (the renderer's
// buffers are a second copy, in memory on llvmpipe).
using BakeRenderer = std::function<Result<gpu::Renderer*>()>;

struct BakeContext {
  const Scene& scene;
  Store& store;           // the technique writes its blobs in transactions of its own (a
                          // shard on ranks other than 0)
  BakeRenderer renderer;  // for bakes that render (TechniqueDescriptor::bake_renders), else
                          // empty (and on ranks other than 0)
  Progress& progress;
  const BakeShards* shards = nullptr;  // null: one process
};

class Technique {
 public:
  virtual ~Technique() = default;
  virtual std::string_view name() const = 0;
  // Offline preprocessing into the store. Techniques with nothing worth keeping refuse.
  virtual Result<void> bake(const BakeContext& context);
  // Builds the run-time structures: from the store's bake where the technique has one there,
  // else from the scene (or refuses, for techniques that need a bake).
  virtual Result<void> load(const LoadContext& context) = 0;
  // Every frame: appends what to draw for `input.region` to `out` (never clears it). The
  // list may be drawn after the next select() has begun: what it points to stays valid until
  // frame_done(input.frame).
  virtual void select(const FrameInput& input, DrawList& out) = 0;
  // The frame's list has been drawn: data kept for it may go.
  virtual void frame_done(uint64_t /*frame*/) {}
  // After select(): the box beyond which this frame's far field stands in for the scene
  // (stratified: its viewcell's box), or none where it drew no far field.
  virtual std::optional<Bounds3> far_field_box() const { return std::nullopt; }
  // Frames so far that fell back to plain geometry for want of anything better (outside a
  // bake's region, ...).
  virtual uint64_t fallback_frames() const { return 0; }
  // After load: a pose where what the technique baked is seen at its best (stratified: inside
  // a baked viewcell), for a viewer given no path; none where every pose is alike.
  virtual std::optional<CameraPose> start_pose() const { return std::nullopt; }
  // One line on what load built (nodes, depth, ...), for reports.
  virtual std::string describe() const { return {}; }
  // The same as named numbers for bench.json (e.g. paper 002's Table 1 for colorcube).
  virtual std::vector<std::pair<std::string, double>> figures() const { return {}; }
  // Bird's-eye pictures (paper 000, Fig. 5-2): called after select() for `eye` with its list,
  // adds the technique's own marks (its viewcell, ...) and places stand-ins where they are.
  virtual void annotate(const View& /*eye*/, DrawList& /*list*/) const {}
  // Colours the list's scene geometry by representation (DrawList::tints; paper 001, Fig. D,
  // right), for bird's-eye pictures and the view's colouring; techniques with one kind of
  // geometry leave it.
  virtual void tint(DrawList& /*list*/) const {}
  // The first error met while running (a damaged blob found by a background load); empty if
  // none. select() has no error channel: callers check this and stop.
  virtual std::string failure() const { return {}; }
};

}  // namespace farfield
