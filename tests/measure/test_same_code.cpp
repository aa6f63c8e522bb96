// Same code, same cost (issue 18): llvmpipe ignores RelaxedPrecision, so a mediump variant and its highp twin
// run the same code on lavapipe and OSMesa. The SPIR-V fingerprint sees through the decorations, the twins
// really render the same bits, and measure times one of each pair and copies its row to the other.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "compile/spirv_fingerprint.h"
#include "decide/pareto.h"
#include "measure/same_code.h"
#include "render_support.h"
#include "test_support.h"

namespace aovar::test {
namespace {

const std::vector<std::string> kBackends = {"lavapipe", "osmesa"};
const std::vector<std::string> kAlgorithms = {"alchemy", "sao", "gtao"};

// The highp key of an algorithm's 8-sample variant on the mobile buffers (r16f: mediump's only depth format).
std::string hp_key(const std::string& algorithm) {
  return fmt::format("{}-s08-p0-{}-zdep-rst-d16-bsep-x1-hp", algorithm, algorithm == "sao" ? "ndep" : "nrgb8");
}
std::string mp_key(const std::string& algorithm) {
  std::string k = hp_key(algorithm);
  return k.replace(k.size() - 2, 2, "mp");
}

const compile::CompiledSpace& twins() {
  static const compile::CompiledSpace c = [] {
    std::vector<std::string> keys;
    for (const auto& a : kAlgorithms) keys.insert(keys.end(), {hp_key(a), mp_key(a)});
    return compile_variants(keys);
  }();
  return c;
}

// The SPIR-V of a program by key on a target (the canonical copy of a deduplicated one).
const std::vector<std::uint32_t>& spirv(const compile::CompiledSpace& c, variants::Target t, const std::string& key) {
  const int ti = c.target_index(t);
  for (std::size_t p = 0; p < c.space.programs.size(); ++p)
    if (c.space.programs[p].key == key) {
      const int canon = c.builds[ti][p].same_as >= 0 ? c.builds[ti][p].same_as : static_cast<int>(p);
      return c.builds[ti][canon].output.spirv;
    }
  throw std::runtime_error("no program " + key);
}

// The AO fragment program of an algorithm's 8-sample variant: "<algorithm>-s08-...-hp.frag".
std::string ao_program(const compile::CompiledSpace& c, const std::string& algorithm, const std::string& precision) {
  for (const auto& p : c.space.programs)
    if (p.key.rfind(algorithm + "-s08-", 0) == 0 && p.key.ends_with("-" + precision + ".frag")) return p.key;
  throw std::runtime_error("no AO program for " + algorithm + " " + precision);
}

TEST(SameCode, FingerprintIgnoresRelaxedPrecisionAndDebugOnly) {
  const auto& c = twins();
  const auto relaxed = compile::relaxed_precision_only();
  for (const auto& a : kAlgorithms) {
    const auto& hp = spirv(c, variants::Target::vulkan, ao_program(c, a, "hp"));
    const auto& mp = spirv(c, variants::Target::vulkan, ao_program(c, a, "mp"));
    ASSERT_FALSE(hp.empty());
    EXPECT_NE(hp, mp) << a << ": mediump should add RelaxedPrecision decorations on Vulkan";
    EXPECT_EQ(compile::executable_fingerprint(hp, relaxed), compile::executable_fingerprint(mp, relaxed)) << a;
    EXPECT_NE(compile::executable_fingerprint(hp, {}), compile::executable_fingerprint(mp, {})) << a;
    // GL SPIR-V (what stands for OSMesa's GLSL) of the twins: the same code once the decorations are ignored.
    const auto& ghp = spirv(c, variants::Target::gl45, ao_program(c, a, "hp"));
    const auto& gmp = spirv(c, variants::Target::gl45, ao_program(c, a, "mp"));
    ASSERT_FALSE(ghp.empty());
    EXPECT_EQ(compile::executable_fingerprint(ghp, relaxed), compile::executable_fingerprint(gmp, relaxed)) << a;
  }
  const auto& alchemy = spirv(c, variants::Target::vulkan, ao_program(c, "alchemy", "hp"));
  const auto& gtao = spirv(c, variants::Target::vulkan, ao_program(c, "gtao", "hp"));
  EXPECT_NE(compile::executable_fingerprint(alchemy, relaxed), compile::executable_fingerprint(gtao, relaxed));
  EXPECT_THROW(compile::executable_fingerprint({1, 2, 3, 4, 5, 6}, relaxed), std::runtime_error);
  EXPECT_EQ(compile::executable_fingerprint({}, relaxed), "");
}

TEST(SameCode, IdentityGroupsTwinsPerTargetAndKeepsTheBaseline) {
  const auto& c = twins();
  for (const auto& b : kBackends) {
    const variants::Target t = target_of(b);
    std::vector<int> vs;
    std::vector<std::string> ids;
    for (const auto& a : kAlgorithms)
      for (const auto& key : {hp_key(a), mp_key(a)}) {
        vs.push_back(variant_index(c, key));
        ids.push_back(measure::executable_identity(c, c.target_index(t), render::plan_pipeline(c, vs.back(), t),
                                                   compile::relaxed_precision_only()));
      }
    std::map<int, int> expected;
    for (const auto& a : kAlgorithms) expected[variant_index(c, mp_key(a))] = variant_index(c, hp_key(a));
    EXPECT_EQ(measure::group_twins(vs, ids, -1), expected) << b << ": each mp twin runs its hp variant's code";
    // The baseline leads its group even when it sorts after its twin.
    const int mp = variant_index(c, mp_key("gtao")), hp = variant_index(c, hp_key("gtao"));
    EXPECT_EQ(measure::group_twins(vs, ids, mp).at(hp), mp) << b;
  }
}

// The rule rests on this, checked for real: on both drivers the twins render the same bits.
TEST(SameCode, MediumpAndHighpTwinsRenderBitIdenticalImages) {
  const auto& c = twins();
  auto sc = scene::load_scene("builtin:stairs");
  for (const auto& b : kBackends) {
    auto backend = render::make_backend(b, {});
    backend->set_scene(sc);
    for (const auto& a : kAlgorithms) {
      auto render = [&](const std::string& key) {
        auto plan = render::plan_pipeline(c, variant_index(c, key), target_of(b));
        return render_plan(*backend, plan, sc.views[0], {64, 36}, sc.ao_radius, 1);
      };
      const image::FloatImage hp = render(hp_key(a)), mp = render(mp_key(a));
      ASSERT_FALSE(hp.pixels.empty());
      EXPECT_TRUE(measure::same_pixels(hp, mp))
          << b << " " << a << ": mean |hp - mp| = " << compare(hp, mp).mean_abs;
    }
  }
}

const measure::MeasureRow& row_of(const measure::MeasureResult& r, const std::string& key, const std::string& backend) {
  for (const auto& row : r.rows)
    if (row.variant == key && row.backend == backend) return row;
  throw std::runtime_error("no row " + key + " on " + backend);
}

TEST(SameCode, MeasureTimesOneTwinAndCopiesItsRow) {
  TempDir dir;
  const std::string hp = hp_key("alchemy"), mp = mp_key("alchemy");
  auto o = tiny_measure(dir.path(), {hp, mp}, "alchemy-s04-p0-nrgb8-zdep-rst-d16-bsep-x1-hp");
  o.backends = kBackends;
  o.timing.reps = 3;
  o.truth.enabled = true;
  o.truth.rays = 8;
  std::vector<std::string> notes;
  auto r = measure::run_measure(o, [&](const std::string& s) {
    if (s.rfind("note: ", 0) == 0) notes.push_back(s);
  });
  EXPECT_TRUE(notes.empty()) << notes.front();
  for (const auto& b : kBackends) {
    const auto& h = row_of(r, hp, b);
    const auto& m = row_of(r, mp, b);
    EXPECT_EQ(h.same_code_as, "") << b;
    EXPECT_EQ(m.same_code_as, hp) << b;
    EXPECT_EQ(m.time_ms.min, h.time_ms.min) << b;
    EXPECT_EQ(m.time_ms.median, h.time_ms.median) << b;
    EXPECT_EQ(m.rounds, h.rounds) << b;
    EXPECT_NE(m.inputs_hash, h.inputs_hash) << b;
    EXPECT_NE(m.spirv_hash, h.spirv_hash) << b;
    EXPECT_EQ(m.axes.at("precision"), "mediump") << b;
  }
  // One batch per backend, of the baseline and hp only: mp was never prepared.
  for (const auto& run : r.runs) EXPECT_EQ(run.pipelines, 2) << run.backend;
  for (const auto& d : r.devices) EXPECT_NE(d.precision.find("verified"), std::string::npos) << d.precision;

  auto rows = measure::cost_rows(r);
  decide::mark_pareto(rows);
  for (const auto& b : kBackends) {
    int front = 0;
    for (const auto& row : rows)
      if (row.backend == b && row.pareto && (row.variant == hp || row.variant == mp)) ++front;
    EXPECT_LE(front, 1) << b;
  }

  // A repeated run reuses the measured row and copies it again; the copy itself is never reused as a measurement.
  auto again = measure::run_measure(o);
  for (const auto& b : kBackends) {
    EXPECT_TRUE(row_of(again, hp, b).reused) << b;
    EXPECT_EQ(row_of(again, mp, b).same_code_as, hp) << b;
    EXPECT_EQ(row_of(again, mp, b).time_ms.min, row_of(again, hp, b).time_ms.min) << b;
  }
}

}  // namespace
}  // namespace aovar::test
