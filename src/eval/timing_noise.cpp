#include "farfield/eval/timing_noise.hpp"

#include <algorithm>
#include <barrier>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

namespace farfield {

namespace {

using Clock = std::chrono::steady_clock;

// A dependent chain of multiply-adds: no memory traffic, nothing the compiler can drop.
double spin(uint64_t steps, double seed) {
  double a = seed;
  for (uint64_t i = 0; i < steps; ++i) a = a * 1.0000001 + 1e-9;
  return a;
}

// Threads that each run `steps` of the workload per round, started and joined by barriers,
// as a renderer's persistent threads take a frame's tiles.
class Workers {
 public:
  explicit Workers(uint32_t count) : start_(count + 1), done_(count + 1), sinks_(count) {
    for (uint32_t k = 0; k < count; ++k)
      threads_.emplace_back([this, k] {
        for (;;) {
          start_.arrive_and_wait();
          if (stop_) return;
          sinks_[k] += spin(steps_, 1.0 + k);
          done_.arrive_and_wait();
        }
      });
  }
  ~Workers() {
    stop_ = true;
    start_.arrive_and_wait();
    for (std::thread& t : threads_) t.join();
  }
  double round_ms(uint64_t steps) {
    steps_ = steps;
    const auto begin = Clock::now();
    start_.arrive_and_wait();
    done_.arrive_and_wait();
    return std::chrono::duration<double, std::milli>(Clock::now() - begin).count();
  }

 private:
  std::barrier<> start_, done_;
  std::vector<std::thread> threads_;
  uint64_t steps_ = 0;
  bool stop_ = false;
  std::vector<double> sinks_;  // each thread's result, kept so that its work is not dropped
};

}  // namespace

TimingNoise measure_timing_noise(double work_ms, uint32_t rounds, uint32_t threads) {
  work_ms = std::clamp(work_ms, 0.1, 1000.0);
  rounds = std::max(rounds, 1u);
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  Workers workers(threads);
  // Calibrated on rounds of at least a quarter of the length, the best of three (the least
  // disturbed).
  uint64_t steps = 1 << 16;
  while (workers.round_ms(steps) < 0.25 * work_ms && steps < (uint64_t(1) << 40)) steps *= 2;
  double best = INFINITY;
  for (int k = 0; k < 3; ++k) best = std::min(best, workers.round_ms(steps));
  steps = std::max<uint64_t>(1, uint64_t(double(steps) * work_ms / std::max(best, 1e-3)));

  std::vector<double> ms(rounds);
  for (double& m : ms) m = workers.round_ms(steps);
  std::vector<double> sorted = ms;
  std::sort(sorted.begin(), sorted.end());
  TimingNoise out;
  out.rounds = rounds;
  out.threads = threads;
  out.work_ms = work_ms;
  out.median_ms = sorted[sorted.size() / 2];
  const double p99 = sorted[std::min(sorted.size() - 1, size_t(0.99 * double(sorted.size())))];
  out.p99_to_median = out.median_ms > 0 ? p99 / out.median_ms : 0.0;
  out.over_1_1x = double(std::count_if(ms.begin(), ms.end(),
                                       [&](double m) { return m > 1.1 * out.median_ms; })) /
                  double(rounds);
  return out;
}

}  // namespace farfield
