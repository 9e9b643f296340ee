#include "farfield/eval/frame_loop.hpp"

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "farfield/eval/birdseye.hpp"

namespace farfield {

namespace {

using Clock = std::chrono::steady_clock;

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

void fill(FrameTiming& t, const gpu::FrameStats& stats, const DrawList& list) {
  t.gpu_ms = stats.gpu_ms;
  t.upload_ms = stats.upload_ms;
  t.triangles = stats.triangles;
  t.draw_calls = stats.draw_calls;
  t.mesh_triangles = list.mesh_triangle_count();
  t.predicted_ms = list.predicted_ms;
  t.occlusion_ms = list.occlusion_ms;
}

}  // namespace

FrameBudget next_budget(double target_ms, const FrameTiming& last) {
  return {target_ms,      last.frame_ms,   last.select_ms,
          last.triangles, last.draw_calls, last.upload_ms};
}

FrameTiming FrameLoop::run(Technique& technique, const View& view, uint64_t frame,
                           const FrameBudget& budget, float birdseye_height, bool tinted) {
  FrameTiming t;
  const auto start = Clock::now();
  list_.clear();
  technique.select({view, frame, Region::everything(), budget}, list_);
  t.select_ms = ms_between(start, Clock::now());
  if (tinted || birdseye_height > 0.0f) technique.tint(list_);
  gpu::FrameStats stats;
  if (birdseye_height > 0.0f) {
    technique.annotate(view, list_);
    add_frustum_lines(view, birdseye_height * 0.5f, list_);
    stats = renderer_.draw(birdseye_view(view, birdseye_height), list_);
  } else {
    stats = renderer_.draw(view, list_);
  }
  renderer_.finish();
  technique.frame_done(frame);
  t.frame_ms = t.latency_ms = ms_between(start, Clock::now());
  fill(t, stats, list_);
  return t;
}

FrameTiming FrameLoop::run_raw(const View& view) {
  FrameTiming t;
  const auto start = Clock::now();
  list_.clear();
  const gpu::FrameStats stats = renderer_.draw_everything_at_once(view);
  renderer_.finish();
  t.frame_ms = t.latency_ms = ms_between(start, Clock::now());
  t.gpu_ms = stats.gpu_ms;
  t.triangles = stats.triangles;
  t.draw_calls = stats.draw_calls;
  return t;
}

void FrameLoop::draw_birdseye(Technique* technique, const View& eye, float height) {
  if (technique) {
    technique->annotate(eye, list_);
    technique->tint(list_);
  }
  add_frustum_lines(eye, height * 0.5f, list_);
  const View above = birdseye_view(eye, height);
  if (technique)
    renderer_.draw(above, list_);
  else
    renderer_.draw_everything_at_once(above);  // the raw bound draws no lines
  renderer_.finish();
}

void FrameLoop::run_pipelined(Technique& technique, uint64_t first, uint64_t count,
                              const std::function<View(uint64_t)>& view_of,
                              const FrameBudget& budget,
                              const std::function<void(uint64_t, const FrameTiming&)>& after) {
  // Two lists: the selector fills one while the renderer draws the other. A list is handed
  // over when selected and handed back once its frame is done.
  struct Slot {
    bool ready = false;  // selected, not yet drawn
    Clock::time_point select_start;
    double select_ms = 0;
  };
  std::mutex mutex;
  std::condition_variable changed;
  Slot slots[2];
  // Every call into the technique happens on the selector thread: frame_done(f - 2) once
  // frame f - 2 is drawn (its list is free again), then select(f) into that list.
  const uint64_t end = first + count;
  std::thread selector([&] {
    for (uint64_t f = first; f < end + 2; ++f) {
      Slot& slot = slots[f % 2];
      {
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return !slot.ready; });
      }
      if (f >= first + 2) technique.frame_done(f - 2);
      if (f >= end) continue;
      const auto start = Clock::now();
      DrawList& list = lists_[f % 2];
      list.clear();
      technique.select({view_of(f), f, Region::everything(), budget}, list);
      {
        std::lock_guard lock(mutex);
        slot.select_start = start;
        slot.select_ms = ms_between(start, Clock::now());
        slot.ready = true;
      }
      changed.notify_all();
    }
  });
  std::optional<Clock::time_point> interval_start;
  for (uint64_t f = first; f < end; ++f) {
    Slot& slot = slots[f % 2];
    {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return slot.ready; });
    }
    if (!interval_start) interval_start = slot.select_start;
    const gpu::FrameStats stats = renderer_.draw(view_of(f), lists_[f % 2]);
    renderer_.finish();
    const auto drawn = Clock::now();
    FrameTiming t;
    t.frame_ms = ms_between(*interval_start, drawn);
    t.latency_ms = ms_between(slot.select_start, drawn);
    t.select_ms = slot.select_ms;
    fill(t, stats, lists_[f % 2]);
    after(f, t);  // its list is handed back afterwards
    interval_start = Clock::now();
    {
      std::lock_guard lock(mutex);
      slot.ready = false;
    }
    changed.notify_all();
  }
  selector.join();
}

}  // namespace farfield
