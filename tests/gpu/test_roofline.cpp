// The roofline estimate (src/gpu/roofline.h, pass_loads.h, family_specs.h, costs.h): the arithmetic on
// hand-made inputs, the embedded per-family data, the plan's draws and pixel shares, and with a RADV
// installed, how the statistics and the estimate follow the taps.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "gpu/costs.h"
#include "gpu/families.h"
#include "gpu/family_specs.h"
#include "gpu/pass_loads.h"
#include "gpu/roofline.h"
#include "render/plan.h"
#include "radv_support.h"
#include "render_support.h"
#include "test_support.h"

namespace aovar {
namespace {

// 10 CUs x 2 SIMDs at 1 GHz, 40 TMUs, 100 GB/s: round numbers so each bound is easy to write down.
gpu::FamilySpec test_spec() {
  gpu::FamilySpec s;
  s.family = "test";
  s.product = "Test GPU";
  s.cus = 10, s.simds_per_cu = 2, s.clock_mhz = 1000, s.tmus = 40, s.bandwidth_gbs = 100;
  return s;
}
const gpu::Frame kFrame{640, 100};  // 64,000 pixels: 1,000 waves of 64

table::GpuPassCost roofline(double inverse_throughput, double fetches, double bytes, double draws = 1,
                            double share = 1) {
  table::GpuPassCost c;
  c.inverse_throughput = inverse_throughput;
  gpu::apply_roofline(c, {"ao", draws, share, fetches, bytes}, test_spec(), kFrame);
  return c;
}

TEST(Roofline, AluBoundWhenTheShaderIsLongAndReadsLittle) {
  const auto c = roofline(640, 1, 1);
  EXPECT_DOUBLE_EQ(c.alu_ms, 1e3 * 640 * 1000 / (20 * 1e9));  // cycles per 64 px x waves / (SIMDs x clock)
  EXPECT_DOUBLE_EQ(c.texture_ms, 1e3 * 1 * 64000 / (40 * 1e9));
  EXPECT_DOUBLE_EQ(c.bandwidth_ms, 1e3 * 1 * 64000 / 100e9);
  EXPECT_EQ(c.bound, "alu");
  EXPECT_DOUBLE_EQ(c.est_ms, c.alu_ms);
}

TEST(Roofline, TextureBoundWhenFetchesDominate) {
  const auto c = roofline(1, 100, 1);
  EXPECT_EQ(c.bound, "texture");
  EXPECT_DOUBLE_EQ(c.est_ms, 1e3 * 100 * 64000 / (40 * 1e9));
}

TEST(Roofline, BandwidthBoundWhenBytesDominate) {
  const auto c = roofline(1, 1, 1000);
  EXPECT_EQ(c.bound, "bandwidth");
  EXPECT_DOUBLE_EQ(c.est_ms, 1e3 * 1000 * 64000 / 100e9);
}

TEST(Roofline, DrawsAndPixelShareScaleEveryBound) {
  const auto one = roofline(640, 100, 1000);
  const auto two_quarters = roofline(640, 100, 1000, 2, 0.25);
  EXPECT_DOUBLE_EQ(two_quarters.alu_ms, one.alu_ms * 0.5);
  EXPECT_DOUBLE_EQ(two_quarters.texture_ms, one.texture_ms * 0.5);
  EXPECT_DOUBLE_EQ(two_quarters.bandwidth_ms, one.bandwidth_ms * 0.5);
  EXPECT_EQ(two_quarters.draws, 2);
  EXPECT_EQ(two_quarters.pixel_share, 0.25);
}

TEST(Roofline, UnreportedThroughputGivesNoEstimate) {
  const auto c = roofline(NAN, 100, 1000);
  EXPECT_TRUE(std::isnan(c.est_ms));
  EXPECT_TRUE(c.bound.empty());
}

TEST(Roofline, VariantSumsItsPassesWithoutTheGBuffer) {
  gpu::VariantStats v{"k", {}};
  for (const char* pass : {"gbuffer", "ao", "blur"}) {
    gpu::PipelineStats stats;
    stats.unrolled = gpu::ShaderStats::from_values({{"Inverse Throughput", 64}, {"Instructions", 10}});
    stats.shipped = stats.unrolled;
    v.passes.push_back({pass, 0, std::make_shared<const gpu::PipelineStats>(stats)});
  }
  const std::vector<gpu::PassLoad> loads = {{"gbuffer", 1, 1, 0, 0}, {"ao", 1, 1, 0, 0}, {"blur", 2, 1, 0, 0}};
  const gpu::FamilySpec spec = test_spec();
  const auto cost = gpu::estimate(v, loads, &spec, kFrame, "Mesa test");
  ASSERT_EQ(cost.passes.size(), 2u);
  EXPECT_EQ(cost.passes[0].pass, "ao");
  EXPECT_DOUBLE_EQ(cost.est_ms, cost.passes[0].est_ms + cost.passes[1].est_ms);
  EXPECT_DOUBLE_EQ(cost.passes[1].est_ms, 2 * cost.passes[0].est_ms);
  EXPECT_EQ(cost.product, "Test GPU");
  EXPECT_EQ(cost.mesa, "Mesa test");
  EXPECT_EQ(cost.frame, "640x100");
  const auto statistics_only = gpu::estimate(v, loads, nullptr, kFrame, "Mesa test");
  EXPECT_TRUE(std::isnan(statistics_only.est_ms));
  EXPECT_EQ(statistics_only.passes.size(), 2u);
  EXPECT_EQ(statistics_only.passes[0].instructions, 10);
}

TEST(Roofline, AnalyzeSizeRejectsJunk) {
  for (const char* bad : {"1920", "1920x", "x1080", "0x10", "1920x1080x2", "ax b"}) {
    auto r = test::run_aovar(std::string("analyze --gpu navi21 --variants nothing --size '") + bad + "'");
    EXPECT_NE(r.status, 0) << bad;
    EXPECT_NE(r.output.find("--size"), std::string::npos) << bad << ": " << r.output;
  }
}

TEST(RooflineData, EveryFamilyHasASourceAndPositiveFigures) {
  const auto& specs = gpu::family_specs();
  ASSERT_FALSE(specs.empty());
  std::set<std::string> names;
  for (const auto& s : specs) {
    EXPECT_TRUE(names.insert(s.family).second) << "twice: " << s.family;
    EXPECT_FALSE(s.product.empty()) << s.family;
    EXPECT_EQ(s.source.rfind("https://", 0), 0u) << s.family << ": " << s.source;
    EXPECT_GT(s.cus, 0) << s.family;
    EXPECT_TRUE(s.simds_per_cu == 2 || s.simds_per_cu == 4) << s.family;
    EXPECT_TRUE(s.wave_size == 32 || s.wave_size == 64) << s.family;
    EXPECT_GT(s.clock_mhz, 0) << s.family;
    EXPECT_GT(s.tmus, 0) << s.family;
    EXPECT_GT(s.bandwidth_gbs, 0) << s.family;
  }
  for (const char* needed : {"navi21", "vangogh", "polaris10"}) EXPECT_NE(gpu::family_spec(needed), nullptr) << needed;
  ASSERT_NE(gpu::family_spec("gfx1100"), nullptr);  // an alias
  EXPECT_EQ(gpu::family_spec("gfx1100")->family, "navi31");
  EXPECT_EQ(gpu::family_spec("navi99"), nullptr);
}

// The plan's draws, as the renderer issues them.
const gpu::PassLoad* load_of(const std::vector<gpu::PassLoad>& loads, const std::string& pass) {
  for (const auto& l : loads)
    if (l.pass == pass) return &l;
  return nullptr;
}

const std::vector<std::string> kPlanned = {"alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x1-hp",
                                           "alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x2-hp",
                                           "sao-s08-p0-ndep-zdep-rst-d32-bsep-x1-hp"};

std::vector<gpu::PassLoad> planned_loads(int i) {
  static const compile::CompiledSpace c = test::compile_variants(kPlanned);
  static std::map<std::string, analyze::ProgramCost> analysed;
  for (std::size_t v = 0; v < c.space.variants.size(); ++v)
    if (c.space.variants[v].key == kPlanned[i])
      return gpu::pass_loads(render::plan_pipeline(c, static_cast<int>(v), variants::Target::vulkan), analysed);
  ADD_FAILURE() << "not compiled: " << kPlanned[i];
  return {};
}

TEST(RooflineLoads, DrawsAndSharesComeFromThePlan) {
  const auto full = planned_loads(0), half = planned_loads(1), sao = planned_loads(2);
  ASSERT_NE(load_of(full, "ao"), nullptr);
  ASSERT_NE(load_of(full, "blur"), nullptr);
  EXPECT_EQ(load_of(full, "blur")->draws, 2);  // separable: two draws
  EXPECT_EQ(load_of(full, "ao")->draws, 1);
  EXPECT_EQ(load_of(full, "ao")->pixel_share, 1);
  EXPECT_GE(load_of(full, "ao")->fetches, 8);  // eight taps at least
  EXPECT_GT(load_of(full, "ao")->bytes_per_pixel, 0);
  ASSERT_NE(load_of(half, "ao"), nullptr);
  EXPECT_DOUBLE_EQ(load_of(half, "ao")->pixel_share, 0.25);  // x2: half width, half height
  ASSERT_NE(load_of(half, "upsample"), nullptr);
  EXPECT_DOUBLE_EQ(load_of(half, "upsample")->pixel_share, 1);
  const gpu::PassLoad* zmip = load_of(sao, "prefilter");  // SAO's z pyramid
  ASSERT_NE(zmip, nullptr);
  EXPECT_EQ(zmip->draws, render::kZmipLevels);  // one draw per pyramid level
  EXPECT_GT(zmip->draws * zmip->pixel_share, 1.0);
  EXPECT_LT(zmip->draws * zmip->pixel_share, 4.0 / 3.0);  // 1 + 1/4 + 1/16 + ...
}

// With a RADV: the statistics and the estimate follow the taps.

const std::vector<std::string> kLadder = {
    "alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x1-hp", "alchemy-s16-p0-nrgb8-zdep-rst-d32-bsep-x1-hp",
    "alchemy-s32-p0-nrgb8-zdep-rst-d32-bsep-x1-hp", "alchemy-s08-p1-nrgb8-zdep-rst-d32-bsep-x1-hp",
    "alchemy-s16-p1-nrgb8-zdep-rst-d32-bsep-x1-hp", "alchemy-s32-p1-nrgb8-zdep-rst-d32-bsep-x1-hp"};
const std::vector<std::string> kFamilies = {"navi21", "vangogh", "polaris10"};

const std::map<std::string, table::GpuCosts>& ladder_costs() {
  static const compile::CompiledSpace c = test::compile_variants(kLadder);
  static const auto costs = [] {
    std::vector<int> all(c.space.variants.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    std::vector<std::string> errors;
    auto out = gpu::costs_of(gpu::analyze_gpu(c, all, {kFamilies, {}, {}, {}}), gpu::variant_loads(c, all), gpu::kDefaultFrame, &errors);
    for (const auto& e : errors) ADD_FAILURE() << e;
    return out;
  }();
  return costs;
}

const table::GpuPassCost& ao_of(const std::string& key, const std::string& family) {
  return *ladder_costs().at(key).at(family).pass("ao");
}

TEST(RooflineRadv, UnrolledCountsAndEstimateGrowWithSamples) {
  REQUIRE_RADV();
  for (const auto& f : kFamilies) {
    for (int p : {0, 3}) {  // the plain and the progressive ladder
      const auto &s08 = ao_of(kLadder[p], f), &s16 = ao_of(kLadder[p + 1], f), &s32 = ao_of(kLadder[p + 2], f);
      EXPECT_GT(s16.instructions, s08.instructions) << f << " " << kLadder[p];
      EXPECT_GT(s32.instructions, s16.instructions) << f << " " << kLadder[p];
      const auto& c08 = ladder_costs().at(kLadder[p]).at(f);
      const auto& c32 = ladder_costs().at(kLadder[p + 2]).at(f);
      EXPECT_FALSE(c08.mesa.empty()) << f;
      EXPECT_FALSE(c08.product.empty()) << f;
      EXPECT_EQ(c08.frame, "1920x1080");
      EXPECT_GT(s32.est_ms, s08.est_ms) << f;
      EXPECT_GT(c32.est_ms, c08.est_ms) << f;
      EXPECT_EQ(c08.pass("gbuffer"), nullptr);
      // Mesa 25's unweighted VMEM count against the SPIR-V analyser's fetches: every tap is one image load.
      if (!std::isnan(s08.vmem)) {
        EXPECT_EQ(s08.vmem, s08.fetches) << f;
      }
    }
  }
}

// The progressive AO pass does half the taps per frame: its per-frame ALU work is about half the plain
// pass's. The measure is VALU (Mesa 25: unweighted count) or instructions (older Mesa). The fixed part of
// the shader (unprojection, normal decode, frame-parity select, export) does not halve, so the ratio sits
// above one half and nears it as the taps grow; at 32 samples Mesa 25 gave 0.53 (VALU) and 0.59
// (instructions) on these families, hence within 20% of one half.
TEST(RooflineRadv, ProgressiveHalvesTheAoPassAlu) {
  REQUIRE_RADV();
  for (const auto& f : kFamilies) {
    const auto &plain = ao_of(kLadder[2], f), &progressive = ao_of(kLadder[5], f);
    const bool valu = !std::isnan(plain.valu);
    const double a = valu ? plain.valu : plain.instructions, b = valu ? progressive.valu : progressive.instructions;
    const double ratio = b / a;
    EXPECT_GT(ratio, 0.5 * 0.8) << f << (valu ? " VALU " : " instructions ") << b << " / " << a;
    EXPECT_LT(ratio, 0.5 * 1.2) << f << (valu ? " VALU " : " instructions ") << b << " / " << a;
  }
}

}  // namespace
}  // namespace aovar
