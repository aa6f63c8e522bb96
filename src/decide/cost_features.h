#pragma once
// The cost model's static features (sweep fits them per scene, view and backend): what of a row's typed
// static cost (static_cost.h) and axes predicts its time. Rows without a static cost give zeros.
#include "decide/cost_model.h"

namespace aovar::decide {

// The AO pass's fetches, ALU and transcendentals, the passes' ALU and fetches, the work per pixel.
FeatureSpec static_features();

// For small tables: six features that carry the cost structure of a pipeline — the static work per output
// pixel of all fullscreen passes, the AO pass's reads scaled by the pixels it runs on, those pixels, and
// which blur and progressive passes run.
FeatureSpec compact_features();

// Instruction classes weighted by the pixels each pass covers: AO pass and the other passes apart, and the
// AO pass's reads of the G-buffer apart from its reads of the prefiltered depth (SAO's z pyramid, unsharp's
// blurred depth), which stay in small, cache-resident levels. On the Vulkan CPU backend every class has its own price (a
// texture read is a JIT-compiled sampler, a transcendental a polynomial, a branch masks SIMD lanes), which
// one sum of counts cannot capture. 13 features.
FeatureSpec weighted_class_features();

}  // namespace aovar::decide
