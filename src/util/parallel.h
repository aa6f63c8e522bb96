#pragma once
// The thread pool generate compiles with: `count` tasks over `jobs` threads (0 = hardware threads), each
// thread taking the next index from a shared counter, the calling thread working too. bench/compile's
// glslang floor uses the same pool, so the two compare on the same threads.
#include <cstddef>
#include <functional>

namespace aovar::util {

// Threads that `jobs` means: jobs > 0 as given, else the hardware threads (at least 1).
unsigned pool_threads(int jobs);

// Runs task(0) ... task(count - 1) on min(pool_threads(jobs), count) threads; returns when all are done.
// When a task throws, no further task starts and the first exception is rethrown here.
void run_parallel(std::size_t count, int jobs, const std::function<void(std::size_t)>& task);

}  // namespace aovar::util
