#include "farfield/core/parallel.hpp"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace farfield {

bool parallel_for(size_t count, int threads, Progress& progress, const std::string& task,
                  const std::function<void(size_t)>& work, const std::function<bool()>& poll) {
  std::atomic<size_t> next{0}, done{0};
  std::atomic<bool> stop{false};
  auto worker = [&] {
    for (size_t i; !stop.load() && (i = next.fetch_add(1)) < count; done.fetch_add(1)) work(i);
  };
  const unsigned n =
      threads > 0 ? unsigned(threads) : std::max(1u, std::thread::hardware_concurrency());
  progress.start(task, count);
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < n; ++t) pool.emplace_back(worker);
  bool ok = true;
  for (size_t reported = 0; reported < count && ok;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const size_t now = done.load();
    progress.advance(now - reported);
    reported = now;
    if (poll && !poll()) ok = false;
  }
  stop.store(!ok);
  for (auto& t : pool) t.join();
  if (ok && poll) ok = poll();
  progress.finish();
  return ok;
}

void parallel_for(size_t count, int threads, Progress& progress, const std::string& task,
                  const std::function<void(size_t)>& work) {
  parallel_for(count, threads, progress, task, work, {});
}

void run_below_other_threads() {
  setpriority(PRIO_PROCESS, pid_t(syscall(SYS_gettid)), 10);
}

}  // namespace farfield
