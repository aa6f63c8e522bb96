#include "trace/trace_set.h"

#include <algorithm>
#include <set>

#include <fmt/format.h>

#include "compile/spirv_fingerprint.h"

namespace aovar::trace {

TraceSet::TraceSet(runner::VariantRunner& runner, const scene::View& view, float radius, TraceOptions options)
    : runner_(runner), view_(view), radius_(radius), options_(std::move(options)) {
  options_.draws.clear();
}

std::string TraceSet::draw_key(const render::PipelinePlan& plan, int draw) {
  const render::Draw& d = plan.draws.at(draw);
  std::string key = fmt::format("{}|{}|{}|{}|{}", compile::executable_fingerprint(plan.shaders.at(d.fragment).spirv,
                                                                                  compile::relaxed_precision_only()),
                                d.full_resolution ? "full" : "ao", d.level, render::depth_use_name(d.depth),
                                plan.resolution);
  for (float p : d.params) key += fmt::format("|{}", p);  // e.g. the separable blur's axis
  for (const auto& [binding, ref] : d.inputs) {
    const render::Texture& t = plan.textures.at(ref.texture);
    key += fmt::format("|{}:{}:{}:{}:{}", binding, render::format_name(t.format), t.full_resolution ? "full" : "ao",
                       t.levels, ref.level);
  }
  return key;
}

std::vector<std::pair<std::string, std::string>> TraceSet::draws_of(int variant) const {
  return draws_of(runner_.plan(variant));
}

std::vector<std::pair<std::string, std::string>> TraceSet::draws_of(const render::PipelinePlan& plan) {
  std::vector<std::pair<std::string, std::string>> out;
  for (int i : traceable_draws(plan)) out.emplace_back(draw_key(plan, i), plan.draws[i].pass);
  return out;
}

std::vector<const gpu::FetchTrace*> TraceSet::of(int variant) {
  std::vector<const gpu::FetchTrace*> out;
  for (const auto& [key, trace] : keyed(variant))
    if (trace) out.push_back(trace);
  return out;
}

std::vector<std::pair<std::string, const gpu::FetchTrace*>> TraceSet::keyed(int variant,
                                                                            const std::set<std::string>& skip) {
  const render::PipelinePlan plan = runner_.plan(variant);
  std::vector<std::string> keys;
  TraceOptions missing = options_;
  std::set<std::string> missing_keys;  // two draws of one plan with one key (none today): trace the first
  for (int i : traceable_draws(plan)) {
    std::string key = draw_key(plan, i);
    if (skip.count(key)) continue;
    if (traces_.count(key) == 0 && missing_keys.insert(key).second) missing.draws.push_back(i);
    keys.push_back(std::move(key));
  }
  shared_ += static_cast<int>(keys.size() - missing.draws.size());
  if (!missing.draws.empty()) {
    std::vector<gpu::FetchTrace> fresh = trace_variant(runner_, variant, view_, radius_, missing);
    // One trace per traced draw the prepared plan kept (render::plan_for_size drops draws into missing levels).
    for (gpu::FetchTrace& t : fresh)
      traces_[draw_key(plan, t.plan_draw)] = std::make_unique<gpu::FetchTrace>(std::move(t));
    traced_ += static_cast<int>(fresh.size());
  }
  std::vector<std::pair<std::string, const gpu::FetchTrace*>> out;
  for (const std::string& k : keys) {
    auto it = traces_.find(k);
    out.emplace_back(k, it != traces_.end() ? it->second.get() : nullptr);
  }
  return out;
}

std::unique_ptr<gpu::FetchTrace> TraceSet::take(const std::string& key) {
  auto it = traces_.find(key);
  if (it == traces_.end()) return nullptr;
  std::unique_ptr<gpu::FetchTrace> out = std::move(it->second);
  traces_.erase(it);
  return out;
}

}  // namespace aovar::trace
