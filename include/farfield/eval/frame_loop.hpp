// The frame loop of bench and view (DESIGN.md, "The benchmark protocol"): a technique selects
// into a list, the renderer draws it, the frame ends in glFinish, and the technique hears that
// its frame is done. Timed from the start of selection to the end of drawing.
//
// Pipelined (bench --pipelined): selection of frame f+1 runs on a second thread while frame f
// is drawn (paper 001 Sec. 5.3; Maciel and Shirley ran selection and drawing on two
// processors). Then `frame_ms` is the time between the ends of successive frames and
// `latency_ms` the time from the start of a frame's selection to the end of its drawing. All
// calls into the technique then happen on the selection thread, frame_done(f) included.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include "farfield/core/view.hpp"
#include "farfield/gpu/draw_list.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/techniques/technique.hpp"

namespace farfield {

struct FrameTiming {
  double frame_ms = 0;    // see above
  double select_ms = 0;   // the technique's select()
  double latency_ms = 0;  // pipelined: selection start to drawing end; else frame_ms
  double gpu_ms = 0;
  double upload_ms = 0;  // of frame_ms, the renderer's taking in the list's uploads
  uint64_t triangles = 0, draw_calls = 0;
  uint64_t mesh_triangles = 0;  // of the triangles, technique meshes (stand-ins)
  double predicted_ms = -1.0;   // DrawList::predicted_ms
  double occlusion_ms = -1.0;   // DrawList::occlusion_ms (part of select_ms)
};

// The budget of the next frame: the target and what the last frame measured.
FrameBudget next_budget(double target_ms, const FrameTiming& last);

class FrameLoop {
 public:
  explicit FrameLoop(gpu::Renderer& renderer) : renderer_(renderer) {}

  // One frame of `technique` at `view`; with a bird's-eye height the selection is drawn from
  // that far above the eye, annotated and tinted (paper 000, Fig. 5-2), instead of from the
  // eye; `tinted`: coloured by representation from the eye too (Technique::tint).
  FrameTiming run(Technique& technique, const View& view, uint64_t frame, const FrameBudget& budget,
                  float birdseye_height = 0.0f, bool tinted = false);
  // The last frame's selection (after run(); the viewer picks in it).
  const DrawList& last_list() const { return list_; }
  // The raw bound: every triangle in one draw.
  FrameTiming run_raw(const View& view);
  // The last frame's selection seen from above, annotated and tinted (after run() of the same
  // view).
  void draw_birdseye(Technique* technique, const View& eye, float height);

  // Frames `first` .. `first + count - 1` pipelined; `view_of(f)` gives each view and
  // `after(f, timing)` is called on this thread once frame f is drawn, before the next is drawn
  // (a capture there is not timed: the next interval starts when it returns).
  void run_pipelined(Technique& technique, uint64_t first, uint64_t count,
                     const std::function<View(uint64_t)>& view_of, const FrameBudget& budget,
                     const std::function<void(uint64_t, const FrameTiming&)>& after);

 private:
  gpu::Renderer& renderer_;
  DrawList list_;
  DrawList lists_[2];  // pipelined
};

}  // namespace farfield
