#include "util/in_order.h"

#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace aovar::util {

void run_in_order(std::size_t items, std::size_t workers, const std::function<void(std::size_t, std::size_t)>& work,
                  const std::function<void(std::size_t)>& emit) {
  if (workers <= 1) {
    for (std::size_t i = 0; i < items; ++i) work(0, i), emit(i);
    return;
  }
  std::mutex m;
  std::condition_variable changed;
  std::vector<char> done(items, 0);
  std::size_t emitted = 0;  // items [0, emitted) handed to emit
  std::exception_ptr failure;
  auto worker = [&](std::size_t w) {
    for (std::size_t i = w; i < items; i += workers) {
      {
        std::unique_lock lock(m);
        changed.wait(lock, [&] { return failure || i < emitted + workers; });
        if (failure) return;
      }
      try {
        work(w, i);
      } catch (...) {  // an exception leaving a std::thread would terminate: hand the first to the caller
        std::lock_guard lock(m);
        if (!failure) failure = std::current_exception();
        changed.notify_all();
        return;
      }
      std::lock_guard lock(m);
      done[i] = 1;
      changed.notify_all();
    }
  };
  std::vector<std::thread> threads;
  threads.reserve(workers);
  for (std::size_t w = 0; w < workers; ++w) threads.emplace_back(worker, w);
  try {
    for (std::size_t i = 0; i < items; ++i) {
      {
        std::unique_lock lock(m);
        changed.wait(lock, [&] { return failure || done[i]; });
        if (failure) break;
      }
      emit(i);  // unlocked: the workers go on meanwhile
      std::lock_guard lock(m);
      emitted = i + 1;
      changed.notify_all();
    }
  } catch (...) {
    std::lock_guard lock(m);
    if (!failure) failure = std::current_exception();
    changed.notify_all();
  }
  for (auto& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace aovar::util
