#pragma once
// `aovar ship`'s second step: every method's parameters fitted on the scene's training views (calibrate),
// the held-out views apart, into OUT/calibration.json. Read back instead of refitted while its inputs are the
// same (OUT/ship.json records them); a join adopts its shards' fit of the same inputs.
#include <map>
#include <string>

#include "calibrate/calibrate.h"
#include "render/plan.h"
#include "scene/scene.h"
#include "ship/ship.h"
#include "table/table.h"
#include "variants/manifest.h"

namespace aovar::ship {

struct Fitted {
  table::CalibrationRef calibration;  // OUT/calibration.json: where, its hash and the fitted values
  std::string inputs;  // hash of what the fit depends on (manifest, scene, views, normals, sizes, budget)
  bool reused = false;
};

// `normals`: "depth" or "buffer", what the fit renders normals from (the profile's lean decides).
Fitted fit_methods(const ShipOptions& options, const scene::Scene& scene, const calibrate::ViewSplit& split,
                   const std::string& normals, const variants::Manifest& manifest, const Progress& progress);

}  // namespace aovar::ship
