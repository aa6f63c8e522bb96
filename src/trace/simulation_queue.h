#pragma once
// Cache simulations (gpu::simulate) on a worker thread, in the order queued, while the caller traces the next
// variant: the simulator is single-threaded, and a trace render leaves a core to it part of the time (its
// readback and decoding run on one thread). The results are the same as simulating in line.
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include "gpu/cache_sim.h"
#include "gpu/fetch_trace.h"

namespace aovar::trace {

class SimulationQueue {
 public:
  SimulationQueue() = default;
  SimulationQueue(const SimulationQueue&) = delete;
  SimulationQueue& operator=(const SimulationQueue&) = delete;
  ~SimulationQueue();  // stops after the running simulation; what is still queued is dropped

  // Simulates `trace` through `hierarchy` into *into, which must stay where it is until finish() returns and
  // must not be read before.
  void add(std::shared_ptr<const gpu::FetchTrace> trace, gpu::CacheHierarchy hierarchy, gpu::CacheSimResult* into);
  // Waits for every queued simulation; returns the seconds they took. Rethrows the first exception of one
  // (the simulations after it are dropped).
  double finish();

 private:
  struct Job {
    std::shared_ptr<const gpu::FetchTrace> trace;
    gpu::CacheHierarchy hierarchy;
    gpu::CacheSimResult* into;
  };
  void work();

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Job> jobs_;
  bool running_job_ = false, stopping_ = false;
  std::exception_ptr error_;
  double seconds_ = 0;
  std::thread worker_;  // started by the first add
};

}  // namespace aovar::trace
