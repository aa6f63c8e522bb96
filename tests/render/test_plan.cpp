// Pipeline plans (src/render/plan.h) without a backend: what the single-frame form of a progressive plan reads.
#include <gtest/gtest.h>

#include <map>

#include "compile/generate.h"
#include "render/plan.h"
#include "test_support.h"

namespace aovar::test {
namespace {

TEST(Plan, SingleFramePlanReadsThisFramesHalfTwice) {
  compile::CompileOptions co;
  co.scope.targets = {variants::Target::vulkan};
  co.globs = {"alchemy-s16-p[01]-nrgb8-zdep-rst-d32-bsep-x1-hp"};
  auto c = compile::compile_space(aovar::test::on_manifest(co, source_dir() / "shader_src" / "aovar.toml"));
  ASSERT_TRUE(c.ok());
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    auto plan = render::plan_pipeline(c, static_cast<int>(v), variants::Target::vulkan);
    auto one = render::plan_single_frame(plan);
    ASSERT_EQ(one.draws.size(), plan.draws.size());
    for (std::size_t d = 0; d < plan.draws.size(); ++d) {
      if (plan.draws[d].name != "progressive") {
        EXPECT_EQ(one.draws[d].inputs.size(), plan.draws[d].inputs.size());
        continue;
      }
      std::map<int, render::TextureRef> in(one.draws[d].inputs.begin(), one.draws[d].inputs.end());
      EXPECT_EQ(in.at(5).texture, in.at(6).texture);
      EXPECT_FALSE(in.at(6).previous) << "no history";
    }
  }
}

}  // namespace
}  // namespace aovar::test
