#include "measure/gbuffer_export.h"

#include <stdexcept>

#include <fmt/format.h>

#include "compile/generate.h"
#include "render/backend.h"
#include "runner/variant_runner.h"
#include "scene/scene.h"

namespace aovar::measure {

render::GbufferImage export_gbuffer(const GbufferRequest& r) {
  const std::string backend = render::backend_for(variants::Target::vulkan);
  compile::CompileOptions co{r.scope};
  co.scope.targets = {variants::Target::vulkan};
  co.globs = {r.variant};
  const compile::CompiledSpace c = compile::compile_space(co);
  const int variant = runner::find_variant(c, r.variant);
  if (variant < 0)
    throw std::runtime_error(fmt::format("--variant {}: no such variant in {} (aovar list shows the keys)", r.variant,
                                         r.scope.manifest.path().string()));
  if (!c.ok()) throw std::runtime_error(fmt::format("--variant {}: {}", r.variant, c.diagnostics.front()));

  scene::LoadOptions load;
  load.views_file = r.views_file;
  const scene::Scene scene = scene::load_scene(r.scene, load);
  const scene::View& view = r.view.empty() ? scene.views.front() : scene.view(r.view);
  const float radius = r.radius > 0 ? r.radius : scene.ao_radius;

  runner::RunnerOptions ro;
  ro.backend = backend;
  ro.size = r.size;
  ro.device.threads = r.scope.threads;
  ro.device.device = r.device;
  runner::VariantRunner run(c, ro);
  run.use_scene(scene);
  const render::PipelinePlan plan = run.plan(variant);
  auto pipeline = run.prepare(plan);
  run.render_still(*pipeline, plan, view, radius);

  render::GbufferImage image;
  image.size = r.size;
  // Frame 0 of the still with the AO pass at full resolution: docs/template-contract.md says how a variant at
  // another resolution and frame changes it.
  image.frame = render::make_frame_block({&view, 0, true, radius}, r.size, r.size, run.backend().clip_depth());
  image.planes = run.backend().read_gbuffer(*pipeline);
  return image;
}

}  // namespace aovar::measure
