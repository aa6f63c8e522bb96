// The pass plan in the library the CMake step generates (issue 53, point 2): for variants of every plan shape, the
// embedded plan is the plan the renderer runs (render::plan_pipeline), draw by draw, and its frame-size rules drop
// the draws render::plan_for_size drops.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "aovar_default_shaders.h"
#include "compile/generate.h"
#include "render/plan.h"
#include "test_support.h"

namespace {
namespace lib = aovar_default_shaders;
using namespace aovar;

// One variant of each shape: the separable blur's two draws, SAO's z pyramid with its keyed blur at half
// resolution, progressive at half resolution with the upsample, unsharp's depth Gaussian, a depth_mip pyramid
// at quarter resolution, the position buffer.
const std::vector<std::string> kKeys = {
    "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp", "sao-s08-p0-ndep-zdep-rst-d16-bsep-x2-hp",
    "alchemy-s08-p1-nrg8-zdep-rst-d16-bsep-x2-hp", "unsharp-s04-p0-ndep-zdep-_r-d16-bsep-x1-hp",
    "hbao-s08-p0-ndep-zdep-rst-d16-bbil-x4-hp-zmip", "alchemy-s04-p0-ndep-zpos-rip-d16-bbil-x1-hp"};

const compile::CompiledSpace& shapes() {
  static const compile::CompiledSpace c = [] {
    compile::CompileOptions co;
    co.scope.targets = {variants::Target::vulkan};
    co.globs = kKeys;
    return compile::compile_space(test::on_manifest(co, test::source_dir() / "shader_src" / "aovar.toml"));
  }();
  return c;
}

int index_of(const compile::CompiledSpace& c, const std::string& key) {
  for (std::size_t i = 0; i < c.space.variants.size(); ++i)
    if (c.space.variants[i].key == key) return static_cast<int>(i);
  throw std::runtime_error(key + " was not compiled");
}

void expect_same_ref(const lib::TextureRef& embedded, const render::TextureRef& planned, const std::string& where) {
  EXPECT_EQ(embedded.texture, planned.texture) << where;
  EXPECT_EQ(embedded.previous, planned.previous) << where;
  EXPECT_EQ(embedded.level, planned.level) << where;
}

void expect_same_textures(const lib::Plan& e, const render::PipelinePlan& p) {
  ASSERT_EQ(e.texture_count, p.textures.size());
  for (std::size_t i = 0; i < e.texture_count; ++i) {
    const lib::Texture& t = e.textures[i];
    const render::Texture& r = p.textures[i];
    EXPECT_EQ(t.name, r.name);
    EXPECT_STREQ(render::format_name(static_cast<render::Format>(t.format)), render::format_name(r.format)) << r.name;
    EXPECT_EQ(t.full_resolution, r.full_resolution) << r.name;
    EXPECT_EQ(t.double_buffered, r.double_buffered) << r.name;
    EXPECT_EQ(t.cleared, r.cleared) << r.name;
    for (int k = 0; k < 4; ++k) EXPECT_EQ(t.clear[k], r.clear[k]) << r.name;
    EXPECT_EQ(t.levels, r.levels) << r.name;
  }
  ASSERT_EQ(e.depth_buffer_count, p.depth_buffers.size());
  for (std::size_t i = 0; i < e.depth_buffer_count; ++i) {
    EXPECT_EQ(e.depth_buffers[i].name, p.depth_buffers[i].name);
    EXPECT_EQ(e.depth_buffers[i].full_resolution, p.depth_buffers[i].full_resolution);
  }
}

// Draw `e` of the library against the renderer's draw `d`: programs (by their SPIR-V), inputs, outputs, viewport,
// depth use and the AOParams block the renderer uploads.
void expect_same_draw(const lib::Variant& v, const lib::Draw& e, const render::PipelinePlan& p, const render::Draw& d) {
  EXPECT_EQ(e.name, d.name);
  const lib::PassPrograms& programs = lib::programs(v, lib::Target::vulkan, e.pass);
  ASSERT_NE(programs.fragment, nullptr) << d.name;
  const auto& spirv = p.shaders[d.fragment].spirv;
  ASSERT_EQ(programs.fragment->spirv_words, spirv.size()) << d.name;
  EXPECT_EQ(std::memcmp(programs.fragment->spirv, spirv.data(), spirv.size() * 4), 0) << d.name;
  EXPECT_EQ(programs.vertex->spirv_words, p.shaders[d.vertex].spirv.size()) << d.name;
  EXPECT_EQ(e.geometry, d.geometry) << d.name;
  ASSERT_EQ(e.input_count, d.inputs.size()) << d.name;
  for (std::size_t i = 0; i < e.input_count; ++i) {
    EXPECT_EQ(e.inputs[i].binding, d.inputs[i].first) << d.name;
    expect_same_ref(e.inputs[i].texture, d.inputs[i].second, d.name);
  }
  ASSERT_EQ(e.output_count, d.outputs.size()) << d.name;
  for (std::size_t i = 0; i < e.output_count; ++i) expect_same_ref(e.outputs[i], d.outputs[i], d.name);
  EXPECT_EQ(e.full_resolution, d.full_resolution) << d.name;
  EXPECT_EQ(e.level, d.level) << d.name;
  EXPECT_STREQ(render::depth_use_name(static_cast<render::DepthUse>(e.depth)), render::depth_use_name(d.depth)) << d.name;
  EXPECT_EQ(e.depth_buffer, d.depth_buffer) << d.name;
  EXPECT_EQ(std::vector<float>(e.block_values, e.block_values + e.block_size), d.params) << d.name;
}

const float* member(const lib::Draw& d, const char* name) {
  for (std::size_t i = 0; i < d.block_size; ++i)
    if (std::strcmp(d.block_members[i], name) == 0) return &d.block_values[i];
  return nullptr;
}

const lib::Draw* draw_named(const lib::Plan& p, const char* name) {
  for (std::size_t i = 0; i < p.draw_count; ++i)
    if (std::strcmp(p.draws[i].name, name) == 0) return &p.draws[i];
  return nullptr;
}

TEST(EmbeddedPlan, EqualsTheRenderersPlanForEveryShape) {
  const compile::CompiledSpace& c = shapes();
  ASSERT_TRUE(c.ok());
  for (const std::string& key : kKeys) {
    SCOPED_TRACE(key);
    const lib::Variant* v = lib::find_variant(key);
    ASSERT_NE(v, nullptr);
    ASSERT_NE(v->plan, nullptr);
    const render::PipelinePlan p = render::plan_pipeline(c, index_of(c, key), variants::Target::vulkan);
    const lib::Plan& e = *v->plan;
    EXPECT_EQ(e.resolution, p.resolution);
    EXPECT_EQ(e.progressive, p.progressive);
    EXPECT_EQ(e.result, p.result);
    expect_same_textures(e, p);
    ASSERT_EQ(e.draw_count, p.draws.size());
    for (std::size_t i = 0; i < e.draw_count; ++i) expect_same_draw(*v, e.draws[i], p, p.draws[i]);
    // Each per-draw uniform is the block member of that name, with that value.
    for (std::size_t i = 0; i < e.draw_count; ++i)
      for (std::size_t u = 0; u < e.draws[i].uniform_count; ++u) {
        const float* value = member(e.draws[i], e.draws[i].uniforms[u].name);
        ASSERT_NE(value, nullptr) << e.draws[i].name << " " << e.draws[i].uniforms[u].name;
        EXPECT_EQ(*value, e.draws[i].uniforms[u].value);
      }
  }
}

TEST(EmbeddedPlan, SaysWhatEachShapeRuns) {
  // The separable blur: two draws of the blur pass, horizontal then vertical.
  const lib::Plan& sep = *lib::find_variant(kKeys[0])->plan;
  const lib::Draw *h = draw_named(sep, "blur.h"), *v = draw_named(sep, "blur.v");
  ASSERT_TRUE(h && v);
  EXPECT_LT(h, v);
  EXPECT_EQ(h->pass, lib::Pass::blur);
  ASSERT_TRUE(member(*h, "axis") && member(*v, "axis"));
  EXPECT_EQ(*member(*h, "axis"), 0.0f);
  EXPECT_EQ(*member(*v, "axis"), 1.0f);
  EXPECT_EQ(v->outputs[0].texture, sep.result);

  // SAO: its z pyramid, one draw per level, each reading the level below.
  const lib::Plan& sao = *lib::find_variant(kKeys[1])->plan;
  const lib::Draw* top = draw_named(sao, "zmip.5");
  ASSERT_NE(top, nullptr);
  const lib::Texture& zmip = sao.textures[top->outputs[0].texture];
  EXPECT_EQ(zmip.levels, 6);
  EXPECT_FALSE(zmip.full_resolution);
  EXPECT_EQ(top->level, 5);
  ASSERT_NE(member(*top, "level"), nullptr);
  EXPECT_EQ(*member(*top, "level"), 5.0f);
  EXPECT_TRUE(std::any_of(top->inputs, top->inputs + top->input_count,
                          [](const lib::Input& in) { return in.binding == 7 && in.texture.level == 4; }));
  // Half resolution: the AO chain at the AO extent, then the upsample at full resolution writes the result.
  const lib::Plan& half = *lib::find_variant(kKeys[2])->plan;
  EXPECT_EQ(half.resolution, 0.5f);
  EXPECT_FALSE(draw_named(half, "ao")->full_resolution);
  const lib::Draw* up = draw_named(half, "upsample");
  ASSERT_NE(up, nullptr);
  EXPECT_TRUE(up->full_resolution);
  EXPECT_EQ(up->outputs[0].texture, half.result);
  // Progressive: the AO half is double-buffered and the average reads the previous frame's copy.
  EXPECT_TRUE(half.progressive);
  const lib::Draw* prog = draw_named(half, "progressive");
  ASSERT_NE(prog, nullptr);
  EXPECT_TRUE(half.textures[draw_named(half, "ao")->outputs[0].texture].double_buffered);
  EXPECT_TRUE(std::any_of(prog->inputs, prog->inputs + prog->input_count,
                          [](const lib::Input& in) { return in.texture.previous; }));
}

TEST(EmbeddedPlan, DropsTheDrawsASmallFrameDrops) {
  const compile::CompiledSpace& c = shapes();
  ASSERT_TRUE(c.ok());
  for (const std::string& key : {kKeys[1], kKeys[4]}) {
    const render::PipelinePlan p = render::plan_pipeline(c, index_of(c, key), variants::Target::vulkan);
    const lib::Plan& e = *lib::find_variant(key)->plan;
    for (int w : {1, 2, 3, 7, 8, 24, 33, 96, 130})
      for (int h : {1, 5, 14, 54, 64}) {
        const lib::Extent ao = lib::ao_extent({w, h}, e.resolution);
        const render::Extent rao = render::ao_extent({w, h}, p.resolution);
        EXPECT_EQ(ao.width, rao.width);
        EXPECT_EQ(ao.height, rao.height);
        std::vector<std::string> kept, ran;
        for (std::size_t i = 0; i < e.draw_count; ++i)
          if (lib::draw_runs_at(e, e.draws[i], {w, h})) kept.push_back(e.draws[i].name);
        for (const auto& d : render::plan_for_size(p, {w, h}).draws) ran.push_back(d.name);
        EXPECT_EQ(kept, ran) << key << " at " << w << "x" << h;
      }
  }
}

}  // namespace
