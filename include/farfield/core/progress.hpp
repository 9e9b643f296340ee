// Progress of long work, shown on stderr: a line rewritten every 0.2 s on a terminal, a new
// line every 2 s otherwise (logs, CI); work shorter than that shows nothing. Quiet mode shows
// nothing. Not thread-safe: report from one thread.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace farfield {

class Progress {
 public:
  explicit Progress(bool quiet = false);
  ~Progress();
  // Starts a task of `total` steps; ends any previous one.
  void start(std::string task, uint64_t total);
  void advance(uint64_t steps = 1);
  void finish();

 private:
  void print(bool force);

  std::string task_;
  uint64_t total_ = 0, done_ = 0;
  bool quiet_, terminal_, active_ = false, printed_ = false;
  std::chrono::steady_clock::time_point start_, last_print_;
};

}  // namespace farfield
