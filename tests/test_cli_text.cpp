// What the CLI prints, formatted by the libraries: compile (list, generate), analyze, reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "analyze/text.h"
#include "compile/text.h"
#include "reference/text.h"

namespace {
using namespace aovar;

int count_lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// Three variants (the third the same programs as the first), one dropped by a rule on line 12, one target.
compile::CompiledSpace small_space() {
  compile::CompiledSpace c;
  c.manifest.path = "shader_src/aovar.toml";
  variants::Rule rule;
  rule.reason = "progressive needs a history buffer";
  rule.pos.line = 12;
  c.manifest.rules.push_back(rule);
  c.space.space = 8;
  c.space.collapsed = 3;
  for (const char* key : {"alchemy-s08-a", "alchemy-s16-b", "sao-s08-c"}) c.space.variants.push_back({key, {}, {}});
  c.space.pruned.push_back({"alchemy-s08-p1-x", 0});
  c.variant_same_as = {-1, -1, 0};
  c.dedup = 2;
  c.targets = {variants::Target::vulkan};
  compile::TargetStats st;
  st.programs = 6;
  st.unique = 4;
  st.compiled = 3;
  st.cached = 1;
  st.failed = 0;
  st.spirv_bytes = 12345;
  c.stats = {st};
  return c;
}

TEST(CliText, ListNamesEachVariantItsDuplicateAndTheCounts) {
  auto c = small_space();
  EXPECT_EQ(compile::list_text(c, false),
            "alchemy-s08-a\nalchemy-s16-b\nsao-s08-c  same as alchemy-s08-a\n# space 8 / rules 3 / dedup 2\n");
}

TEST(CliText, ListPrunedAddsEachRuleDropWithReasonAndManifestLine) {
  auto c = small_space();
  std::string text = compile::list_text(c, true);
  EXPECT_NE(text.find("alchemy-s08-p1-x  dropped: progressive needs a history buffer (shader_src/aovar.toml:12)\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text, compile::list_text(c, false).insert(text.find("alchemy-s08-p1-x"),
                                                       compile::rule_drops_text(c.manifest, c.space)));
  EXPECT_EQ(count_lines(text), 5);
}

TEST(CliText, SummaryTableHasOneRowPerTargetAndTheCountsLine) {
  auto c = small_space();
  std::string table = compile::summary_table(c);
  EXPECT_EQ(count_lines(table), 3) << table;
  EXPECT_EQ(table.rfind("target ", 0), 0u) << table;
  EXPECT_NE(table.find("vulkan           6       4         3       1       0        12345\n"), std::string::npos)
      << table;
  EXPECT_NE(table.find("space 8 / rules 3 / dedup 2  (3 variants)\n"), std::string::npos) << table;
  // A no-op generate prints the counts part of the recorded table.
  std::string noop = compile::up_to_date_text(table, "out", 0.25);
  EXPECT_EQ(noop, "space 8 / rules 3 / dedup 2  (3 variants)\n"
                  "up to date: nothing compiled, no file written -> out (0.25 s)\n");
}

TEST(CliText, FailureLineCountsErrorsAndFailedBuilds) {
  auto c = small_space();
  c.errors = 2;
  c.stats[0].failed = 3;
  EXPECT_EQ(compile::failure_line(c), "aovar: 2 error(s), 3 program build(s) failed; nothing was written\n");
}

TEST(CliText, StaleTextListsTwentyFilesAndTheCommandToRun) {
  compile::OutputReport r;
  EXPECT_EQ(compile::stale_text(r, "gen"), "");
  for (int i = 0; i < 23; ++i) r.changed.push_back("gen/f" + std::to_string(i));
  std::string text = compile::stale_text(r, "gen");
  EXPECT_EQ(count_lines(text), 22) << text;
  EXPECT_NE(text.find("stale: gen/f19\n"), std::string::npos);
  EXPECT_EQ(text.find("stale: gen/f20\n"), std::string::npos);
  EXPECT_NE(text.find("stale: ... and 3 more\n"), std::string::npos);
  EXPECT_NE(text.find("aovar: 23 generated file(s) in gen are out of date: run aovar generate --out gen\n"),
            std::string::npos);
  r.unchanged = 7;
  r.written = 2;
  r.removed = 1;
  EXPECT_EQ(compile::up_to_date_line(r, "gen"), "7 files up to date in gen\n");
  EXPECT_EQ(compile::written_line(r, "gen", 1.5), "files: 2 written, 7 unchanged, 1 removed -> gen (1.50 s)\n");
}

TEST(CliText, AnalyzeSummaryCountsProgramsAndVariants) {
  analyze::Analysis a;
  a.programs.resize(5);
  a.variants.resize(2);
  EXPECT_EQ(analyze::summary_line(a, "gen/analysis.json"),
            "# 5 programs, 2 variants (counts per pixel, upper bounds) -> gen/analysis.json\n");
}

TEST(CliText, ReferenceTableHasEachViewItsFiguresAndTheScene) {
  reference::RunResult r;
  r.scene = "builtin:atrium";
  r.triangles = 1234;
  r.wall_s = 2.5;
  reference::RunView v;
  v.view = "overview";
  v.options.size = {64, 32};
  v.options.rays = 16;
  v.options.radius = 0.5f;
  v.stats.mean_visibility = 0.75;
  v.stats.mean_std_error = 0.0125;
  v.stats.background_share = 0.1;
  v.trace_s = 2;
  v.rays_traced = 4'000'000;
  r.views.push_back(v);
  v.view = "closeup";
  v.from_cache = true;
  v.trace_s = 0;
  r.views.push_back(v);
  std::string text = reference::to_text(r, "refs");
  EXPECT_EQ(count_lines(text), 4) << text;
  EXPECT_EQ(text.rfind("view ", 0), 0u) << text;
  // size, rays, mode, radius, mean visibility, mean error, background %, trace s, Mrays/s
  EXPECT_NE(text.find("overview         64x32     16 occlusion       0.5    0.7500    0.0125    10.0      2.00     2.00\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("closeup "), std::string::npos);
  EXPECT_NE(text.find("0.00  (cached)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("# scene builtin:atrium (1234 triangles) in 2.5 s -> refs/reference.json\n"), std::string::npos)
      << text;
}

}  // namespace
