// The timed rounds on a shared G-buffer (measure/timing.h, render/gbuffer_share.h): each round draws every
// G-buffer its pipelines read once, and every frame of that round reports that draw's time.
#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <string>
#include <vector>

#include "measure/timing.h"
#include "render/backend.h"
#include "render_support.h"

namespace aovar::test {
namespace {

// [0] and [1] draw the same G-buffer (rg8 normals, depth, r32f), [2] another (rgb8 normals).
const std::vector<std::string> kRoundKeys = {backend_test_keys()[0], backend_test_keys()[5], backend_test_keys()[1]};
const CompiledVariants kRoundVariants(kRoundKeys);

TEST(TimedRounds, EachRoundDrawsEveryGbufferOnceAndItsFramesShareThatDraw) {
  const scene::View view = box_view();
  auto backend = render::make_backend("lavapipe", {});
  backend->set_scene(box_on_floor());
  std::vector<std::unique_ptr<render::PreparedPipeline>> owned;
  std::vector<render::PreparedPipeline*> pipelines;
  for (const auto& key : kRoundKeys) {
    owned.push_back(backend->prepare(kRoundVariants.plan(key, "lavapipe"), {96, 54}));
    pipelines.push_back(owned.back().get());
  }
  measure::TimingOptions o;
  o.warmup = 1;
  o.reps = 5;
  o.radius = kBoxRadius;
  measure::RoundRobinResult r = measure::warm_up(*backend, pipelines, view, o, nullptr);
  EXPECT_EQ(backend->gbuffer_draws(), 2u) << "the warm-up draws each G-buffer once: the camera stands still";
  measure::time_rounds(*backend, pipelines, view, o, r);
  EXPECT_EQ(backend->gbuffer_draws(), 2u + 2u + 2u * o.reps)
      << "then once each in the warm-up's untimed round shaped like the timed ones, and once a round each";
  for (const auto& t : r.pipelines) EXPECT_EQ(t.total_ms.size(), static_cast<std::size_t>(o.reps)) << "the untimed round records nothing";
  std::set<double> samples;
  for (int round = 0; round < o.reps; ++round) {
    SCOPED_TRACE(round);
    const double shared = r.pipelines[0].draw_ms.at(round).at(0);  // draw 0: the G-buffer
    EXPECT_GT(shared, 0.0);
    EXPECT_EQ(r.pipelines[1].draw_ms.at(round).at(0), shared) << "one G-buffer, one sample a round";
    EXPECT_NE(r.pipelines[2].draw_ms.at(round).at(0), shared) << "another format, drawn apart";
    samples.insert(shared);
  }
  EXPECT_GT(samples.size(), 1u) << "drawn again each round, not one draw's time reported throughout";
}

}  // namespace
}  // namespace aovar::test
