#pragma once
// Items worked on side by side, handed on in order: item i goes to worker i % workers (each worker its own
// resource, a rendering device say, so that item 0 is always worker 0's), and `emit` sees the results on the
// calling thread in item order, each as soon as it and every item before it are done, so a caller can
// checkpoint as it goes. A worker runs at most `workers` items ahead of the last emitted one (memory stays
// bounded). run_parallel (parallel.h) has no order and no per-worker resource: this is for what has both.
#include <cstddef>
#include <functional>

namespace aovar::util {

// Calls work(worker, item) for every item in [0, items) on `workers` threads (1: on the calling thread, no
// thread started), and emit(item) on the calling thread in item order after its work returned. The first
// exception of a work or an emit stops every worker before its next item and is rethrown here; no item after
// a failed one is emitted.
void run_in_order(std::size_t items, std::size_t workers, const std::function<void(std::size_t worker, std::size_t item)>& work,
                  const std::function<void(std::size_t item)>& emit);

}  // namespace aovar::util
