#pragma once
// The one variant runner: what measure, stress, calibrate and profile share between a compiled selection
// and an image. It owns a backend (any in render/registry.cpp, with the programs of that backend's target), keeps
// the scene uploaded, plans variants with their algorithm's calibrated parameters and the caller's
// overrides, prepares them, renders a still frame or a camera path, reads the result back with its health,
// and scores it against a ray-traced reference. Timing stays with its caller (measure/timing.h interleaves
// many prepared pipelines on backend()).
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "compile/generate.h"
#include "image/health.h"
#include "metrics/metrics.h"
#include "reference/reference.h"
#include "render/backend.h"
#include "runner/score.h"  // score(): scoring an image read back

namespace aovar::runner {

struct RunnerOptions {
  std::string backend = render::default_backend();  // render::backend_names()
  render::BackendOptions device;     // threads, validation, mediump as fp16
  render::Extent size{640, 360};     // output size every prepared pipeline renders at
  // Calibrated parameter values by variant key or algorithm name (aovar calibrate; a variant's entry wins
  // over its algorithm's); a plan's overrides win over both.
  variants::CalibratedValues calibration;
};

// An AO result read back, with its NaN / Inf / out-of-range counts over every pixel.
struct Still {
  image::FloatImage image;
  image::Health health;
  double mean_visibility = 0;  // mean of the finite pixels (0 for an empty image)
};

// The plan of `variant` (index into compiled.space.variants) for `target`, as VariantRunner::plan makes it:
// its calibrated values from `calibration`, then `overrides` on top. Needs no backend.
render::PipelinePlan plan_variant(const compile::CompiledSpace& compiled, int variant, variants::Target target,
                                  const variants::CalibratedValues& calibration,
                                  const render::ParamOverrides& overrides = {}, bool strict = false);

class VariantRunner {
 public:
  // `compiled` must hold successful builds for the backend's target and outlive the runner. Throws
  // render::BackendError (unknown backend, missing driver) with what to do.
  VariantRunner(const compile::CompiledSpace& compiled, RunnerOptions options);

  render::Backend& backend() { return *backend_; }
  const render::DeviceInfo& device() const { return backend_->info(); }
  variants::Target target() const { return target_; }
  const compile::CompiledSpace& compiled() const { return compiled_; }
  render::Extent size() const { return options_.size; }

  // Uploads the scene unless it is the one already uploaded (by address).
  void use_scene(const scene::Scene& scene);

  // Variant `variant`'s plan (index into compiled().space.variants): its algorithm's calibrated values,
  // then `overrides` on top; `strict` as render::plan_pipeline.
  render::PipelinePlan plan(int variant, const render::ParamOverrides& overrides = {}, bool strict = false) const;
  std::unique_ptr<render::PreparedPipeline> prepare(const render::PipelinePlan& plan);

  // A still image on a static camera: progressive plans render frames 0 and 1 (the second combines both
  // halves), others frame 0. Throws render::BackendError when the driver fails.
  Still render_still(render::PreparedPipeline& pipeline, const render::PipelinePlan& plan, const scene::View& view,
                     float radius);
  // Frames along the view's camera path: renders frames 0 .. first + count - 1 and returns the last
  // `count` of them (first = 1 gives a progressive variant its history before the first kept frame).
  std::vector<image::FloatImage> render_path(render::PreparedPipeline& pipeline, const scene::View& view, float radius,
                                             int first, int count);
  // Reads the last rendered frame back.
  Still read(render::PreparedPipeline& pipeline);

 private:
  const compile::CompiledSpace& compiled_;
  RunnerOptions options_;
  variants::Target target_;
  std::unique_ptr<render::Backend> backend_;
  const scene::Scene* scene_ = nullptr;
};

// Index of the variant with this key in compiled.space.variants, -1 when the selection does not hold it.
int find_variant(const compile::CompiledSpace& compiled, const std::string& key);


}  // namespace aovar::runner
