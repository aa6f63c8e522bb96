// Reading cost_table.json (table/json_reader.cpp, issue 34 point 5): a file that is not a cost table fails in
// one line naming the file, the row, the line and what is wrong; a newer schema is named before any row;
// fields aovar does not know are skipped; and rows read after the text before them went back to the system
// are whole, with lines still counted from the top of the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include <nlohmann/json.hpp>

#include "table/table.h"
#include "test_support.h"
#include "cost_rows.h"
#include "util/fs.h"
#include "util/schema.h"

namespace {
using namespace aovar;
using namespace aovar::table;
using json = nlohmann::json;

CostTable two_rows() {
  CostTable t;
  t.rows = {test::timed_row("quick", {1.0, 1.01, 1.02, 0.99, 1.0, 1.03}, 0.05),
            test::timed_row("careful", {1.3, 1.31, 1.29, 1.3, 1.32, 1.28}, 0.02)};
  return t;
}

// The one-line error of reading `text` as dir/cost_table.json, or "" when it is read.
std::string read_error(const std::string& text, const test::TempDir& dir) {
  util::write_atomic(dir / "cost_table.json", text);
  try {
    read_table(dir / "cost_table.json");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// " (line N)" of the first occurrence of `needle` in `text`.
std::string line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return " (line " + std::to_string(1 + std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) + ")";
}

TEST(TableReader, MalformedTablesFailInOneLineNamingTheFileTheRowAndTheLine) {
  test::TempDir dir;
  const json good = to_json(two_rows());
  ASSERT_EQ(read_error(good.dump(1), dir), "");

  json wrong_type = good;
  wrong_type["rows"][1]["time_ms"]["min"] = "fast";
  std::string text = wrong_type.dump(1);
  std::string e = read_error(text, dir);
  EXPECT_NE(e.find("cost_table.json: row 1" + line_of(text, "\"fast\"") + ": "), std::string::npos) << e;
  EXPECT_NE(e.find("time_ms.min is a string, not a number"), std::string::npos) << e;

  json missing = good;
  missing["rows"][0].erase("scene");
  e = read_error(missing.dump(1), dir);
  EXPECT_NE(e.find("cost_table.json: row 0 (line "), std::string::npos) << e;
  EXPECT_NE(e.find("row 'quick': field scene is missing"), std::string::npos) << e;

  json nested = good;  // static and error.breakdown are read member by member: each one is needed
  nested["rows"][0]["static"] = to_json(std::optional<StaticCost>(StaticCost{}));
  nested["rows"][0]["error"]["breakdown"] = to_json(metrics::ErrorBreakdown{});
  ASSERT_EQ(read_error(nested.dump(1), dir), "");
  json no_alu = nested;
  no_alu["rows"][0]["static"]["passes"].erase("alu");
  EXPECT_NE(read_error(no_alu.dump(1), dir).find("field 'static': static.passes.alu is missing"), std::string::npos);
  json no_far_rmse = nested;
  no_far_rmse["rows"][0]["error"]["breakdown"]["far"].erase("rmse");
  EXPECT_NE(read_error(no_far_rmse.dump(1), dir).find("field 'error': error.breakdown.far.rmse is missing"),
            std::string::npos);

  json not_an_object = good;
  not_an_object["rows"][1] = 5;
  text = not_an_object.dump(1);
  e = read_error(text, dir);
  EXPECT_NE(e.find("row 1" + line_of(text, "  5\n") + " is a number, not an object"), std::string::npos) << e;

  json no_rows = good;
  no_rows["rows"] = json::object();
  EXPECT_NE(read_error(no_rows.dump(1), dir).find("not a cost table (no \"rows\" array)"), std::string::npos);
  EXPECT_NE(read_error("[1, 2]", dir).find("not a cost table"), std::string::npos);

  text = good.dump(1);
  for (const std::string& broken : {text.substr(0, text.size() / 2), text + " x", std::string("{\"rows\": [}"), std::string("")}) {
    e = read_error(broken, dir);
    EXPECT_NE(e.find("cost_table.json: "), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_TRUE(e.find("not valid JSON") != std::string::npos || e.find("text after the table") != std::string::npos) << e;
  }
}

TEST(TableReader, ANewerSchemaIsNamedBeforeAnyRow) {
  test::TempDir dir;
  json newer = to_json(two_rows());
  newer["schema_version"] = util::kSchemaVersion + 1;
  newer["rows"][0]["time_ms"] = "a format this aovar cannot read";
  const std::string e = read_error(newer.dump(1), dir);
  EXPECT_NE(e.find("is newer than this aovar reads"), std::string::npos) << e;
}

TEST(TableReader, FieldsItDoesNotKnowAreSkipped) {
  test::TempDir dir;
  const CostTable t = two_rows();
  json with_more = to_json(t);
  with_more["rows"][0]["a_later_field"] = {{"nested", {1, 2, {{"x", nullptr}}}}, {"text", "}]"}};
  with_more["a_later_top_level_field"] = json::array({"rows"});
  util::write_atomic(dir / "cost_table.json", with_more.dump(1));
  EXPECT_EQ(read_table(dir / "cost_table.json").rows, t.rows);
}

// More than the 64 MiB after which the text before the row being read is released.
TEST(TableReader, RowsAfterReleasedTextAreWholeAndLinesStayRight) {
  test::TempDir dir;
  CostTable t = two_rows();
  for (int i = 0; i < 70000; ++i) t.meta.other["filler"]["k" + std::to_string(i)] = std::string(1000, 'x');
  std::string text = to_json(t).dump(1);
  ASSERT_GT(text.size(), std::size_t{66} << 20);
  util::write_atomic(dir / "cost_table.json", text);
  const CostTable back = read_table(dir / "cost_table.json");
  EXPECT_EQ(back.rows, t.rows);
  EXPECT_EQ(back.meta, t.meta);

  json broken = to_json(t);
  broken["rows"][1]["time_ms"]["min"] = "slow";
  text = broken.dump(1);
  const std::string e = read_error(text, dir);
  EXPECT_NE(e.find("row 1" + line_of(text, "\"slow\"")), std::string::npos) << e.substr(0, 300);
  EXPECT_NE(e.find("time_ms.min is a string, not a number"), std::string::npos) << e.substr(0, 300);
}

}  // namespace
