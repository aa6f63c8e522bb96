#include "measure/timing.h"

#include <chrono>
#include <numeric>

#include <fmt/format.h>

#include "util/clock.h"

namespace aovar::measure {
namespace {

using util::seconds_since;

render::FrameSetup setup(const scene::View& view, int frame, const TimingOptions& o) {
  render::FrameSetup s;
  s.view = &view;
  s.frame = frame;
  s.static_camera = !o.camera_path;  // progressive parity alternates either way
  s.radius = o.radius;
  return s;
}

}  // namespace

RoundRobinResult time_round_robin(render::Backend& backend, const std::vector<render::PreparedPipeline*>& pipelines,
                                  const scene::View& view, const TimingOptions& o, const Progress& progress) {
  RoundRobinResult r;
  r.pipelines.resize(pipelines.size());
  auto start = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < pipelines.size(); ++i) {
    PipelineTiming& t = r.pipelines[i];
    auto ms = backend.render(*pipelines[i], setup(view, t.frames++, o));
    t.first_frame_ms = std::accumulate(ms.begin(), ms.end(), 0.0);
    for (int w = 0; w < o.warmup; ++w) backend.render(*pipelines[i], setup(view, t.frames++, o));
  }
  r.wall_warmup_s = seconds_since(start);

  start = std::chrono::steady_clock::now();
  std::size_t n = pipelines.size();
  for (int round = 0; round < o.reps; ++round) {
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t i = (k + static_cast<std::size_t>(round)) % n;  // rotate the order every round
      PipelineTiming& t = r.pipelines[i];
      auto ms = backend.render(*pipelines[i], setup(view, t.frames++, o));
      double total = std::accumulate(ms.begin(), ms.end(), 0.0);
      t.total_ms.push_back(total);
      t.draw_ms.push_back(std::move(ms));
      r.sum_timed_s += total / 1000.0;
    }
    if (progress) progress(fmt::format("round {}/{}", round + 1, o.reps));
  }
  r.wall_timed_s = seconds_since(start);
  return r;
}

std::vector<std::pair<std::string, util::TimeStats>> pass_stats(const render::PipelinePlan& plan, const PipelineTiming& t) {
  std::vector<std::pair<std::string, util::TimeStats>> out;
  for (const auto& pass : plan.passes()) {
    std::vector<double> samples;
    for (const auto& round : t.draw_ms) {
      double sum = 0;
      for (std::size_t d = 0; d < plan.draws.size() && d < round.size(); ++d)
        if (plan.draws[d].pass == pass) sum += round[d];
      samples.push_back(sum);
    }
    out.emplace_back(pass, util::summarize(std::move(samples)));
  }
  return out;
}

double median_ratio(const PipelineTiming& t, const PipelineTiming& reference) {
  std::vector<double> ratios;
  for (std::size_t i = 0; i < t.total_ms.size() && i < reference.total_ms.size(); ++i)
    if (reference.total_ms[i] > 0) ratios.push_back(t.total_ms[i] / reference.total_ms[i]);
  return util::summarize(std::move(ratios)).median;
}

}  // namespace aovar::measure
