#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "util/in_order.h"

namespace aovar::test {
namespace {

// Items finish out of order (the even ones sleep), yet emit sees 0, 1, 2, ... on the calling thread, each after
// its own work, with item i on worker i % workers.
TEST(InOrder, EmitsInItemOrderOnTheCallingThreadWithEachItemOnItsWorker) {
  for (std::size_t workers : {1u, 2u, 3u}) {
    const std::size_t items = 11;
    std::mutex m;
    std::vector<int> worked(items, -1);
    std::vector<std::size_t> emitted;
    std::vector<std::thread::id> worker_thread(workers);
    const auto caller = std::this_thread::get_id();
    util::run_in_order(
        items, workers,
        [&](std::size_t w, std::size_t i) {
          if (i % 2 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(3));
          std::lock_guard lock(m);
          worked[i] = static_cast<int>(w);
          if (i < workers) worker_thread[w] = std::this_thread::get_id();
          EXPECT_EQ(worker_thread[w], std::this_thread::get_id()) << "worker " << w << " moved threads";
        },
        [&](std::size_t i) {
          EXPECT_EQ(std::this_thread::get_id(), caller);
          std::lock_guard lock(m);
          EXPECT_EQ(worked[i], static_cast<int>(i % workers)) << "item " << i << " not worked before its emit";
          emitted.push_back(i);
        });
    ASSERT_EQ(emitted.size(), items) << workers << " workers";
    for (std::size_t i = 0; i < items; ++i) EXPECT_EQ(emitted[i], i) << workers << " workers";
  }
}

// A worker starts item i only once fewer than `workers` items before it wait for their emit (i < emitted +
// workers), however slow the emits: with 2 workers, at most 1 item beyond the next to emit.
TEST(InOrder, WorkersWaitForTheEmitsToCatchUp) {
  std::atomic<std::size_t> emitted{0};
  std::atomic<std::size_t> furthest_ahead{0};
  util::run_in_order(
      20, 2,
      [&](std::size_t, std::size_t i) {
        const std::size_t ahead = i - emitted.load();
        if (ahead > furthest_ahead) furthest_ahead = ahead;
      },
      [&](std::size_t) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        ++emitted;
      });
  EXPECT_EQ(emitted.load(), 20u);
  EXPECT_LE(furthest_ahead.load(), 1u);
  EXPECT_GE(furthest_ahead.load(), 1u) << "the second worker ran beside the first";
}

// A failed work stops the rest: its exception reaches the caller, and neither it nor any later item is emitted.
TEST(InOrder, AFailedItemIsRethrownAndNothingFromItOnIsEmitted) {
  for (std::size_t workers : {1u, 2u}) {
    std::vector<std::size_t> emitted;
    EXPECT_THROW(util::run_in_order(
                     10, workers,
                     [&](std::size_t, std::size_t i) {
                       if (i == 5) throw std::runtime_error("item 5 failed");
                     },
                     [&](std::size_t i) { emitted.push_back(i); }),
                 std::runtime_error);
    ASSERT_LE(emitted.size(), 5u) << workers << " workers";
    for (std::size_t i = 0; i < emitted.size(); ++i) EXPECT_EQ(emitted[i], i);
  }
  // An emit that throws stops the workers too.
  std::atomic<std::size_t> worked{0};
  EXPECT_THROW(util::run_in_order(
                   100, 2, [&](std::size_t, std::size_t) { ++worked; },
                   [&](std::size_t i) {
                     if (i == 3) throw std::runtime_error("emit 3 failed");
                   }),
               std::runtime_error);
  EXPECT_LE(worked.load(), 5u) << "workers went on after the emit failed (items 0 to 4 may start before it)";
}

}  // namespace
}  // namespace aovar::test
