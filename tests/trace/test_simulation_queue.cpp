// trace::SimulationQueue: simulations on a worker give what gpu::simulate gives in line, each into its own
// result, a bad trace's exception comes out of finish(), and a queue destroyed with work left stops after the
// simulation it runs (each result whole or untouched).
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <vector>

#include "gpu/cache_sim.h"
#include "trace/simulation_queue.h"

namespace aovar {
namespace {

gpu::CacheHierarchy two_levels() {
  gpu::CacheLevelSpec l1{}, l2{};
  l1.name = "L1", l1.scope = gpu::CacheScope::cu, l1.size_bytes = 4096, l1.line_bytes = 64, l1.ways = 4;
  l2.name = "L2", l2.scope = gpu::CacheScope::chip, l2.size_bytes = 65536, l2.line_bytes = 128, l2.ways = 16;
  l1.bytes_per_clock = l2.bytes_per_clock = 64;
  return {"test", 32, 4, 2, {l1, l2}};
}

// `w` x 32 pixels, each reading 5 texels of a 256x256 4-byte texture along a stride set by `seed`.
std::shared_ptr<const gpu::FetchTrace> strided_trace(int w, int seed) {
  auto t = std::make_shared<gpu::FetchTrace>();
  t->pass = "ao";
  t->frame_width = t->width = w;
  t->frame_height = t->height = 32;
  t->max_taps = 5;
  t->textures = {{"ao_depth_tex", 0, 256, 256, 1, 4}};
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < w; ++x)
      for (int tap = 0; tap < 5; ++tap)
        t->reads.push_back(gpu::pack_read({0, 0, (x * seed + tap * 29) % 256, (y * 3 + tap * seed) % 256}));
  return t;
}

void expect_same(const gpu::CacheSimResult& a, const gpu::CacheSimResult& b) {
  EXPECT_EQ(a.reads, b.reads);
  EXPECT_EQ(a.dram_bytes, b.dram_bytes);
  ASSERT_EQ(a.levels.size(), b.levels.size());
  for (std::size_t i = 0; i < a.levels.size(); ++i) {
    EXPECT_EQ(a.levels[i].accesses, b.levels[i].accesses);
    EXPECT_EQ(a.levels[i].hits, b.levels[i].hits);
    EXPECT_EQ(a.levels[i].unique_lines, b.levels[i].unique_lines);
  }
}

TEST(SimulationQueue, GivesEachResultWhatSimulatingInLineGives) {
  std::vector<std::shared_ptr<const gpu::FetchTrace>> traces;
  for (int seed = 1; seed <= 6; ++seed) traces.push_back(strided_trace(16 * seed, seed * 7));
  std::vector<gpu::CacheSimResult> queued(traces.size());
  trace::SimulationQueue queue;
  for (std::size_t i = 0; i < traces.size(); ++i) queue.add(traces[i], two_levels(), &queued[i]);
  EXPECT_GE(queue.finish(), 0.0);
  for (std::size_t i = 0; i < traces.size(); ++i) {
    SCOPED_TRACE(i);
    const gpu::CacheSimResult inline_result = gpu::simulate(*traces[i], two_levels());
    EXPECT_GT(inline_result.levels.at(0).misses(), 0);
    expect_same(queued[i], inline_result);
  }
  // A second round on the same queue.
  gpu::CacheSimResult again;
  queue.add(traces[2], two_levels(), &again);
  queue.finish();
  expect_same(again, queued[2]);
}

TEST(SimulationQueue, ABadTraceThrowsFromFinish) {
  auto bad = std::make_shared<gpu::FetchTrace>(*strided_trace(16, 3));
  bad->reads.pop_back();  // one read short of width x height x taps
  gpu::CacheSimResult good_result, bad_result;
  trace::SimulationQueue queue;
  queue.add(strided_trace(16, 5), two_levels(), &good_result);
  queue.add(bad, two_levels(), &bad_result);
  EXPECT_THROW(queue.finish(), std::invalid_argument);
  EXPECT_EQ(good_result.reads, 16 * 32 * 5);
  EXPECT_NO_THROW(queue.finish());  // the error was handed out once
}

TEST(SimulationQueue, DestroyedWithWorkLeftItStops) {
  std::vector<gpu::CacheSimResult> results(50);
  {
    trace::SimulationQueue queue;
    for (auto& r : results) queue.add(strided_trace(256, 11), two_levels(), &r);
  }  // joins the running simulation and drops the queued ones
  for (const auto& r : results) EXPECT_TRUE(r.reads == 0 || r.reads == 256 * 32 * 5) << r.reads;
}

}  // namespace
}  // namespace aovar
