#include "trace/simulation_queue.h"

#include <chrono>
#include <utility>

namespace aovar::trace {

SimulationQueue::~SimulationQueue() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    jobs_.clear();
  }
  changed_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void SimulationQueue::add(std::shared_ptr<const gpu::FetchTrace> trace, gpu::CacheHierarchy hierarchy,
                          gpu::CacheSimResult* into) {
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back({std::move(trace), std::move(hierarchy), into});
  }
  if (!worker_.joinable()) worker_ = std::thread([this] { work(); });
  changed_.notify_all();
}

double SimulationQueue::finish() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return !running_job_ && (jobs_.empty() || error_); });
  if (error_) {
    jobs_.clear();
    std::rethrow_exception(std::exchange(error_, nullptr));
  }
  return std::exchange(seconds_, 0.0);
}

void SimulationQueue::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
    if (stopping_) return;
    Job job = std::move(jobs_.front());
    jobs_.pop_front();
    running_job_ = true;
    lock.unlock();
    const auto start = std::chrono::steady_clock::now();
    std::exception_ptr error;
    try {
      *job.into = gpu::simulate(*job.trace, job.hierarchy);
    } catch (...) {
      error = std::current_exception();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    job = {};  // the trace's memory goes now, not with the next job
    lock.lock();
    running_job_ = false;
    seconds_ += seconds;
    if (error && !error_) error_ = error;
    changed_.notify_all();
  }
}

}  // namespace aovar::trace
