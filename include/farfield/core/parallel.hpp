// Work spread over the cores: work(i) for every i in [0, count), taken in order by `threads`
// threads (0: every core), with progress shown from the calling thread, which waits.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "farfield/core/progress.hpp"

namespace farfield {

void parallel_for(size_t count, int threads, Progress& progress, const std::string& task,
                  const std::function<void(size_t)>& work);

// As above, and `poll()` on the calling thread while the work runs (every 50 ms) and once
// after it: the place for work that must stay on one thread (writing finished results to a
// store). When poll returns false, no further work starts and parallel_for returns false.
bool parallel_for(size_t count, int threads, Progress& progress, const std::string& task,
                  const std::function<void(size_t)>& work, const std::function<bool()>& poll);

// Lowers the calling thread below the process's others (Linux: a thread's own nice value, 10):
// a background loader on a machine whose cores the renderer fills (llvmpipe).
void run_below_other_threads();

}  // namespace farfield
