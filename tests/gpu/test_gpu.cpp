// AMD ISA statistics from RADV's null device (src/gpu, `aovar analyze --gpu`): unrolled counts follow the
// taps, runs repeat, unknown families and a missing driver give one-line errors, a crash costs one family.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

#include "gpu/families.h"
#include "gpu/gpu.h"
#include "gpu/spirv_unroll.h"
#include "gpu/text.h"
#include "radv_support.h"
#include "render_support.h"
#include "test_support.h"

namespace aovar {
namespace {

const std::vector<std::string> kSamples = {"alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x1-hp",
                                           "alchemy-s16-p0-nrgb8-zdep-rst-d32-bsep-x1-hp",
                                           "alchemy-s32-p0-nrgb8-zdep-rst-d32-bsep-x1-hp"};


const compile::CompiledSpace& samples_space() {
  static const compile::CompiledSpace c = test::compile_variants(kSamples);
  return c;
}

gpu::GpuAnalysis analyze(const std::vector<std::string>& families) {
  const auto& c = samples_space();
  std::vector<int> all(c.space.variants.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  return gpu::analyze_gpu(c, all, {families, {}, {}, {}});
}

double ao_instructions(const gpu::FamilyStats& f, const std::string& key) {
  for (const auto& v : f.variants)
    if (v.key == key) return v.pass("ao")->unrolled().instructions;
  ADD_FAILURE() << "no statistics for " << key << " on " << f.family;
  return 0;
}

TEST(Gpu, UnrollHintsSetOnEveryLoopMerge) {
  // Header, OpLoopMerge %1 %2 DontUnroll, OpLoopMerge %3 %4 Unroll (already: unchanged).
  std::vector<std::uint32_t> words = {0x07230203, 0x00010500, 0, 10, 0, (4u << 16) | 246, 1, 2, 0x2,
                                      (4u << 16) | 246, 3, 4, 0x1};
  const auto r = gpu::with_unroll_hints(words);
  EXPECT_EQ(r.loops_changed, 1);
  EXPECT_EQ(r.words[8], 0x1u);
  EXPECT_EQ(r.words[12], 0x1u);
  EXPECT_THROW(gpu::with_unroll_hints({1, 2, 3}), std::runtime_error);
}

TEST(Gpu, CombineSumsCountsAndKeepsTheWorstRegistersAndOccupancy) {
  const auto a = gpu::ShaderStats::from_values({{"VGPRs", 24}, {"Subgroups per SIMD", 32}, {"Instructions", 100},
                                                {"VMEM Clause", 3}, {"Hash", 7}});
  const auto b = gpu::ShaderStats::from_values({{"VGPRs", 40}, {"Subgroups per SIMD", 16}, {"Instructions", 50},
                                                {"VMEM Clause", 1}, {"Hash", 9}});
  const auto t = gpu::combine({&a, &b});
  EXPECT_EQ(t.vgprs, 40);
  EXPECT_EQ(t.subgroups_per_simd, 16);
  EXPECT_EQ(t.instructions, 150);
  EXPECT_EQ(t.vmem_clauses, 4);
  EXPECT_EQ(t.values.count("Hash"), 0u);  // hashes identify one pipeline: no total
  EXPECT_TRUE(std::isnan(t.latency));     // not reported: NaN, never 0
}

TEST(Gpu, UnrolledInstructionsGrowWithSampleCount) {
  REQUIRE_RADV();
  const auto a = analyze({"navi21", "polaris10"});
  ASSERT_EQ(a.families.size(), 2u);
  for (const auto& f : a.families) {
    ASSERT_TRUE(f.ok()) << f.family << ": " << f.error;
    ASSERT_EQ(f.variants.size(), 3u) << f.family;
    EXPECT_NE(f.driver.find("Mesa"), std::string::npos) << f.driver;
    const double s08 = ao_instructions(f, kSamples[0]), s16 = ao_instructions(f, kSamples[1]),
                 s32 = ao_instructions(f, kSamples[2]);
    EXPECT_GT(s16, s08) << f.family;
    EXPECT_GT(s32, s16) << f.family;
    const auto* ao = f.variants[0].pass("ao");
    EXPECT_GT(ao->unrolled().vgprs, 0) << f.family;
    EXPECT_GT(ao->stats->loops_unrolled, 0) << f.family;
    EXPECT_GE(f.variants[0].total(true).instructions, ao->unrolled().instructions);
  }
}

TEST(Gpu, TwoRunsGiveIdenticalStatistics) {
  REQUIRE_RADV();
  EXPECT_EQ(gpu::to_json(analyze({"navi21"})), gpu::to_json(analyze({"navi21"})));
}

TEST(Gpu, UnknownFamilyIsOneLineListingTheKnownOnes) {
  REQUIRE_RADV();
  const std::string what = test::thrown_message<std::runtime_error>([&] { analyze({"navi21", "navi99"}); });
  EXPECT_NE(what.find("unknown GPU family 'navi99'"), std::string::npos) << what;
  EXPECT_NE(what.find("navi21"), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
}

TEST(Gpu, MissingDriverNamesThePackage) {
  test::ScopedEnv icd("AOVAR_RADV_ICD", "/nonexistent/radeon_icd.x86_64.json");
  const std::string m = test::thrown_message<std::runtime_error>([&] { gpu::find_radeon_icd(); });
  EXPECT_NE(m.find("mesa-vulkan-drivers"), std::string::npos) << m;
}

TEST(Gpu, CrashInOneFamilyLeavesTheOthers) {
  REQUIRE_RADV();
  const auto a = [] {
    test::ScopedEnv crash("AOVAR_GPU_TEST_CRASH", "polaris10");
    return analyze({"navi21", "polaris10", "vangogh"});
  }();
  ASSERT_EQ(a.families.size(), 3u);
  EXPECT_TRUE(a.families[0].ok()) << a.families[0].error;
  EXPECT_EQ(a.families[0].variants.size(), 3u);
  EXPECT_FALSE(a.families[1].ok());
  EXPECT_NE(a.families[1].error.find("crashed (signal"), std::string::npos) << a.families[1].error;
  EXPECT_TRUE(a.families[1].variants.empty());
  EXPECT_TRUE(a.families[2].ok()) << a.families[2].error;
  EXPECT_EQ(a.families[2].variants.size(), 3u);
}

TEST(Gpu, CliWritesGpuJsonAndRejectsUnknownFamilies) {
  REQUIRE_RADV();
  test::TempDir dir;
  auto r = test::run_aovar("analyze --gpu navi21 --variants '" + kSamples[0] + "' --out " + dir.path().string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("NAVI21"), std::string::npos) << r.output;
  std::ifstream in(dir / "gpu.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["families"][0]["variants"][0]["key"], kSamples[0]);
  auto bad = test::run_aovar("analyze --gpu navi99 --variants '" + kSamples[0] + "'");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("unknown GPU family 'navi99'"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace aovar
