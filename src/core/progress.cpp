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
  printed_ = false;
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
  if (printed_ && terminal_) std::fputc('\n', stderr);
}

void Progress::print(bool force) {
  if (quiet_ || !active_) return;
  const auto now = std::chrono::steady_clock::now();
  // Short tasks stay silent; long ones report every 0.2 s on a terminal, every 2 s in a log.
  const auto interval = std::chrono::milliseconds(terminal_ ? 200 : 2000);
  if (now - last_print_ < interval && !(force && printed_)) return;
  const int percent = total_ ? static_cast<int>(100 * done_ / total_) : 100;
  const double seconds = std::chrono::duration<double>(now - start_).count();
  std::fprintf(stderr, "%s%s: %3d%% (%llu/%llu) %.1f s%s", terminal_ ? "\r" : "", task_.c_str(),
               percent, static_cast<unsigned long long>(done_),
               static_cast<unsigned long long>(total_), seconds, terminal_ ? "" : "\n");
  std::fflush(stderr);
  last_print_ = now;
  printed_ = true;
}

}  // namespace farfield
