#include "runner/variant_runner.h"

#include <cmath>

#include "compile/parameters.h"

namespace aovar::runner {

VariantRunner::VariantRunner(const compile::CompiledSpace& compiled, RunnerOptions options)
    : compiled_(compiled), options_(std::move(options)), target_(render::target_of(options_.backend)),
      backend_(render::make_backend(options_.backend, options_.device)) {}

void VariantRunner::use_scene(const scene::Scene& scene) {
  if (scene_ == &scene) return;
  backend_->set_scene(scene);
  scene_ = &scene;
}

render::PipelinePlan plan_variant(const compile::CompiledSpace& compiled, int variant, variants::Target target,
                                  const variants::CalibratedValues& calibration,
                                  const render::ParamOverrides& overrides, bool strict) {
  render::ParamOverrides values = overrides;
  if (const auto* calibrated = compile::calibrated_for(compiled, variant, calibration))
    values.insert(calibrated->begin(), calibrated->end());  // keeps the caller's
  return render::plan_pipeline(compiled, variant, target, values, strict);
}

render::PipelinePlan VariantRunner::plan(int variant, const render::ParamOverrides& overrides, bool strict) const {
  return plan_variant(compiled_, variant, target_, options_.calibration, overrides, strict);
}

std::unique_ptr<render::PreparedPipeline> VariantRunner::prepare(const render::PipelinePlan& plan) {
  return backend_->prepare(plan, options_.size);
}

Still VariantRunner::read(render::PreparedPipeline& pipeline) {
  Still s;
  s.image = backend_->read_result(pipeline);
  s.health = image::health(s.image);
  double sum = 0;
  for (float v : s.image.pixels) sum += std::isfinite(v) ? v : 0.0f;
  s.mean_visibility = s.image.pixels.empty() ? 0 : sum / static_cast<double>(s.image.pixels.size());
  return s;
}

Still VariantRunner::render_still(render::PreparedPipeline& pipeline, const render::PipelinePlan& plan,
                                  const scene::View& view, float radius) {
  for (int f = 0; f < (plan.progressive ? 2 : 1); ++f) backend_->render(pipeline, {&view, f, true, radius});
  return read(pipeline);
}

std::vector<image::FloatImage> VariantRunner::render_path(render::PreparedPipeline& pipeline, const scene::View& view,
                                                          float radius, int first, int count) {
  std::vector<image::FloatImage> frames;
  for (int f = 0; f < first + count; ++f) {
    backend_->render(pipeline, {&view, f, false, radius});
    if (f >= first) frames.push_back(backend_->read_result(pipeline));
  }
  return frames;
}

int find_variant(const compile::CompiledSpace& compiled, const std::string& key) {
  for (std::size_t i = 0; i < compiled.space.variants.size(); ++i)
    if (compiled.space.variants[i].key == key) return static_cast<int>(i);
  return -1;
}

}  // namespace aovar::runner
