// The pass plan in the C++ embedding (compile/emit_plan.cpp): its parameter blocks are the ones the renderer
// uploads, with the variant's fitted values (issue 53).
#include <gtest/gtest.h>

#include <string>

#include "compile/generate.h"
#include "render/plan.h"
#include "render_support.h"
#include "test_support.h"
#include "util/cpp_literal.h"

namespace aovar::test {
namespace {

// The initializer of a `const float kBlockValues_<n>[]` array holding `values`.
std::string block_array_text(const std::vector<float>& values) {
  std::string init;
  for (float v : values) init += " " + util::cpp_float_literal(v) + ",";
  return "[] = {" + init + " };";
}

TEST(EmitPlan, BlocksCarryTheFittedValuesTheRendererUploads) {
  const auto c = compile_variants({"alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp"}, {variants::Target::vulkan});
  const variants::CalibratedValues fitted = {{"alchemy", {{"ao.intensity", 0.625}, {"ao.contrast", 1.25}}}};
  const std::string with_fit = compile::cpp_embedding(c, "fitted_shaders", {}, fitted).second;
  const std::string without = compile::cpp_embedding(c, "plain_shaders").second;
  const render::PipelinePlan scored = render::plan_pipeline(c, 0, variants::Target::vulkan, fitted.at("alchemy"));
  const render::PipelinePlan plain = render::plan_pipeline(c, 0, variants::Target::vulkan);
  for (std::size_t d = 0; d < scored.draws.size(); ++d) {
    if (scored.draws[d].params.empty()) continue;
    EXPECT_NE(with_fit.find(block_array_text(scored.draws[d].params)), std::string::npos) << scored.draws[d].name;
    EXPECT_NE(without.find(block_array_text(plain.draws[d].params)), std::string::npos) << plain.draws[d].name;
    if (scored.draws[d].name == "ao") {
      EXPECT_NE(scored.draws[d].params, plain.draws[d].params) << "the fit changes the ao block";
      EXPECT_EQ(without.find(block_array_text(scored.draws[d].params)), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace aovar::test
