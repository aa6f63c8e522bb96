// measure_scene (measure.h): what `aovar measure` runs, one call: the checks, the profile's pruning, the
// measurement and the GPU estimate on its rows.
#include <memory>

#include "measure/measure.h"
#include "scene/scene.h"
#include "util/fs.h"

namespace aovar::measure {

namespace {

// The rows estimated on each GPU (as sweep --gpu does), then measure.json written again with them.
void estimate_rows_on_gpu(MeasureResult& res, const MeasureOptions& o, const trace::GpuEstimateOptions& gpu,
                          const Progress& progress) {
  std::vector<table::CostRow*> rows;
  for (auto& r : res.rows) rows.push_back(&r);
  res.gpu_meta = trace::add_gpu_costs(rows, gpu_request(o, gpu), [&](const std::string& line) {
                   if (progress) progress(line);
                 }).to_json();
  if (!o.out.empty()) util::write_atomic(o.out / "measure.json", to_json(res, o).dump(1) + "\n");
}

}  // namespace

MeasureResult measure_scene(const MeasureSceneOptions& options, const Progress& progress) {
  MeasureOptions o = options.measure;
  gpu::check_gpus(options.gpu.families);  // an unknown GPU fails before anything is measured
  check_request(o);              // so does a bad --param, before the profile
  if (options.prune_by_profile) {
    scene::LoadOptions load;
    load.views_file = o.views_file;
    o.pruning = prune_by_profile(o, scene::load_scene(o.scene, load), o.globs, progress);
  }
  MeasureResult res = run_measure(o, progress);
  if (!options.gpu.families.empty()) estimate_rows_on_gpu(res, o, options.gpu, progress);
  return res;
}

}  // namespace aovar::measure
