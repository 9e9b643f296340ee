// Progress of long work, shown on stderr: a rewritten line on a terminal, a line every 10%
// otherwise (logs, CI). Quiet mode shows nothing. Not thread-safe: report from one thread.
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
  int last_decile_ = -1;
  bool quiet_, terminal_, active_ = false;
  std::chrono::steady_clock::time_point start_, last_print_;
};

}  // namespace farfield
