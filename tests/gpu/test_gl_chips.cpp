// Compiler statistics of the GL chips (NVIDIA, Adreno, Mali, Intel) from Mesa's GL drivers through drm-shim
// (src/gpu/gl_*.h): each vendor's runner on a tiny shader, the taps showing after the unroll on every paper
// chip, mediump against highp where the compiler honours it, one line for a rejected shader and for a crash,
// a cache that is used when whole and recomputed when damaged, and the blur's taps counted at its radius.
// Outside CI a vendor that is not installed skips (scripts/mesa-gl, scripts/intel-shim); in CI (CI=true) it
// fails: scripts/deps installs every vendor.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "gpu/family_specs.h"
#include "gpu/gl/analysis.h"
#include "gpu/gl/compiler.h"
#include "gpu/gl/vendor.h"
#include "render_support.h"
#include "test_support.h"
#include "util/fs.h"
#include "util/verified_cache.h"

namespace aovar {
namespace {
namespace fs = std::filesystem;

// Skips outside CI when the vendor's compiler is not installed; in CI that is a failure.
#define REQUIRE_GL_VENDOR(name)                                                                  \
  do {                                                                                           \
    try {                                                                                        \
      gpu::check_installed(gpu::find_gl_install(), *gpu::gl_vendor(name));                      \
    } catch (const std::exception& e) {                                                          \
      if (std::getenv("CI")) FAIL() << e.what();                                                 \
      GTEST_SKIP() << e.what();                                                                  \
    }                                                                                            \
  } while (0)

const char* kGlVertex = "#version 300 es\nout vec2 uv;\nvoid main() { uv = vec2(gl_VertexID & 1, gl_VertexID >> 1);\n"
                      "gl_Position = vec4(uv * 2.0 - 1.0, 0.0, 1.0); }\n";
const char* kGlFragment = "#version 300 es\nprecision highp float;\nin vec2 uv;\nuniform sampler2D t;\nout vec4 c;\n"
                        "void main() { c = texture(t, uv) * 0.5 + vec4(uv, 0.0, 1.0); }\n";

const compile::CompiledSpace& gl_alchemy_space() {
  static const compile::CompiledSpace c = test::compile_variants(
      {"alchemy-s16-p0-nrg8-zdep-rst-d16-bsep-x1-hp", "alchemy-s32-p0-nrg8-zdep-rst-d16-bsep-x1-hp",
       "alchemy-s16-p0-nrg8-zdep-rst-d16-bsep-x1-mp"},
      true);
  return c;
}

double gl_ao_instructions(const gpu::FamilyStats& f, const std::string& key) {
  for (const auto& v : f.variants)
    if (v.key == key) return v.pass("ao")->unrolled().instructions;
  ADD_FAILURE() << "no statistics for " << key << " on " << f.family << ": " << f.error;
  return 0;
}

// Each vendor's parser on a statistics line as its compiler prints it (the forms in gpu/gl/vendors/*.cpp), with no
// driver: the line kept as raw, `inst` as instructions, the vendor's own fields, and the last line of several.
TEST(GlVendorParsers, EachReadsItsOwnStatisticsLine) {
  const auto stats = [](const std::string& vendor, const std::vector<std::string>& messages) {
    return gpu::gl_vendor(vendor)->fragment_stats(messages);
  };
  const std::string fd = "FRAG shader: 826 inst, 340 nops, 0 half, 8 full, 16 cat5, 3 cat6, 12 waves, 0 loops";
  const auto a = stats("freedreno", {"VERT shader: 10 inst", "FRAG shader: 1 inst", fd});
  ASSERT_TRUE(a);
  EXPECT_EQ(a->raw, fd);
  EXPECT_EQ(a->instructions, 826);
  EXPECT_EQ(a->texture, 16);
  EXPECT_EQ(a->registers, 8);
  EXPECT_EQ(a->occupancy, 12);
  EXPECT_EQ(gpu::gl_vendor("freedreno")->alu_lane_cycles(*a), 826);

  const auto nv = stats("nouveau", {"type: 4, local: 0, shared: 0, gpr: 29, inst: 451, bytes: 3608, cached: 77"});
  ASSERT_TRUE(nv);
  EXPECT_EQ(nv->instructions, 451);
  EXPECT_EQ(nv->registers, 29);
  EXPECT_EQ(nv->values.count("type") + nv->values.count("cached"), 0u);

  const auto mali = stats("panfrost", {"MESA_SHADER_FRAGMENT shader: 349 inst, 176 bundles, 301 quadwords, "
                                       "8 registers, 2 threads, 0 loops, 0:0 spills:fills"});
  ASSERT_TRUE(mali);
  EXPECT_EQ(mali->instructions, 349);
  EXPECT_EQ(mali->registers, 8);
  EXPECT_EQ(mali->spills, 0);
  EXPECT_EQ(gpu::gl_vendor("panfrost")->alu_lane_cycles(*mali), 176);  // Midgard: the bundles

  const auto brw = stats("intel", {"FS SIMD16 shader: 470 inst, 0 loops, 9000 cycles, 0:0 spills:fills, 12 sends",
                                   "FS SIMD8 shader: 465 inst, 0 loops, 11046 cycles, 0:0 spills:fills, 11 sends"});
  ASSERT_TRUE(brw);
  EXPECT_EQ(brw->instructions, 470);  // the widest width compiled
  EXPECT_EQ(brw->memory, 12);
  EXPECT_EQ(brw->values.at("simd"), 16);

  for (const gpu::GlVendor* v : gpu::gl_vendors()) EXPECT_FALSE(v->fragment_stats({"no statistics here"})) << v->name;
}

class GlVendorRunner : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(GlVendorRunner, CompilesATinyShaderAndReadsItsFragmentLine) {
  const auto& [vendor_name, chip] = GetParam();
  REQUIRE_GL_VENDOR(vendor_name);
  const gpu::GlVendor& vendor = *gpu::gl_vendor(vendor_name);
  const gpu::FamilySpec* spec = gpu::gl_chip(chip);
  ASSERT_NE(spec, nullptr);
  const auto batch = gpu::compile_on_chip(gpu::find_gl_install(), vendor, spec->compiler->chip,
                                          {{"tiny.frag", kGlVertex, kGlFragment}, {"tiny2.frag", kGlVertex, kGlFragment}});
  EXPECT_NE(batch.version.find("Mesa"), std::string::npos) << batch.version;
  ASSERT_EQ(batch.results.size(), 2u);
  for (const auto& r : batch.results) {
    ASSERT_TRUE(r.stats) << r.error;
    EXPECT_GT(r.stats->instructions, 0) << r.stats->raw;
    EXPECT_FALSE(r.stats->raw.empty());
    EXPECT_EQ(r.stats->instructions, batch.results[0].stats->instructions);  // one process, the same program
  }
}

INSTANTIATE_TEST_SUITE_P(Vendors, GlVendorRunner,
                         ::testing::Values(std::pair{"nouveau", "gf110"}, std::pair{"freedreno", "a530"},
                                           std::pair{"panfrost", "t760"}, std::pair{"intel", "byt"}),
                         [](const auto& info) { return info.param.first; });

TEST(GlChips, ARejectedShaderIsOneLineNamingTheProgramAndTheChip) {
  REQUIRE_GL_VENDOR("nouveau");
  const auto batch = gpu::compile_on_chip(gpu::find_gl_install(), *gpu::gl_vendor("nouveau"), "c8",
                                          {{"broken.frag", kGlVertex, "#version 300 es\nvoid main() { undefined_x = 1; }\n"},
                                           {"fine.frag", kGlVertex, kGlFragment}});
  ASSERT_EQ(batch.results.size(), 2u);
  const std::string& e = batch.results[0].error;
  EXPECT_FALSE(batch.results[0].stats);
  EXPECT_NE(e.find("broken.frag"), std::string::npos) << e;
  EXPECT_NE(e.find("c8"), std::string::npos) << e;
  EXPECT_NE(e.find("undefined_x"), std::string::npos) << e;  // the driver's own log, on the same line
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  EXPECT_TRUE(batch.results[1].stats) << "the program after a rejected one still compiles";
}

TEST(GlChips, ACrashCostsTheProgramItCrashedOn) {
  REQUIRE_GL_VENDOR("nouveau");
  ::setenv("AOVAR_GL_STATS_TEST_CRASH", "1", 1);  // the runner raises SIGSEGV on program 1 (test hook)
  const auto batch = gpu::compile_on_chip(gpu::find_gl_install(), *gpu::gl_vendor("nouveau"), "c8",
                                          {{"a.frag", kGlVertex, kGlFragment}, {"b.frag", kGlVertex, kGlFragment},
                                           {"c.frag", kGlVertex, kGlFragment}});
  ::unsetenv("AOVAR_GL_STATS_TEST_CRASH");
  EXPECT_TRUE(batch.results[0].stats);
  EXPECT_FALSE(batch.results[1].stats);
  EXPECT_NE(batch.results[1].error.find("b.frag"), std::string::npos) << batch.results[1].error;
  EXPECT_NE(batch.results[1].error.find("crashed"), std::string::npos) << batch.results[1].error;
  EXPECT_TRUE(batch.results[2].stats) << "the runner starts again after the crash";
}

// The issue's acceptance: on every paper chip the AO pass at 32 samples costs at least 1.8x its cost at 16.
TEST(GlChips, TheTapsShowOnEveryPaperChipAfterTheUnroll) {
  for (const char* v : {"nouveau", "freedreno", "panfrost", "intel"}) REQUIRE_GL_VENDOR(v);
  const auto& c = gl_alchemy_space();
  std::vector<int> all(c.space.variants.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  const std::vector<std::string> chips = {"gt200", "gf110", "gk20a", "a320", "a530", "t760", "byt"};
  const auto a = gpu::analyze_gl_chips(c, all, chips, {});
  ASSERT_EQ(a.chips.size(), chips.size());
  for (const auto& f : a.chips) {
    ASSERT_TRUE(f.ok()) << f.family << ": " << f.error;
    const double s16 = gl_ao_instructions(f, "alchemy-s16-p0-nrg8-zdep-rst-d16-bsep-x1-hp");
    const double s32 = gl_ao_instructions(f, "alchemy-s32-p0-nrg8-zdep-rst-d16-bsep-x1-hp");
    EXPECT_GE(s32, 1.8 * s16) << f.family << ": s16 " << s16 << ", s32 " << s32;
    for (const auto& v : f.variants) EXPECT_EQ(v.pass("ao")->unrolled().loops > 0, false) << f.family << " " << v.key;
  }
}

TEST(GlChips, MediumpDiffersFromHighpWhereTheCompilerHonoursIt) {
  REQUIRE_GL_VENDOR("freedreno");
  const auto& c = gl_alchemy_space();
  std::vector<int> all(c.space.variants.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  const auto a = gpu::analyze_gl_chips(c, all, {"a530"}, {});
  ASSERT_EQ(a.chips.size(), 1u);
  const auto& f = a.chips[0];
  const gpu::ShaderStats* hp = nullptr;
  const gpu::ShaderStats* mp = nullptr;
  for (const auto& v : f.variants) {
    if (v.key == "alchemy-s16-p0-nrg8-zdep-rst-d16-bsep-x1-hp") hp = &v.pass("ao")->unrolled();
    if (v.key == "alchemy-s16-p0-nrg8-zdep-rst-d16-bsep-x1-mp") mp = &v.pass("ao")->unrolled();
  }
  ASSERT_TRUE(hp && mp);
  // a5xx keeps mediump values in half registers: the half-register count differs, and so does the code.
  EXPECT_NE(hp->values.at("half"), mp->values.at("half")) << hp->raw << "\n" << mp->raw;
  EXPECT_NE(hp->raw, mp->raw);
}

TEST(GlChips, TheCacheIsUsedWhenWholeAndRecomputedWhenDamaged) {
  REQUIRE_GL_VENDOR("nouveau");
  const auto& c = gl_alchemy_space();
  const test::TempDir tmp;
  const std::vector<int> one = {0};
  const auto cold = gpu::analyze_gl_chips(c, one, {"gf110"}, tmp.path());
  ASSERT_TRUE(cold.chips[0].ok()) << cold.chips[0].error;
  EXPECT_EQ(cold.chips[0].cached, 0);
  const auto warm = gpu::analyze_gl_chips(c, one, {"gf110"}, tmp.path());
  EXPECT_EQ(warm.chips[0].cached, static_cast<int>(warm.chips[0].pipelines.size()));
  EXPECT_EQ(warm.chips[0].variants[0].total(true).instructions, cold.chips[0].variants[0].total(true).instructions);
  // Damage every entry three ways: garbage, another entry moved over it, and (its checksum right, written through
  // the cache layer) a line the parser cannot read. Each is compiled again with a warning, to the same answer.
  std::vector<fs::path> entries;
  for (const auto& e : fs::recursive_directory_iterator(tmp.path() / "gl-stats"))
    if (e.is_regular_file()) entries.push_back(e.path());
  ASSERT_GE(entries.size(), 3u);
  const util::VerifiedCache cache(tmp.path(), "gl-stats");
  util::write_atomic(entries[0], "{not json");
  util::write_atomic(entries[1], util::read_file(entries[2]).value());
  const std::string key = util::VerifiedCache::key_of(util::read_file(entries[2]).value()).value();
  cache.write(key, R"({"renderer":"x","version":"y","messages":["nothing"]})");
  ASSERT_EQ(cache.entry_path(key), entries[2]);
  testing::internal::CaptureStderr();
  const auto again = gpu::analyze_gl_chips(c, one, {"gf110"}, tmp.path());
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_EQ(again.chips[0].cached, static_cast<int>(entries.size()) - 3);
  EXPECT_TRUE(test::has_text(said, "not an entry of this cache format")) << said;
  EXPECT_TRUE(test::has_text(said, "the entry of another key")) << said;
  EXPECT_TRUE(test::has_text(said, "no statistics line the nouveau parser reads")) << said;
  EXPECT_EQ(again.chips[0].variants[0].total(true).instructions, cold.chips[0].variants[0].total(true).instructions);
  EXPECT_EQ(gpu::analyze_gl_chips(c, one, {"gf110"}, tmp.path()).chips[0].cached, static_cast<int>(entries.size()))
      << "stored again, whole";
}

// Issue 56: the blur's loop runs to its radius parameter; the GL analysis unrolls it at the value the variant
// renders with, so the chip's count grows with the kernel (one iteration was counted before), and each radius
// is an entry of its own in the cache.
TEST(GlChips, TheBlurCountsItsTapsAtTheRadiusAndEachRadiusIsItsOwnEntry) {
  REQUIRE_GL_VENDOR("nouveau");
  const auto& c = gl_alchemy_space();
  const std::string key = "alchemy-s16-p0-nrg8-zdep-rst-d16-bsep-x1-hp";
  int variant = -1;
  for (std::size_t i = 0; i < c.space.variants.size(); ++i)
    if (c.space.variants[i].key == key) variant = static_cast<int>(i);
  ASSERT_GE(variant, 0);
  const test::TempDir tmp;
  const auto at = [&](double radius) {
    return gpu::analyze_gl_chips(c, {variant}, {"gt200"}, tmp.path(), {{key, {{"blur.radius_px", radius}}}});
  };
  const auto r1 = at(1), r3 = at(3), r1_again = at(1);
  for (const auto* a : {&r1, &r3, &r1_again}) {
    ASSERT_TRUE(a->chips[0].ok()) << a->chips[0].error;
    ASSERT_EQ(a->chips[0].variants.size(), 1u);
  }
  const auto& blur1 = *r1.chips[0].variants[0].pass("blur")->stats;
  const auto& blur3 = *r3.chips[0].variants[0].pass("blur")->stats;
  EXPECT_EQ(blur1.loops_kept, 0);
  EXPECT_EQ(blur1.specialised, (std::map<std::string, double>{{"params.radius_px", 1.0}}));
  EXPECT_EQ(blur3.specialised, (std::map<std::string, double>{{"params.radius_px", 3.0}}));
  // 7 taps against 3 around the same fixed part (the centre's reads, the normalisation).
  EXPECT_GT(blur3.unrolled.instructions, 1.5 * blur1.unrolled.instructions)
      << "r 1: " << blur1.unrolled.raw << "\nr 3: " << blur3.unrolled.raw;
  EXPECT_EQ(r1.chips[0].cached, 0);
  EXPECT_EQ(r3.chips[0].cached, static_cast<int>(r3.chips[0].pipelines.size()) - 1) << "all but the blur's";
  EXPECT_EQ(r1_again.chips[0].cached, static_cast<int>(r1_again.chips[0].pipelines.size()));
  EXPECT_EQ(r1_again.chips[0].variants[0].pass("blur")->unrolled().instructions, blur1.unrolled.instructions);
  EXPECT_NE(gpu::gl_cache_key("gt200", "nv50", "Mesa", "v", "f", {{"params.radius_px", 1.0}}),
            gpu::gl_cache_key("gt200", "nv50", "Mesa", "v", "f", {{"params.radius_px", 3.0}}));
}

// Without a calibration each blur unrolls at its manifest radius, read from the pass whose program it is: SAO's
// keyed blur draws in the "blur" timing group but takes [passes.blur_keyed]'s radius_px (4), the 2-D bilateral
// [passes.blur]'s (2). No blur loop is left to count once.
TEST(GlChips, EachBlurUnrollsAtItsOwnPassesManifestRadius) {
  REQUIRE_GL_VENDOR("nouveau");
  const auto c = test::compile_variants(
      {"sao-s08-p0-ndep-zdep-rst-d32-bsep-x1-hp", "alchemy-s08-p0-nrgb8-zdep-rst-d16-bbil-x1-hp"}, true);
  const auto a = gpu::analyze_gl_chips(c, {0, 1}, {"gt200"}, {});
  ASSERT_TRUE(a.chips[0].ok()) << a.chips[0].error;
  ASSERT_EQ(a.chips[0].variants.size(), 2u);
  for (const auto& v : a.chips[0].variants) {
    const auto* blur = v.pass("blur");
    ASSERT_NE(blur, nullptr) << v.key;
    const double radius = v.key.rfind("sao", 0) == 0 ? 4.0 : 2.0;
    EXPECT_EQ(blur->stats->specialised, (std::map<std::string, double>{{"params.radius_px", radius}})) << v.key;
    EXPECT_EQ(blur->stats->loops_kept, 0) << v.key;
  }
}

TEST(GlChips, ACacheThatCannotBeWrittenDoesNotFailTheRun) {
  REQUIRE_GL_VENDOR("nouveau");
  const test::TempDir tmp;
  test::write_text(tmp / "a-file", "not a folder");  // the cache "folder" is a file: nothing can be written
  const auto a = gpu::analyze_gl_chips(gl_alchemy_space(), {0}, {"gf110"}, tmp / "a-file");
  ASSERT_EQ(a.chips.size(), 1u);
  EXPECT_TRUE(a.chips[0].ok()) << a.chips[0].error;
  EXPECT_EQ(a.chips[0].variants.size(), 1u);
}

TEST(GlChips, UnknownChipsAndMissingVendorsAreOneLineBeforeAnyWork) {
  const auto& c = gl_alchemy_space();
  try {
    gpu::analyze_gl_chips(c, {0}, {"gx9999"}, {});
    FAIL() << "an unknown chip was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("gx9999"), std::string::npos) << e.what();
  }
  const test::TempDir tmp;
  ::setenv("AOVAR_MESA_PREFIX", tmp.path().c_str(), 1);
  try {
    gpu::analyze_gl_chips(c, {0}, {"a320"}, {});
    ADD_FAILURE() << "a missing install was accepted";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("scripts/mesa-gl"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  ::unsetenv("AOVAR_MESA_PREFIX");
}

TEST(GlChips, EveryChipInTheDataFileHasARegisteredVendorAndPublicFigures) {
  ASSERT_GE(gpu::gl_chips().size(), 10u);
  for (const char* paper : {"gt200", "gf110", "gk107", "gk20a", "gp107", "a320", "a330", "a530", "t760", "byt"})
    EXPECT_NE(gpu::gl_chip(paper), nullptr) << paper;
  for (const gpu::FamilySpec* s : gpu::gl_chips()) {
    EXPECT_NE(gpu::gl_vendor(s->compiler->driver), nullptr) << s->family;
    EXPECT_FALSE(s->source.empty()) << s->family;
    EXPECT_GT(s->clock_mhz, 0) << s->family;
    EXPECT_GT(s->bandwidth_gbs, 0) << s->family;
    EXPECT_FALSE(s->caches.empty()) << s->family;
  }
}

}  // namespace
}  // namespace aovar
