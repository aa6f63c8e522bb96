#pragma once
// The pass plan in the C++ embedding (emit_plan.cpp; docs/template-contract.md, "The pass plan"): each variant's
// passes as data an engine runs without aovar.
#include <string>
#include <vector>

#include "compile/array_pool.h"
#include "variants/manifest.h"

namespace aovar::compile {

struct CompiledSpace;

// The header's plan types, the frame-size rules (ao_extent, mip_levels_at, draw_runs_at) and the AOFrame
// layout; after the manifest's enums (it names Pass), before Variant (which points to a Plan).
std::string plan_header_types();

// Each variant's plan, its arrays appended through `pool` (equal arrays shared between variants). Returns per
// variant the initializer of its Variant::plan: a plan array's name, or "nullptr" when no target compiled all
// of its programs. Block values are the variant's: `values`' fitted ones (calibrated_for), else the manifest's.
// Throws std::runtime_error when two targets disagree on a program's AOParams layout.
std::vector<std::string> append_plans(ArrayPool& pool, const CompiledSpace& c, const variants::CalibratedValues& values);

}  // namespace aovar::compile
