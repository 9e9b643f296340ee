// The machine's own frame-time noise (bench --noise-floor): a fixed arithmetic workload, split
// over every core as a renderer's threads split a frame, timed round after round. Whatever
// varies in its times is the machine's (other processes, the scheduler, a virtual machine's
// host), not a technique's: no technique can hold a budget more steadily than this.
#pragma once

#include <cstdint>

namespace farfield {

struct TimingNoise {
  uint32_t rounds = 0, threads = 0;
  double work_ms = 0;    // the round's length the workload was calibrated to
  double median_ms = 0;  // of the rounds measured
  double p99_to_median = 0;
  double over_1_1x = 0;  // the share of rounds over 1.1 x the median
};

// Times `rounds` rounds of about `work_ms` each (calibrated first), on `threads` threads
// (0: one per core). work_ms in (0, 1000], rounds at least 1.
TimingNoise measure_timing_noise(double work_ms, uint32_t rounds, uint32_t threads = 0);

}  // namespace farfield
