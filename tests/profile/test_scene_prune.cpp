// Scene-profile pruning inside `aovar measure` and `aovar sweep` (issue 8): the variants a scene's profile
// drops are never compiled nor measured, each is listed with its rule and reason (measure.json "pruned",
// cost_table.json meta.pruned), a repeated run reads the stored profile back, and --no-prune measures them.
// builtin:far at 320x180 drops r16f (its depths make half-float steps ~11 % of the radius) and half
// resolution (radius under one AO pixel), and keeps r32f at full resolution; builtin:stairs keeps all four.
#include <gtest/gtest.h>

#include <set>

#include <nlohmann/json.hpp>

#include "table/table.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

const std::string kKept = "alchemy-s04-p0-nrgb8-zdep-rst-d32-bsep-x1-hp";
const std::set<std::string> kDropped = {"alchemy-s04-p0-nrgb8-zdep-rst-d16-bsep-x1-hp",
                                        "alchemy-s04-p0-nrgb8-zdep-rst-d16-bsep-x2-hp",
                                        "alchemy-s04-p0-nrgb8-zdep-rst-d32-bsep-x2-hp"};
const std::string kSelection =
    " --view overview --size 320x180 --reps 1 --warmup 0 --variants 'alchemy-s04-p0-nrgb8-zdep-rst-d*-bsep-x[12]-hp'";

std::set<std::string> row_variants(const json& rows) {
  std::set<std::string> out;
  for (const auto& r : rows)
    if (!r.value("is_baseline", false)) out.insert(r.at("variant").get<std::string>());
  return out;
}

// Every dropped variant with its decision and the evidence, as `aovar list --scene --pruned` prints it.
void expect_listed(const json& pruned, const std::set<std::string>& dropped) {
  std::set<std::string> listed;
  for (const auto& v : pruned.at("variants")) {
    const std::string rule = v.at("rule"), reason = v.at("reason");
    listed.insert(v.at("variant").get<std::string>());
    EXPECT_EQ(reason.rfind(rule + ": ", 0), 0u) << reason;
    EXPECT_GT(reason.size(), rule.size() + 20) << "the evidence: " << reason;
  }
  EXPECT_EQ(listed, dropped);
  EXPECT_EQ(pruned.at("dropped"), dropped.size());
  int by_rule = 0;
  for (const auto& [rule, n] : pruned.at("rules").items()) by_rule += n.get<int>();
  EXPECT_EQ(by_rule, static_cast<int>(dropped.size()));
}

TEST(ScenePrune, MeasureNeverCompilesWhatTheSceneDropsAndListsEachWithItsReason) {
  TempDir dir;
  const fs::path out = dir / "m";
  const std::string args = "measure --scene builtin:far" + kSelection + " --baseline " + kKept + " --out " + out.string();
  auto first = run_aovar(args);
  ASSERT_EQ(first.status, 0) << first.output;
  json m = read_json(out / "measure.json");
  EXPECT_EQ(row_variants(m.at("rows")), std::set<std::string>{kKept});
  // Compiled: the kept variant alone (the counts line is the compiled space's).
  EXPECT_NE(m.at("counts").get<std::string>().find("selected 1 /"), std::string::npos) << m.at("counts");
  const json& pruned = m.at("pruned");
  EXPECT_EQ(pruned.at("scene"), "builtin:far");
  EXPECT_EQ(pruned.at("selected"), 4);
  EXPECT_EQ(pruned.at("kept"), 1);
  expect_listed(pruned, kDropped);
  EXPECT_FALSE(pruned.at("profile_reused").get<bool>());
  ASSERT_TRUE(fs::exists(out / "profile.json"));
  EXPECT_NE(first.output.find("builtin:far keeps 1 of 4 selected variants; drops 3"), std::string::npos) << first.output;

  // The same run again: the stored profile is read back (its inputs are unchanged) and nothing is measured.
  auto again = run_aovar(args);
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("profile reused"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("1 rows (1 reused)"), std::string::npos) << again.output;
  EXPECT_TRUE(read_json(out / "measure.json").at("pruned").at("profile_reused").get<bool>());
  // Another radius is another profile.
  auto other = run_aovar(args + " --radius 9");
  ASSERT_EQ(other.status, 0) << other.output;
  EXPECT_EQ(other.output.find("profile reused"), std::string::npos) << other.output;

  // --no-prune measures every selected variant, and lists nothing as pruned.
  auto all = run_aovar(args + " --no-prune");
  ASSERT_EQ(all.status, 0) << all.output;
  m = read_json(out / "measure.json");
  std::set<std::string> every = kDropped;
  every.insert(kKept);
  EXPECT_EQ(row_variants(m.at("rows")), every);
  EXPECT_TRUE(m.at("pruned").is_null());
}

TEST(ScenePrune, MeasureWithEverySelectedVariantDroppedMeasuresNothingAndSaysWhy) {
  TempDir dir;
  const fs::path out = dir / "m";
  auto r = run_aovar("measure --scene builtin:far --variants 'alchemy-s04-p0-nrgb8-zdep-rst-d16-bsep-x[12]-hp'" +
                     std::string(" --view overview --size 320x180 --reps 1 --warmup 0 --out ") + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("drops every selected variant"), std::string::npos) << r.output;
  json m = read_json(out / "measure.json");
  EXPECT_TRUE(m.at("rows").empty());
  expect_listed(m.at("pruned"), {"alchemy-s04-p0-nrgb8-zdep-rst-d16-bsep-x1-hp", "alchemy-s04-p0-nrgb8-zdep-rst-d16-bsep-x2-hp"});
}

TEST(ScenePrune, SweepMeasuresEachVariantOnlyOnTheScenesThatKeepIt) {
  TempDir dir;
  const fs::path out = dir / "sweep";
  const std::string args =
      "sweep --scene builtin:far --scene builtin:stairs --rays 16" + kSelection + " --out " + out.string();
  auto first = run_aovar(args);
  ASSERT_EQ(first.status, 0) << first.output;
  auto t = table::read_table(out / "cost_table.json");
  std::map<std::string, std::set<std::string>> by_scene;
  for (const auto& row : t.rows) by_scene[row.scene].insert(row.variant);
  std::set<std::string> every = kDropped;
  every.insert(kKept);
  EXPECT_EQ(by_scene["builtin:far"], std::set<std::string>{kKept});
  EXPECT_EQ(by_scene["builtin:stairs"], every) << "stairs keeps all four: compiled for it, measured there";
  ASSERT_TRUE(t.meta.profile_prune.value_or(false));
  const json pruned = table::to_json(t.meta).at("pruned");  // as the file says it
  ASSERT_EQ(pruned.size(), 2u);
  EXPECT_EQ(pruned.at(0).at("scene"), "builtin:far");
  expect_listed(pruned.at(0), kDropped);
  EXPECT_EQ(pruned.at(1).at("scene"), "builtin:stairs");
  expect_listed(pruned.at(1), {});
  EXPECT_EQ(pruned.at(0).at("profile"), "measure/builtin_far/profile.json");
  // The counts: on stdout (the Markdown table's footer), in cost_table.md and in the report.
  const std::string counts = "builtin:far: 4 selected, 1 kept, 3 dropped (";  // then the count per rule
  EXPECT_NE(first.output.find(counts), std::string::npos) << first.output;
  EXPECT_NE(util::read_file(out / "cost_table.md").value().find(counts), std::string::npos);
  EXPECT_NE(util::read_file(out / "report.md").value().find(counts), std::string::npos);
  EXPECT_NE(util::read_file(out / "report.html").value().find(counts), std::string::npos);
  EXPECT_NE(first.output.find("# scene profiles: 2 (0 reused)"), std::string::npos) << first.output;

  // Repeated: both profiles are read back, nothing is measured, the table is the same.
  const std::string table = util::read_file(out / "cost_table.json").value();
  auto again = run_aovar(args);
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("# scene profiles: 2 (2 reused)"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("(0 measured, 5 reused"), std::string::npos) << again.output;
  EXPECT_EQ(util::read_file(out / "cost_table.json").value(), table);

  // --no-prune: the dropped variants are measured on far too (the kept rows are reused).
  auto all = run_aovar(args + " --no-prune");
  ASSERT_EQ(all.status, 0) << all.output;
  auto full = table::read_table(out / "cost_table.json");
  by_scene.clear();
  for (const auto& row : full.rows) by_scene[row.scene].insert(row.variant);
  EXPECT_EQ(by_scene["builtin:far"], every);
  EXPECT_FALSE(full.meta.pruned);
  EXPECT_EQ(all.output.find("Pruned before compiling"), std::string::npos) << all.output;
}

}  // namespace
}  // namespace aovar::test
