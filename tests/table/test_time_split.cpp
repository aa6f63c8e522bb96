// A row's time and its split (issue 55): gbuffer_ms, the format's G-buffer of each round, in cost_table.json,
// the CSV, merge and the reader's checks; the own part derived from it (table::time_split); and decisions
// that stay on the whole frame.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "cost_rows.h"
#include "decide/pareto.h"
#include "decide/select.h"
#include "selection.h"
#include "table/merge.h"
#include "table/table.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {

// A timed row whose rounds give a paired time, with its format's G-buffer draw: a quarter of its median frame.
table::CostRow split_row(const std::string& variant, std::vector<double> ratios, double rmse) {
  table::CostRow r = timed_row(variant, std::move(ratios), rmse, "b1", 4);
  r.time_ms.median = (r.time_ms.median + r.time_ms.p90) / 2;  // raw frames: not on the paired scale
  r.gbuffer_ms = util::TimeStats{0.75, r.time_ms.median / 4, r.time_ms.p90 / 2, r.time_ms.n};
  return r;
}

const std::vector<double> kSplitRatios = {1.5, 1.25, 1.75, 1.5, 1.5, 1.25, 1.75, 1.5};

// The column of `name` in a parsed CSV's header.
std::size_t csv_column(const std::vector<std::vector<std::string>>& lines, const std::string& name) {
  const auto it = std::find(lines.at(0).begin(), lines.at(0).end(), name);
  EXPECT_NE(it, lines.at(0).end()) << name;
  return static_cast<std::size_t>(it - lines.at(0).begin());
}

TEST(TimeSplit, TheOwnPartIsTheDecisionTimeLessTheGbuffersShareOfIt) {
  const table::CostRow r = split_row("a", kSplitRatios, 0.1);
  const auto split = table::time_split(r);
  ASSERT_TRUE(split);
  const double decision = r.time_ms.decision();
  ASSERT_EQ(decision, r.time_ms.paired) << "the paired time decides";
  EXPECT_DOUBLE_EQ(split->gbuffer, decision * r.gbuffer_ms->median / r.time_ms.median);
  EXPECT_DOUBLE_EQ(split->gbuffer, decision / 4) << "the G-buffer is a quarter of the median frame";
  EXPECT_DOUBLE_EQ(split->own + split->gbuffer, decision);

  table::CostRow unpaired = r;
  unpaired.time_ms.paired = 0;
  EXPECT_DOUBLE_EQ(table::time_split(unpaired)->gbuffer, unpaired.time_ms.min / 4) << "the min decides then";

  table::CostRow unknown = r;
  unknown.gbuffer_ms.reset();
  EXPECT_FALSE(table::time_split(unknown)) << "no G-buffer times: no split";
}

TEST(TimeSplit, RoundTripsThroughJsonAndCsv) {
  table::CostTable t;
  t.rows = {split_row("a", kSplitRatios, 0.1), plain_row("predicted", 2, 0.2)};
  t.rows[1].predicted = true;
  const nlohmann::json j = table::to_json(t);
  EXPECT_EQ(j["rows"][0]["gbuffer_ms"]["median"], t.rows[0].gbuffer_ms->median);
  EXPECT_EQ(j["rows"][0]["gbuffer_ms"]["n"], t.rows[0].time_ms.n);
  EXPECT_TRUE(j["rows"][1]["gbuffer_ms"].is_null()) << "no measured split: null";
  EXPECT_EQ(table::table_from_json(j).rows, t.rows);

  TempDir dir;
  table::write_table_files(t, dir.path());
  EXPECT_EQ(table::read_table(dir / "cost_table.json").rows, t.rows);
  const std::string csv = util::read_file(dir / "cost_table.csv").value();
  EXPECT_EQ(table::from_csv(csv).rows, t.rows);
  const auto lines = table::parse_csv(csv);
  EXPECT_EQ(lines[1][csv_column(lines, "own_ms")], fmt::format("{}", table::time_split(t.rows[0])->own));
  EXPECT_EQ(lines[2][csv_column(lines, "gbuffer_ms.median")], "");
  EXPECT_EQ(lines[2][csv_column(lines, "own_ms")], "");
}

TEST(TimeSplit, ATableWrittenBeforeItReadsWithTheSplitUnknown) {
  table::CostTable t;
  t.rows = {split_row("a", kSplitRatios, 0.1)};
  nlohmann::json j = table::to_json(t);
  j["rows"][0].erase("gbuffer_ms");
  const table::CostTable old = table::table_from_json(j);
  ASSERT_EQ(old.rows.size(), 1u);
  EXPECT_FALSE(old.rows[0].gbuffer_ms);
  EXPECT_EQ(old.rows[0].time_ms, t.rows[0].time_ms);

  // The CSV without its five columns.
  auto lines = table::parse_csv(table::to_csv(t));
  for (const char* name : {"own_ms", "gbuffer_ms.n", "gbuffer_ms.p90", "gbuffer_ms.median", "gbuffer_ms.min"}) {
    const std::size_t c = csv_column(lines, name);
    for (auto& line : lines) line.erase(line.begin() + static_cast<std::ptrdiff_t>(c));
  }
  std::string csv;
  for (const auto& line : lines) {
    for (std::size_t i = 0; i < line.size(); ++i) csv += (i ? "," : "") + table::csv_field(line[i]);
    csv += "\r\n";
  }
  EXPECT_FALSE(table::from_csv(csv).rows.at(0).gbuffer_ms);
}

// One line naming the field, through the file reader.
std::string split_read_error(const nlohmann::json& table_json, const std::string& text_override = {}) {
  TempDir dir;
  util::write_atomic(dir / "t.json", text_override.empty() ? table_json.dump() : text_override);
  try {
    table::read_table(dir / "t.json");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "read without an error";
}

TEST(TimeSplit, TheReaderRefusesANegativeNonFiniteOrOversizedGbuffer) {
  table::CostTable t;
  t.rows = {split_row("a", kSplitRatios, 0.1)};
  const nlohmann::json good = table::to_json(t);
  nlohmann::json negative = good;
  negative["rows"][0]["gbuffer_ms"]["min"] = -0.5;
  nlohmann::json above = good;
  above["rows"][0]["gbuffer_ms"]["median"] = t.rows[0].time_ms.median * 2;
  nlohmann::json missing = good;
  missing["rows"][0]["gbuffer_ms"].erase("p90");
  std::string infinite = good.dump();
  const std::string min_text = "\"min\":" + good["rows"][0]["gbuffer_ms"]["min"].dump();
  ASSERT_NE(infinite.find(min_text), std::string::npos);
  infinite.replace(infinite.find(min_text), min_text.size(), "\"min\":1e999");
  for (const auto& [what, message] : {std::pair{"negative", split_read_error(negative)},
                                      std::pair{"above the frame", split_read_error(above)},
                                      std::pair{"missing", split_read_error(missing)},
                                      std::pair{"infinite", split_read_error(good, infinite)}}) {
    SCOPED_TRACE(what);
    EXPECT_NE(message.find("gbuffer_ms."), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  nlohmann::json nan = good;
  nan["rows"][0]["gbuffer_ms"]["median"] = std::numeric_limits<double>::quiet_NaN();  // written as null
  EXPECT_THROW(table::table_from_json(nan), std::runtime_error);
}

TEST(TimeSplit, MergeKeepsItAndRefusesShardsThatDisagreeOnIt) {
  table::CostTable a, b;
  a.rows = {split_row("a", kSplitRatios, 0.1)};
  b.rows = {split_row("b", kSplitRatios, 0.2)};
  b.rows[0].gbuffer_ms.reset();
  const table::CostTable merged = table::merge_tables({{"a.json", a}, {"b.json", b}}, {});
  ASSERT_EQ(merged.rows.size(), 2u);
  EXPECT_EQ(merged.rows[0].gbuffer_ms, a.rows[0].gbuffer_ms);
  EXPECT_FALSE(merged.rows[1].gbuffer_ms);
  table::CostTable other = a;
  other.rows[0].gbuffer_ms->median /= 2;
  EXPECT_THROW(table::merge_tables({{"a.json", a}, {"other.json", other}}, {}), std::runtime_error);
}

// The front and select decide on the whole frame: a variant whose own passes are cheaper but whose format's
// G-buffer costs more than another's is still the slower one, and the split changes no mark or choice.
TEST(TimeSplit, DecisionsStayOnTheWholeFrame) {
  table::CostRow cheap_own = split_row("cheap-own", kSplitRatios, 0.05);  // frame 1.5x, own passes 10 %
  cheap_own.gbuffer_ms->median = cheap_own.time_ms.median * 0.9;
  table::CostRow light_gbuffer = split_row("light-gbuffer", {1, 1, 1, 1, 1, 1, 1, 1}, 0.1);  // frame 1x, own 90 %
  light_gbuffer.gbuffer_ms->median = light_gbuffer.time_ms.median * 0.1;
  ASSERT_LT(table::time_split(cheap_own)->own, table::time_split(light_gbuffer)->own);
  table::CostTable with, without;
  with.rows = {cheap_own, light_gbuffer};
  without = with;
  for (auto& r : without.rows) r.gbuffer_ms.reset();
  decide::mark_pareto(with);
  decide::mark_pareto(without);
  for (std::size_t i = 0; i < with.rows.size(); ++i) EXPECT_EQ(with.rows[i].pareto, without.rows[i].pareto);
  decide::SelectQuery q;
  q.budget_ms = light_gbuffer.time_ms.decision();  // within it: only the lighter frame
  EXPECT_TRUE(chose(decide::select(with, q), "light-gbuffer"));
  EXPECT_TRUE(chose(decide::select(without, q), "light-gbuffer"));
}

}  // namespace
}  // namespace aovar::test
