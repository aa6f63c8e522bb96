#pragma once
// A variant's parameters as it runs: every manifest parameter its passes take, with the value it was scored
// with. The renderer (runner/) and the generated library (emit_cpp.cpp) both take them from here, so what
// ships is what was scored.
#include <set>
#include <string>
#include <vector>

#include "compile/generate.h"
#include "passplan/plan.h"
#include "variants/manifest.h"

namespace aovar::compile {

struct VariantParam {
  std::string key;  // "<pass>.<name>" ("ao.intensity")
  double value = 0;             // the calibrated value where `values` has one, else the manifest's
  double manifest_default = 0;  // the manifest's value, always
  double min = 0, max = 0;
};

// The calibrated values that apply to variant `variant` (an index into c.space.variants): its key's entry,
// else its algorithm's, else none (nullptr).
const variants::ParamValues* calibrated_for(const CompiledSpace& c, int variant, const variants::CalibratedValues& values);

// Each parameter of the variant's passes, in pass order then the program's order (vertex, fragment).
std::vector<VariantParam> variant_params(const CompiledSpace& c, int variant, const variants::CalibratedValues& values);

// The AOParams block of `program` (an index into c.space.programs) on target index `t`, as a draw of manifest
// pass `pass` uploads it: every member in the block's order (std140: consecutive floats). A manifest parameter
// takes `values`' "<pass>.<name>" where it has one, else its manifest value; a member the renderer sets takes the
// draw's uniform of that name (passplan::PassDraw::uniforms). Each parameter key is added to `used` when given.
// Throws std::runtime_error for a member that is neither. The renderer's plan (render::plan_pipeline) and the
// generated library's plan (emit_plan.cpp) both fill their blocks here.
std::vector<float> block_values(const CompiledSpace& c, int t, int program, const std::string& pass,
                                const variants::ParamValues& values, const std::vector<passplan::Uniform>& uniforms,
                                std::set<std::string>* used = nullptr);

}  // namespace aovar::compile
