#pragma once
// What each pass of a variant asks of a GPU per frame, read off its render plan (render/plan.h), so the
// draw counts and pixel shares are the renderer's own: the separable blur's two draws, SAO's z pyramid
// (one draw per MIP level, each a quarter of the last), AO-resolution passes at resolution², the upsample
// at full resolution.
#include <map>
#include <string>
#include <vector>

#include "analyze/analyze.h"

#include "gpu/roofline.h"
#include "render/plan.h"

namespace aovar::gpu {

// One entry per pass (render::PipelinePlan::passes order, the G-buffer included): draws, mean pixel share
// per draw, and per shaded pixel the fragment program's texture fetches (SPIR-V analyser, as
// sweep/static_costs.cpp counts them) and bytes (fetches x the variant's texel sizes, plus the bytes of
// the draw's colour outputs).
// `analysed`: SPIR-V analyses by program key, shared across the variants of one space (most programs are
// in many variants); filled as programs are first seen.
std::vector<PassLoad> pass_loads(const render::PipelinePlan& plan,
                                 std::map<std::string, analyze::ProgramCost>& analysed);

}  // namespace aovar::gpu
