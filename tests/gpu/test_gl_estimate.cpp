// The GL chips' estimate (src/gpu/gl/estimate.h, issue 56) on synthetic statistics: an ALU-bound, a
// texture-bound and a memory-bound pass each take the term they stress, each term moves with its own figure of
// the chip and no other, and the G-buffer's write follows its render targets' bytes. No measured figure here:
// every expectation is a relation between two estimates or a term against the formula's parts.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "gpu/cache_estimate.h"
#include "gpu/family_specs.h"
#include "gpu/gl/estimate.h"
#include "gpu/gl/vendor.h"
#include "gpu/roofline.h"

namespace aovar {
namespace {

// A made-up tiler: 64 lanes at 500 MHz, 4 texture units, 10 GB/s; one texture cache and an L2.
gpu::FamilySpec gl_synthetic_chip() {
  gpu::FamilySpec chip;
  chip.family = "synthetic";
  chip.product = "synthetic chip";
  chip.vendor = "qualcomm";
  chip.cus = 1;
  chip.simds_per_cu = 1;
  chip.wave_size = 16;
  chip.clock_mhz = 500;
  chip.tmus = 4;
  chip.bandwidth_gbs = 10;
  chip.alu_lanes = 64;
  chip.compiler = gpu::CompilerRef{"freedreno", "320"};
  gpu::CacheLevelSpec l1{"Texture L1", gpu::CacheScope::cu, 4096, 64, 4, 64, {}};
  gpu::CacheLevelSpec l2{"L2", gpu::CacheScope::chip, 131072, 64, 16, 64, {}};
  chip.caches = {l1, l2};
  return chip;
}

gpu::PassLoad gl_pass_load(double fetches, double bytes) {
  gpu::PassLoad load;
  load.pass = "ao";
  load.fetches = fetches;
  load.bytes_per_pixel = bytes;
  return load;
}

table::GpuPassCost gl_estimated(const gpu::FamilySpec& chip, double lane_cycles, const gpu::PassLoad& load) {
  table::GpuPassCost c;
  c.pass = load.pass;
  gpu::apply_chip_roofline(c, load, chip, {600, 960}, lane_cycles);
  return c;
}

TEST(GlEstimate, AnAluBoundPassScalesWithItsIssueCountAndTheLanes) {
  const gpu::FamilySpec chip = gl_synthetic_chip();
  const gpu::PassLoad load = gl_pass_load(2, 8);  // few fetches, few bytes
  const table::GpuPassCost a = gl_estimated(chip, 800, load);
  EXPECT_EQ(a.bound, "alu");
  EXPECT_DOUBLE_EQ(a.est_ms, a.alu_ms);
  EXPECT_NEAR(gl_estimated(chip, 1600, load).alu_ms / a.alu_ms, 2.0, 1e-12);  // twice the instructions
  gpu::FamilySpec wider = chip;
  wider.alu_lanes *= 2;
  EXPECT_NEAR(gl_estimated(wider, 800, load).alu_ms / a.alu_ms, 0.5, 1e-12);  // twice the lanes
  // A shader clock apart from the core clock (GT200, Fermi) drives the ALUs, not the texture units.
  gpu::FamilySpec hot = chip;
  hot.shader_clock_mhz = 2 * chip.clock_mhz;
  const table::GpuPassCost h = gl_estimated(hot, 800, load);
  EXPECT_NEAR(h.alu_ms / a.alu_ms, 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(h.texture_ms, a.texture_ms);
}

TEST(GlEstimate, ATextureBoundPassScalesWithFetchesOverTheTexelRate) {
  const gpu::FamilySpec chip = gl_synthetic_chip();
  const gpu::PassLoad load = gl_pass_load(64, 16);  // many fetches from a tiny footprint, little arithmetic
  const table::GpuPassCost t = gl_estimated(chip, 20, load);
  EXPECT_EQ(t.bound, "texture");
  EXPECT_NEAR(t.texture_ms, 1e3 * 64 * 600 * 960 / (chip.tmus * chip.clock_mhz * 1e6), 1e-9);
  gpu::FamilySpec more_tmus = chip;
  more_tmus.tmus *= 2;
  const table::GpuPassCost m = gl_estimated(more_tmus, 20, load);
  EXPECT_NEAR(m.texture_ms / t.texture_ms, 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(m.alu_ms, t.alu_ms);
}

TEST(GlEstimate, AMemoryBoundPassIsBoundByItsTrafficAndTheCacheModelTakesOver) {
  const gpu::FamilySpec chip = gl_synthetic_chip();
  const gpu::PassLoad load = gl_pass_load(4, 400);  // wide texels and many render targets
  table::GpuPassCost c = gl_estimated(chip, 20, load);
  EXPECT_EQ(c.bound, "bandwidth");
  const double untraced = c.est_ms;
  // The traced replay: most reads hit, but the pass still misses 200 B per pixel to DRAM.
  gpu::CacheSimResult traffic;
  traffic.pixels = 1000;
  traffic.reads = 4000;
  traffic.dram_bytes = 200000;
  gpu::CacheLevelStats l1, l2;
  l1.name = "Texture L1", l1.accesses = 4000, l1.hits = 3000, l1.bytes_requested = 16000;
  l2.name = "L2", l2.accesses = 1000, l2.hits = 0, l2.bytes_requested = 64000;
  traffic.levels = {l1, l2};
  gpu::apply_cache_model(c, load, chip, {600, 960}, traffic);
  EXPECT_EQ(c.bound, "dram");
  EXPECT_NEAR(c.dram_ms, 1e3 * 200 * 600 * 960 / (chip.bandwidth_gbs * 1e9), 1e-9);
  EXPECT_LT(c.est_ms, untraced);  // the caches absorb part of the 400 bytes
  EXPECT_TRUE(std::isnan(c.latency_ms));  // no ACO latency on a GL chip: the term is absent, not zero
  EXPECT_GE(c.est_ms, c.alu_ms);
  // A faster memory moves it; more lanes do not.
  gpu::FamilySpec wider = chip;
  wider.alu_lanes *= 4;
  table::GpuPassCost w = gl_estimated(wider, 20, load);
  gpu::apply_cache_model(w, load, wider, {600, 960}, traffic);
  EXPECT_DOUBLE_EQ(w.est_ms, c.est_ms);
}

TEST(GlEstimate, TheGbufferWriteFollowsItsRenderTargetBytes) {
  const gpu::FamilySpec chip = gl_synthetic_chip();
  gpu::PassLoad rg = gl_pass_load(0, 2 + 2), rgb = gl_pass_load(0, 4 + 2);  // rg8 / rgba8 normals, r16f depth
  rg.pass = rgb.pass = "gbuffer";
  table::GpuPassCost a, b;
  gpu::apply_gbuffer_write(a, rg, chip, {600, 960});
  gpu::apply_gbuffer_write(b, rgb, chip, {600, 960});
  EXPECT_EQ(a.bound, "dram");
  EXPECT_EQ(a.pass, "gbuffer");
  EXPECT_NEAR(b.est_ms / a.est_ms, 6.0 / 4.0, 1e-12);
}

TEST(GlEstimate, EachVendorCountsItsOwnIssueSlots) {
  gpu::ShaderStats midgard;
  midgard.instructions = 349;
  midgard.values = {{"inst", 349}, {"bundles", 176}};
  gpu::ShaderStats valhall;
  valhall.instructions = 120;
  valhall.values = {{"inst", 120}, {"cycles", 2.5}};
  gpu::FamilySpec mali = gl_synthetic_chip();
  mali.compiler = gpu::CompilerRef{"panfrost", "750"};
  EXPECT_DOUBLE_EQ(gpu::chip_alu_lane_cycles(mali, midgard), 176);  // a VLIW bundle per pipe-clock
  EXPECT_DOUBLE_EQ(gpu::chip_alu_lane_cycles(mali, valhall), 120);
  for (const char* driver : {"nouveau", "freedreno", "intel"}) {
    gpu::FamilySpec chip = gl_synthetic_chip();
    chip.compiler = gpu::CompilerRef{driver, "x"};
    EXPECT_DOUBLE_EQ(gpu::chip_alu_lane_cycles(chip, valhall), 120) << driver;
  }
  // Without a count the ALU term, and so the estimate, is NaN: never a silent zero.
  gpu::ShaderStats none;
  const gpu::FamilySpec chip = gl_synthetic_chip();
  const table::GpuPassCost c = gl_estimated(chip, gpu::chip_alu_lane_cycles(chip, none), gl_pass_load(4, 8));
  EXPECT_TRUE(std::isnan(c.est_ms));
}

TEST(GlEstimate, EveryGlChipWithLanesHasAnEstimateSpecAndAmdFamiliesKeepTheirs) {
  for (const gpu::FamilySpec* chip : gpu::gl_chips()) {
    EXPECT_GT(chip->alu_lanes, 0) << chip->family;
    EXPECT_EQ(gpu::estimate_spec(chip->family), chip) << chip->family;
    ASSERT_NE(gpu::gl_vendor(chip->compiler->driver), nullptr);
    EXPECT_NE(gpu::gl_vendor(chip->compiler->driver)->alu_lane_cycles, nullptr) << chip->family;
  }
  EXPECT_EQ(gpu::estimate_spec("navi21"), gpu::family_spec("navi21"));
  EXPECT_EQ(gpu::estimate_spec("nosuchchip"), nullptr);
}

}  // namespace
}  // namespace aovar

namespace aovar {
namespace {

// select --target and ship --target say how far to trust the estimate: the paper table where bench/gpu_seeds
// checked the chip, "no validation" where no paper measured it, and "no estimate" for statistics only.
TEST(GlEstimate, EachTargetSaysItsValidationInOneLine) {
  const std::string a320 = gpu::validation_line("a320");
  EXPECT_NE(a320.find("Sunet 2018"), std::string::npos) << a320;
  EXPECT_NE(a320.find("Spearman"), std::string::npos) << a320;
  EXPECT_NE(a320.find("median ratio error"), std::string::npos) << a320;
  EXPECT_NE(gpu::validation_line("a660").find("no validation"), std::string::npos);
  EXPECT_NE(gpu::validation_line("navi21").find("no validation"), std::string::npos);
  EXPECT_NE(gpu::validation_line("phoenix").find("no estimate"), std::string::npos);
  for (const std::string& line : {a320, gpu::validation_line("navi21")}) EXPECT_EQ(line.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace aovar

namespace aovar {
namespace {

// A variant on a GL chip: every pass on the vendor's count, and the G-buffer's write in the frame (on AMD it
// is left out: tests/gpu/test_roofline.cpp).
TEST(GlEstimate, AVariantOnAGlChipSumsItsPassesWithTheGbufferWrite) {
  gpu::VariantStats v{"k", {}};
  for (const char* pass : {"gbuffer", "ao", "blur"}) {
    gpu::PipelineStats stats;
    stats.unrolled.instructions = 100;
    stats.unrolled.values = {{"inst", 100}};
    stats.shipped = stats.unrolled;
    v.passes.push_back({pass, 0, std::make_shared<const gpu::PipelineStats>(stats)});
  }
  const std::vector<gpu::PassLoad> loads = {{"gbuffer", 1, 1, 0, 8}, {"ao", 1, 1, 4, 16}, {"blur", 2, 1, 2, 8}};
  const gpu::FamilySpec chip = gl_synthetic_chip();
  const table::GpuCost cost = gpu::estimate(v, loads, &chip, {600, 960}, "Mesa test");
  ASSERT_EQ(cost.passes.size(), 3u);
  EXPECT_EQ(cost.passes[0].pass, "gbuffer");
  EXPECT_EQ(cost.passes[0].bound, "dram");
  EXPECT_DOUBLE_EQ(cost.est_ms, cost.passes[0].est_ms + cost.passes[1].est_ms + cost.passes[2].est_ms);
  EXPECT_NEAR(cost.passes[1].alu_ms, 1e3 * 100 * 600 * 960 / (chip.alu_lanes * chip.clock_mhz * 1e6), 1e-9);
  EXPECT_NEAR(cost.passes[2].alu_ms, 2 * cost.passes[1].alu_ms, 1e-9);  // the separable blur's two draws
}

}  // namespace
}  // namespace aovar
