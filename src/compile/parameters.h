#pragma once
// A variant's parameters as it runs: every manifest parameter its passes take, with the value it was scored
// with. The renderer (runner/) and the generated library (emit_cpp.cpp) both take them from here, so what
// ships is what was scored.
#include <string>
#include <vector>

#include "compile/generate.h"
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

}  // namespace aovar::compile
