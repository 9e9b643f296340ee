#include "farfield/core/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace farfield {

Progress::Progress(bool quiet) : quiet_(quiet), terminal_(isatty(STDERR_FILENO) != 0) {}

Progress::~Progress() { finish(); }

void Progress::start(std::string task, uint64_t total) {
  finish();
  task_ = std::move(task);
  total_ = total;
  done_ = 0;
  last_decile_ = -1;
  active_ = true;
  start_ = last_print_ = std::chrono::steady_clock::now();
}

void Progress::advance(uint64_t steps) {
  done_ += steps;
  print(false);
}

void Progress::finish() {
  if (!active_) return;
  done_ = total_;
  print(true);
  active_ = false;
  if (!quiet_ && terminal_) std::fputc('\n', stderr);
}

void Progress::print(bool force) {
  if (quiet_ || !active_) return;
  const auto now = std::chrono::steady_clock::now();
  const int percent = total_ ? static_cast<int>(100 * done_ / total_) : 100;
  const double seconds = std::chrono::duration<double>(now - start_).count();
  if (terminal_) {
    if (!force && now - last_print_ < std::chrono::milliseconds(200)) return;
    std::fprintf(stderr, "\r%s: %3d%% (%llu/%llu) %.1f s", task_.c_str(), percent,
                 static_cast<unsigned long long>(done_), static_cast<unsigned long long>(total_),
                 seconds);
  } else {
    const int decile = percent / 10;
    if (decile == last_decile_) return;
    last_decile_ = decile;
    std::fprintf(stderr, "%s: %d%% %.1f s\n", task_.c_str(), percent, seconds);
  }
  std::fflush(stderr);
  last_print_ = now;
}

}  // namespace farfield
