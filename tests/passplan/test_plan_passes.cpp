// The pass plan from the manifest and the variant space alone (src/passplan): nothing compiled, as in a
// generator-only build.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "passplan/plan.h"
#include "test_support.h"
#include "variants/manifest.h"
#include "variants/space.h"

namespace aovar::test {
namespace {

const passplan::PassDraw* plan_draw(const passplan::PassPlan& p, const std::string& name) {
  auto it = std::find_if(p.draws.begin(), p.draws.end(), [&](const passplan::PassDraw& d) { return d.name == name; });
  return it == p.draws.end() ? nullptr : &*it;
}

int space_index(const variants::VariantSpace& space, const std::string& key) {
  for (std::size_t i = 0; i < space.variants.size(); ++i)
    if (space.variants[i].key == key) return static_cast<int>(i);
  ADD_FAILURE() << key << " is not in the space";
  return 0;
}

// Every variant of the default manifest gets a plan whose draws run programs of theirs, read only textures written
// before them (or the previous frame's copy), and end in the full-resolution r32f result.
TEST(PassPlan, EveryDefaultVariantPlansWithoutCompiling) {
  const variants::Manifest m = variants::load_manifest(source_dir() / "shader_src" / "aovar.toml");
  const variants::VariantSpace space = variants::build_space(m);
  ASSERT_GT(space.variants.size(), 10000u);
  for (std::size_t v = 0; v < space.variants.size(); ++v) {
    const passplan::PassPlan p = passplan::plan_passes(m, space, static_cast<int>(v));
    ASSERT_FALSE(p.draws.empty()) << p.variant;
    std::vector<bool> written(p.textures.size(), false);
    for (const passplan::PassDraw& d : p.draws) {
      ASSERT_GE(d.program_pass, 0) << p.variant << " " << d.name;
      EXPECT_GE(space.variants[v].passes[d.program_pass][1], 0) << p.variant << " " << d.name;
      for (const auto& [binding, in] : d.inputs)
        EXPECT_TRUE(in.previous || written[in.texture]) << p.variant << " " << d.name << " reads " << p.textures[in.texture].name;
      for (const auto& out : d.outputs)
        if (out.texture >= 0) written[out.texture] = true;
    }
    ASSERT_GE(p.result, 0);
    EXPECT_EQ(p.textures[p.result].format, passplan::Format::r32f) << p.variant;
    EXPECT_TRUE(p.textures[p.result].full_resolution) << p.variant;
    EXPECT_EQ(p.draws.back().outputs.at(0).texture, p.result) << p.variant;
  }
}

TEST(PassPlan, PerDrawUniformsAreTheBlurAxisAndThePyramidLevel) {
  const variants::Manifest m = variants::load_manifest(source_dir() / "shader_src" / "aovar.toml");
  const std::string sao_key = "sao-s08-p0-ndep-zdep-rst-d16-bsep-x2-hp";
  const std::string bilateral_key = "alchemy-s08-p0-nrg8-zdep-rst-d16-bbil-x1-hp";
  const variants::VariantSpace space = variants::build_space(m, {sao_key, bilateral_key});
  const passplan::PassPlan sao = passplan::plan_passes(m, space, space_index(space, sao_key));
  for (int level = 0; level < passplan::kZmipLevels; ++level) {
    const passplan::PassDraw* z = plan_draw(sao, "zmip." + std::to_string(level));
    ASSERT_NE(z, nullptr) << level;
    ASSERT_EQ(z->uniforms.size(), 1u);
    EXPECT_EQ(z->uniforms[0].name, "level");
    EXPECT_EQ(z->uniforms[0].value, float(level));
    EXPECT_EQ(z->level, level);
  }
  ASSERT_TRUE(plan_draw(sao, "blur.h") && plan_draw(sao, "blur.v"));
  EXPECT_EQ(plan_draw(sao, "blur.h")->uniforms.at(0).value, 0.0f);
  EXPECT_EQ(plan_draw(sao, "blur.v")->uniforms.at(0).value, 1.0f);
  EXPECT_EQ(m.passes[plan_draw(sao, "blur.v")->program_pass].name, "blur_keyed");
  const passplan::PassPlan bilateral = passplan::plan_passes(m, space, space_index(space, bilateral_key));
  ASSERT_NE(plan_draw(bilateral, "blur"), nullptr);
  EXPECT_TRUE(plan_draw(bilateral, "blur")->uniforms.empty());
}

}  // namespace
}  // namespace aovar::test
