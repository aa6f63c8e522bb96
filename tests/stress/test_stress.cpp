// aovar stress: the shipped variants pass the suite on both backends (the CI subset), a guard removed
// from a template makes the suite fail with a reproducer that reproduces, checks are reused, bad input
// gets one-line errors.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>

#include <nlohmann/json.hpp>

#include "reference/reference.h"
#include "scene/scene.h"
#include "stress/checks.h"
#include "stress/stress.h"
#include "test_support.h"
#include "util/fs.h"
#include "util/shell.h"

namespace aovar::test {
namespace {

namespace fs = std::filesystem;

// The reduced suite CI runs: every shipped variant of the default manifest, every default case, both backends.
TEST(Stress, ShippedVariantsPassEveryCaseOnBothBackends) {
  TempDir dir;
  auto r = run_aovar("stress --shipped --backend lavapipe,osmesa --out " + dir.path().string());
  ASSERT_EQ(r.status, 0) << r.output;
  auto j = read_json(dir / "stress.json");
  const auto cases = stress::default_cases();
  ASSERT_GE(j.at("variants").size(), 6u);
  for (const auto& v : j.at("variants")) {
    EXPECT_TRUE(v.at("shipped").get<bool>()) << v;
    EXPECT_TRUE(v.at("passed").get<bool>()) << v;
    EXPECT_EQ(v.at("checks").get<std::size_t>(), 2 * cases.size()) << v.at("variant");
  }
  bool sao_far = false;
  for (const auto& c : j.at("checks")) {
    EXPECT_EQ(c.at("nan").get<long>(), 0) << c;
    EXPECT_EQ(c.at("inf").get<long>(), 0) << c;
    EXPECT_EQ(c.at("out_of_range").get<long>(), 0) << c;
    EXPECT_GT(c.at("pixels").get<long>(), 0) << c;
    // SAO's linear z / far depth key left every pixel nearer than far / 65536 keyed 0 and the keyed blur
    // divided by it: 1290 NaN of 5184 pixels on far-1e6 before common/key.glsl keyed log depth.
    if (c.at("variant").get<std::string>().rfind("sao-", 0) == 0 && c.at("case") == "far-1e6") sao_far = true;
  }
  EXPECT_TRUE(sao_far);
  // The mediump variant is compared with its highp form on every case.
  bool compared = false;
  for (const auto& c : j.at("checks"))
    if (c.at("variant") == "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-mp")
      compared = compared || c.at("partner") == "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp";
  EXPECT_TRUE(compared);
  EXPECT_NE(util::read_file(dir / "stress.md").value().find("| alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp | yes |"),
            std::string::npos);

  // A second run checks nothing again.
  auto again = run_aovar("stress --shipped --backend lavapipe,osmesa --out " + dir.path().string());
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("(" + std::to_string(j.at("checks").size()) + " reused)"), std::string::npos) << again.output;
}

// The mobile path (issue 23): the shipped variants' GLSL ES programs pass every case on gles, whose driver
// runs mediump as it measured (fp16 on llvmpipe's ES) with no rewrite of ours. About 6 s.
TEST(Stress, ShippedVariantsPassEveryCaseOnGles) {
  TempDir dir;
  auto r = run_aovar("stress --shipped --backend gles --out " + dir.path().string());
  ASSERT_EQ(r.status, 0) << r.output;
  auto j = read_json(dir / "stress.json");
  ASSERT_GE(j.at("variants").size(), 6u);
  for (const auto& v : j.at("variants")) {
    EXPECT_TRUE(v.at("passed").get<bool>()) << v;
    EXPECT_EQ(v.at("checks").get<std::size_t>(), stress::default_cases().size()) << v.at("variant");
  }
  for (const auto& c : j.at("checks")) {
    EXPECT_EQ(c.at("backend"), "gles") << c;
    EXPECT_EQ(c.at("nan").get<long>() + c.at("inf").get<long>() + c.at("out_of_range").get<long>(), 0) << c;
  }
}

// Copy of the shader sources with Alchemy's tangent-plane guard removed (max(0, v . n - z beta) in
// common/obscurance.glsl, which Alchemy and SAO share; the test runs Alchemy: only taps
// above C's tangent plane occlude): taps below it then add negative occlusion and AO rises above 1 wherever
// the surface curves away or a tap falls off an edge. The suite must fail the shipped variant and print a
// command that reproduces the failure on its own. (Removing the final max(0, ...) alone, or Alchemy's
// epsilon alone, changes nothing here: the other guard catches what it lets through — llvmpipe's max()
// returns the non-NaN operand — which is the point of guarding in depth.) The copy's folder name holds a
// space and a quote: the reproducer must paste back into a shell (util::shell_quote). Exit 1: a check failed.
TEST(Stress, RemovingAGuardFailsWithAReproducer) {
  TempDir dir;
  const fs::path src = dir / "shader src's";
  fs::copy(fs::path(AOVAR_SOURCE_DIR) / "shader_src", src, fs::copy_options::recursive);
  const fs::path obscurance = src / "common" / "obscurance.glsl";
  std::string text = util::read_file(obscurance).value();
  const std::string guarded = "sum += max(0.0, dot(v, n) - z_bias) / (dot(v, v) + epsilon);";
  auto at = text.find(guarded);
  ASSERT_NE(at, std::string::npos) << "the guard this test removes moved: update the test";
  text.replace(at, guarded.size(), "sum += (dot(v, n) - z_bias) / (dot(v, v) + epsilon);");
  util::write_atomic(obscurance, text);

  const std::string manifest = util::shell_quote((src / "aovar.toml").string());
  const std::string key = "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp";
  auto r = run_aovar("stress --manifest " + manifest + " --variants " + key + " --case baseline --case screen-edges");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("FAIL " + key + " (shipped)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("outside [0, 1]"), std::string::npos) << r.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex("reproduce: aovar (stress [^\n]*)"))) << r.output;
  auto again = run_aovar(m[1].str());
  EXPECT_EQ(again.status, 1) << "the reproducer must fail again: " << m[1].str() << "\n" << again.output;
  EXPECT_NE(again.output.find("FAIL " + key), std::string::npos) << again.output;

  // The unmodified sources pass the same cases.
  auto clean = run_aovar("stress --variants " + key + " --case baseline --case screen-edges");
  EXPECT_EQ(clean.status, 0) << clean.output;
}

// Inverse-projection reconstruction rebuilt NDC z = 1 - near / z and unprojected it: with near = 1e-4 the
// depth came back ~2 % off and the r16f variant disagreed with its r32f form on 2.1 % of the pixels (6 of
// these 32 variants failed); common/unproject.glsl now unprojects on the near plane and scales the ray.
// The whole space runs in forked children (lavapipe never frees per-render memory): slices give the checks
// one process gives, and a renderer crash costs the variant it hit, not the run.
TEST(Stress, ChildProcessesMatchOneProcessAndSurviveACrash) {
  TempDir dir;
  const std::string variants = "--variants 'hbao-s04-p0-nrgb8-zdep-rst-d*-bbil-x1-?\?' --case baseline --case far-1e6 --no-reuse";
  auto one = run_aovar("stress " + variants + " --renders-per-process 0 --out " + (dir / "one").string());
  ASSERT_EQ(one.status, 0) << one.output;
  auto sliced = run_aovar("stress " + variants + " --renders-per-process 2 --out " + (dir / "sliced").string());
  ASSERT_EQ(sliced.status, 0) << sliced.output;
  auto a = read_json(dir / "one" / "stress.json").at("checks"), b = read_json(dir / "sliced" / "stress.json").at("checks");
  ASSERT_EQ(a.size(), 6u);
  EXPECT_EQ(a, b);

  const std::string crashing = "hbao-s04-p0-nrgb8-zdep-rst-d32-bbil-x1-hp";
  test::CommandResult crashed;
  {
    ScopedEnv crash("AOVAR_STRESS_TEST_CRASH", crashing.c_str());
    crashed = run_aovar("stress " + variants + " --renders-per-process 2 --out " + (dir / "crash").string());
  }
  EXPECT_EQ(crashed.status, 0) << crashed.output;  // not shipped: listed, not fatal
  auto j = read_json(dir / "crash" / "stress.json");
  ASSERT_EQ(j.at("checks").size(), 6u) << crashed.output;
  EXPECT_EQ(j.at("failed").get<int>(), 1);
  for (const auto& c : j.at("checks")) {
    if (c.at("variant") == crashing) {
      EXPECT_NE(c.at("failure").get<std::string>().find("the renderer crashed (signal 6"), std::string::npos) << c;
    } else {
      EXPECT_EQ(c.at("failure"), "") << c;  // its group rendered again without it
      EXPECT_GT(c.at("pixels").get<long>(), 0) << c;
    }
  }
  // The reproducer, without the crash, passes.
  std::smatch m;
  const std::string out = crashed.output;
  ASSERT_TRUE(std::regex_search(out, m, std::regex("reproduce: aovar (stress [^\\n]*" + crashing + "[^\\n]*)")))
      << out;
  auto again = run_aovar(m[1].str() + " --out " + (dir / "again").string());
  EXPECT_EQ(again.status, 0) << again.output;
  EXPECT_EQ(read_json(dir / "again" / "stress.json").at("failed").get<int>(), 0);
}

// A whole line from the child that is not a check (bad JSON: the child's memory is not to be trusted) is a
// crashed slice: that variant fails with the line quoted, its group renders again without it, the run goes on.
TEST(Stress, AGarbledChildLineCostsOnlyThatVariant) {
  TempDir dir;
  const std::string variants = "--variants 'hbao-s04-p0-nrgb8-zdep-rst-d*-bbil-x1-?\?' --case baseline --no-reuse";
  const std::string garbled = "hbao-s04-p0-nrgb8-zdep-rst-d16-bbil-x1-hp";
  test::CommandResult r;
  {
    ScopedEnv garble("AOVAR_STRESS_TEST_GARBLE", garbled.c_str());
    r = run_aovar("stress " + variants + " --renders-per-process 2 --out " + (dir / "garbled").string());
  }
  auto j = read_json(dir / "garbled" / "stress.json");
  ASSERT_EQ(j.at("checks").size(), 3u) << r.output;
  EXPECT_EQ(j.at("failed").get<int>(), 1) << r.output;
  for (const auto& c : j.at("checks")) {
    if (c.at("variant") == garbled)
      EXPECT_NE(c.at("failure").get<std::string>().find("the renderer sent a line that is not a check"),
                std::string::npos) << c;
    else
      EXPECT_EQ(c.at("failure"), "") << c;
  }
}

// A crash costs only the variant it hits, wherever it sits in its partner group: the r32f highp form
// (rendered first, since the others compare with it) or the r16f highp form (compared with the r32f form,
// and itself the mediump form's partner). The crashed variant fails with the signal on the case in flight
// and is reported not rendered on the others; every other member's checks are those of a run without the
// crash, except that a member whose partner crashed says it compared with nothing (partner "") rather
// than naming a partner whose image never existed (pair_max 0 read as "identical").
TEST(Stress, ACrashAnywhereInAGroupCostsOnlyThatVariant) {
  TempDir dir;
  const std::string variants = "--variants 'hbao-s04-p0-nrgb8-zdep-rst-d*-bbil-x1-?\?' --case baseline --case far-1e6 "
                               "--no-reuse --renders-per-process 2";
  const std::string d32 = "hbao-s04-p0-nrgb8-zdep-rst-d32-bbil-x1-hp", d16 = "hbao-s04-p0-nrgb8-zdep-rst-d16-bbil-x1-hp",
                    mp = "hbao-s04-p0-nrgb8-zdep-rst-d16-bbil-x1-mp";
  auto clean = run_aovar("stress " + variants + " --out " + (dir / "clean").string());
  ASSERT_EQ(clean.status, 0) << clean.output;
  std::map<std::string, nlohmann::json> expected;  // variant|case
  const auto clean_json = read_json(dir / "clean" / "stress.json");
  for (const auto& c : clean_json.at("checks"))
    expected[c.at("variant").get<std::string>() + "|" + c.at("case").get<std::string>()] = c;
  ASSERT_EQ(expected.size(), 6u);
  for (const std::string c : {"baseline", "far-1e6"}) {
    EXPECT_EQ(expected.at(d32 + "|" + c).at("partner"), "");
    EXPECT_EQ(expected.at(d16 + "|" + c).at("partner"), d32);
    EXPECT_EQ(expected.at(mp + "|" + c).at("partner"), d16);
    EXPECT_GT(expected.at(mp + "|" + c).at("pair_max").get<double>(), 0.0);  // fp16 shows: a real comparison
  }

  for (const std::string& crashing : {d32, d16}) {
    SCOPED_TRACE("crash on " + crashing);
    const fs::path out = dir / ("crash-" + crashing);
    test::CommandResult r;
    {
      ScopedEnv crash("AOVAR_STRESS_TEST_CRASH", crashing.c_str());
      r = run_aovar("stress " + variants + " --out " + out.string());
    }
    EXPECT_EQ(r.status, 0) << r.output;  // not shipped: listed, not fatal
    auto j = read_json(out / "stress.json");
    ASSERT_EQ(j.at("checks").size(), 6u) << r.output;
    EXPECT_EQ(j.at("failed").get<int>(), 1);
    for (const auto& v : j.at("variants")) EXPECT_EQ(v.at("passed").get<bool>(), v.at("variant") != crashing) << v;
    for (const auto& c : j.at("checks")) {
      const std::string variant = c.at("variant"), case_name = c.at("case");
      if (variant == crashing) {
        const std::string failure = c.at("failure");
        if (case_name == "baseline") {
          EXPECT_EQ(failure.rfind("the renderer crashed (signal 6", 0), 0u) << c;
          EXPECT_NE(failure.find("rendering this case"), std::string::npos) << c;
        } else {
          EXPECT_EQ(failure.rfind("not rendered: the renderer crashed (signal 6", 0), 0u) << c;
          EXPECT_NE(failure.find("on case baseline"), std::string::npos) << c;
        }
        EXPECT_EQ(c.at("pixels").get<long>(), 0) << c;
        EXPECT_EQ(c.at("inputs_hash"), expected.at(variant + "|" + case_name).at("inputs_hash")) << c;
        continue;
      }
      auto want = expected.at(variant + "|" + case_name);
      if (want.at("partner") == crashing) want["partner"] = "", want["pair_max"] = 0.0, want["pair_share"] = 0.0;
      EXPECT_EQ(c, want);  // rendered again without the crashed one: the same images, the same checks
    }
  }
}

// mediump runs in real fp16 on lavapipe (render::BackendOptions::mediump_as_fp16), so mediump and highp
// differ; in fp32 they cannot. HBAO squared scene-sized offsets and R in mediump: at radius 1e4, R^2
// overflowed fp16 and every sample was rejected (99 % AO difference from highp on radius-1e4) until the
// falloff moved to highp (ao/hbao.glsl).
TEST(Stress, MediumpRunsInFp16AndLargeRadiiStayInItsRange) {
  TempDir dir;
  const std::string pair = "--variants hbao-s08-p0-ndep-zdep-rst-d16-bno-x1-mp --variants hbao-s08-p0-ndep-zdep-rst-d16-bno-x1-hp "
                           "--case baseline --case radius-1e4 --no-reuse";
  auto fp16 = run_aovar("stress " + pair + " --out " + (dir / "fp16").string());
  ASSERT_EQ(fp16.status, 0) << fp16.output;
  auto j = read_json(dir / "fp16" / "stress.json");
  EXPECT_EQ(j.at("failed").get<int>(), 0) << fp16.output;
  int compared = 0;
  for (const auto& c : j.at("checks"))
    if (c.at("partner") != "") {
      ++compared;
      EXPECT_GT(c.at("pair_max").get<double>(), 0.0) << c;  // fp16 rounding shows
      EXPECT_EQ(c.at("nan").get<long>() + c.at("inf").get<long>(), 0) << c;
      EXPECT_LE(c.at("pair_share").get<double>(), 0.01) << c;
    }
  EXPECT_EQ(compared, 2);

  auto fp32 = run_aovar("stress " + pair + " --mediump-fp32 --out " + (dir / "fp32").string());
  ASSERT_EQ(fp32.status, 0) << fp32.output;
  const auto fp32_json = read_json(dir / "fp32" / "stress.json");  // bound: a temporary's member would dangle in the loop
  ASSERT_EQ(fp32_json.at("checks").size(), 4u);
  for (const auto& c : fp32_json.at("checks")) EXPECT_EQ(c.at("pair_max").get<double>(), 0.0) << c;
}

TEST(Stress, InverseProjectionKeepsDepthWithATinyNearPlane) {
  auto r = run_aovar("stress --variants 'alchemy-s0[46]-p0-*-zdep-rip-d*-bno-x[12]-hp' --case near-1e-4 "
                     "--case near-1e-4-far-1e6");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("32 variants x 2 cases"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(", 0 variants failed"), std::string::npos) << r.output;
}

TEST(Stress, CustomCaseAndBadInput) {
  // A custom case: the form a randomised search prints.
  auto ok = run_aovar("stress --variants alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp --scene builtin:stairs --eye 4,2,6 "
                      "--target -1,0.5,1 --near 0.01 --far 1e6 --radius 0.3");
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_NE(ok.output.find("1 variants x 1 cases"), std::string::npos) << ok.output;

  auto near = run_aovar("stress --variants alchemy-s08-* --scene builtin:stairs --eye 4,2,6 --target 0,0,0 --near 0");
  EXPECT_NE(near.status, 0);
  EXPECT_NE(near.output.find("--near 0 must be > 0"), std::string::npos) << near.output;
  auto vec = run_aovar("stress --scene builtin:stairs --eye 4,2 --target 0,0,0");
  EXPECT_NE(vec.status, 0);
  EXPECT_NE(vec.output.find("--eye: expected x,y,z"), std::string::npos) << vec.output;
  auto unknown = run_aovar("stress --case nope");
  EXPECT_NE(unknown.status, 0);
  EXPECT_NE(unknown.output.find("unknown --case 'nope' (cases: baseline,"), std::string::npos) << unknown.output;

  // A [ship] glob that matches nothing names the manifest line.
  TempDir dir;
  fs::copy(fs::path(AOVAR_SOURCE_DIR) / "shader_src", dir / "shader_src", fs::copy_options::recursive);
  const fs::path manifest = dir / "shader_src" / "aovar.toml";
  std::string text = util::read_file(manifest).value();
  auto at = text.find("variants = [\n");
  ASSERT_NE(at, std::string::npos);
  text.insert(at + 13, "  \"alchemy-s99-*\",\n");
  util::write_atomic(manifest, text);
  auto typo = run_aovar("stress --shipped --manifest " + manifest.string());
  EXPECT_NE(typo.status, 0);
  EXPECT_NE(typo.output.find("aovar.toml:"), std::string::npos) << typo.output;
  EXPECT_NE(typo.output.find("[ship] glob 'alchemy-s99-*' matches no variant"), std::string::npos) << typo.output;
}

// A scaled case fails when its error against its own reference moves past the tolerance from its
// original's, and the comparison is not repeated on checks an earlier run already compared.
TEST(Stress, ScaledCasesCompareTheirErrorWithTheOriginal) {
  const auto cases = stress::default_cases();
  ASSERT_TRUE(std::any_of(cases.begin(), cases.end(), [](const auto& c) { return c.scale_of == "baseline"; }));
  stress::Options o;
  auto check = [](const std::string& variant, const std::string& case_name, double rmse) {
    stress::Check c;
    c.variant = variant, c.backend = "lavapipe", c.case_name = case_name, c.rmse = rmse;
    return c;
  };
  std::vector<stress::Check> checks = {check("a", "baseline", 0.100), check("a", "scale-100", 0.103),
                                       check("b", "baseline", 0.100), check("b", "scale-0.01", 0.120),
                                       check("c", "scale-100", 0.5)};  // no original: nothing to compare
  stress::detail::compare_scaled(checks, cases, o);
  EXPECT_EQ(checks[1].failure, "");
  EXPECT_EQ(checks[3].failure,
            "RMSE 0.1200 against the reference, 0.1000 in baseline: off by 0.0200 (> 0.005) when the scene is scaled");
  EXPECT_EQ(checks[4].failure, "");
  stress::detail::compare_scaled(checks, cases, o);
  EXPECT_EQ(checks[3].failure.find("scaled"), checks[3].failure.rfind("scaled")) << "compared once";
}

TEST(Stress, DefaultCasesSeeWhatTheyClaim) {
  // Each case's camera must see what its description says: a camera inside geometry (every primary ray
  // hits a back face) reads as occluded everywhere and tests nothing. Checked on the ray-traced view.
  for (const auto& c : stress::default_cases()) {
    auto scene = scene::load_scene(c.scene);
    reference::ReferenceOptions ro;
    ro.size = {48, 27};
    ro.rays = 16;
    ro.radius = c.radius > 0 ? c.radius : scene.ao_radius;
    auto ref = reference::trace_reference(scene, c.view, ro);
    auto stats = reference::reference_stats(ref);
    if (c.name == "all-background") {
      EXPECT_EQ(stats.background_share, 1.0) << c.name;
      continue;
    }
    EXPECT_LT(stats.background_share, 0.9) << c.name << ": the camera sees (almost) nothing";
    if (c.name != "radius-1e4") {  // a 1e4 hemisphere holds the whole scene: dark by design
      EXPECT_GT(stats.mean_visibility, 0.5) << c.name << ": occluded everywhere (camera inside geometry?)";
    }
  }
  auto custom = stress::custom_case("builtin:atrium", {0, 1, 5}, {0, 1, 0}, 60, 0.1f, std::numeric_limits<float>::infinity(), 0);
  EXPECT_EQ(stress::case_arguments(custom),
            "--scene builtin:atrium --eye 0,1,5 --target 0,1,0 --up 0,1,0 --fov 60 --near 0.100000001 --far inf --radius 0");
  EXPECT_THROW(stress::custom_case("builtin:atrium", {0, 1, 5}, {0, 1, 5}, 60, 0.1f, 10, 0), std::runtime_error);
}

}  // namespace
}  // namespace aovar::test
