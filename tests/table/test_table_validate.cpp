// One validator on every cost table read from a file (issue 34, point 11): numbers that cannot be and
// conflicting duplicate rows are refused in one line naming the file and the row, by select, diff, report
// and merge alike; "meta": null is named as such.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "cost_rows.h"
#include "table/row_intervals.h"
#include "table/table.h"
#include "test_support.h"
#include "util/fs.h"

namespace {
using namespace aovar;
using namespace aovar::table;
using json = nlohmann::json;

CostRow measured(const std::string& variant, double ratio, double rmse) {
  std::vector<double> ratios;
  for (int i = 0; i < 10; ++i) ratios.push_back(ratio * (1 + 0.002 * i));
  CostRow r = test::timed_row(variant, ratios, rmse);
  r.error->mae = rmse / 2;
  r.error->max = rmse * 4;
  return r;
}

json good_table() {
  CostTable t;
  t.rows = {measured("quick", 1.0, 0.05), measured("careful", 1.3, 0.02)};
  return to_json(t);
}

// The one-line error of reading `doc` from a file, or "" when it is accepted.
std::string read_error(const json& doc, const test::TempDir& dir) {
  util::write_atomic(dir / "cost_table.json", doc.dump());
  try {
    read_table(dir / "cost_table.json");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(TableValidate, ImpossibleNumbersAreRefusedNamingTheFileAndTheRow) {
  test::TempDir dir;
  ASSERT_EQ(read_error(good_table(), dir), "");
  struct Case {
    const char* pointer;
    json value;
    const char* names;
  };
  const Case cases[] = {
      {"/rows/1/time_ms/min", -5.0, "time_ms.min -5 is negative"},
      {"/rows/1/time_ms/paired", -0.5, "time_ms.paired -0.5 is negative"},
      {"/rows/1/time_ms/median", 1e-9, "time_ms.min"},  // min above the median of the same frames
      {"/rows/1/time_ms/n", -1, "time_ms.n -1 is negative"},
      {"/rows/1/time_ms/paired_ci", json::array({2.0, 1.0}), "time_ms.paired_ci [2, 1]"},
      {"/rows/1/rel_time_ci", json::array({-1.0, 2.0}), "rel_time_ci [-1, 2]"},
      {"/rows/1/rel_time", -1.0, "rel_time -1 is negative"},
      {"/rows/1/error/rmse", -0.1, "error.rmse -0.1 is negative"},
      {"/rows/1/error/mae", -1.0, "error.mae -1 is negative"},
      {"/rows/1/error/max", -2.0, "error.max -2 is negative"},
      {"/rows/1/error/ssim", 1.5, "error.ssim 1.5 is outside [-1, 1]"},
      {"/rows/1/health/nan", -3, "health.nan -3 is negative"},
      {"/rows/1/threads", -2, "threads -2 is negative"},
      {"/rows/1/flicker", -1.0, "flicker -1"},
  };
  for (const Case& c : cases) {
    json doc = good_table();
    doc[json::json_pointer(c.pointer)] = c.value;
    const std::string e = read_error(doc, dir);
    EXPECT_NE(e.find("cost_table.json: "), std::string::npos) << c.pointer << ": " << e;
    // The row's index and key (whose last field is threads: -2 in that case).
    EXPECT_NE(e.find("row 1 (careful|builtin:atrium|overview|lavapipe|64x36|"), std::string::npos) << c.pointer << ": " << e;
    EXPECT_NE(e.find(c.names), std::string::npos) << c.pointer << ": " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

TEST(TableValidate, APredictedRowMayExtrapolateBelowZero) {
  // sweep --predict writes the cost model's time, a linear extrapolation: the sweep's own table must read back.
  test::TempDir dir;
  json doc = good_table();
  doc["rows"][1]["predicted"] = true;
  doc["rows"][1]["time_ms"] = {{"min", -0.2}, {"median", -0.2}, {"p90", -0.2}, {"n", 0}, {"paired", -0.2}};
  EXPECT_EQ(read_error(doc, dir), "");
  doc["rows"][1]["predicted"] = false;
  EXPECT_NE(read_error(doc, dir).find("time_ms.min -0.2 is negative"), std::string::npos);
}

TEST(TableValidate, ConflictingDuplicatesAreRefusedIdenticalOnesKept) {
  test::TempDir dir;
  json doc = good_table();
  doc["rows"].push_back(doc["rows"][0]);  // the same row twice: what merge also tolerates
  EXPECT_EQ(read_error(doc, dir), "");
  doc["rows"][2]["error"]["rmse"] = 0.01;
  const std::string e = read_error(doc, dir);
  EXPECT_NE(e.find("rows 0 and 2 are both quick|builtin:atrium|overview|lavapipe|64x36|2 with different values"),
            std::string::npos)
      << e;
  doc["rows"][2] = doc["rows"][1];
  doc["rows"][2]["time_ms"]["min"] = 0.5;  // a duplicate of the other row, conflicting in its time
  EXPECT_NE(read_error(doc, dir).find("rows 1 and 2"), std::string::npos);
}

TEST(TableValidate, MetaMustBeAnObject) {
  test::TempDir dir;
  for (json meta : {json(nullptr), json::array(), json("x")}) {
    json doc = good_table();
    doc["meta"] = meta;
    const std::string e = read_error(doc, dir);
    EXPECT_NE(e.find("\"meta\" is " + std::string(meta.type_name()) + ", not an object"), std::string::npos) << e;
  }
  json doc = good_table();
  doc.erase("meta");  // absent: an empty meta, as before
  EXPECT_EQ(read_error(doc, dir), "");
}

TEST(TableValidate, SelectDiffReportAndMergeRefuseANegativeTime) {
  test::TempDir dir;
  json doc = good_table();
  util::write_atomic(dir / "good.json", doc.dump());
  doc["rows"][0]["time_ms"]["paired"] = -5.0;
  util::write_atomic(dir / "bad.json", doc.dump());
  const std::string bad = (dir / "bad.json").string(), good = (dir / "good.json").string();
  for (const std::string& args : {"select --table " + bad + " --budget-ms 10", "diff " + good + " " + bad,
                                  "report --table " + bad + " --out " + (dir / "report").string(),
                                  "merge " + (dir / "merged.json").string() + " " + good + " " + bad}) {
    const auto r = test::run_aovar(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find("bad.json: row 0 (quick|"), std::string::npos) << args << ": " << r.output;
    EXPECT_NE(r.output.find("time_ms.paired -5 is negative"), std::string::npos) << args << ": " << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "merged.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "report" / "report.html"));
  // "meta": null through report: named, not nlohmann's "cannot use value() with null".
  doc = good_table();
  doc["meta"] = nullptr;
  util::write_atomic(dir / "null_meta.json", doc.dump());
  const auto r = test::run_aovar("report --table " + (dir / "null_meta.json").string() + " --out " + (dir / "r2").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("null_meta.json: \"meta\" is null, not an object"), std::string::npos) << r.output;
}

// Issue 54, reproduction 4: "rmse": null was read as +inf and select showed "rmse inf". A null or non-finite
// rmse, mae, ssim, bias, max or time is refused naming the row; psnr null (a perfect match) is read, and so is
// every null of a row whose image held NaN or Inf pixels (the only rows aovar writes without an error).
TEST(TableValidate, NullOrNonFiniteErrorsAreRefusedUnlessTheImageWasBroken) {
  test::TempDir dir;
  for (const char* field : {"rmse", "mae", "ssim", "bias", "max"}) {
    json doc = good_table();
    doc["rows"][1]["error"][field] = nullptr;
    const std::string e = read_error(doc, dir);
    EXPECT_NE(e.find(std::string("row 1 (careful|")), std::string::npos) << field << ": " << e;
    EXPECT_NE(e.find(std::string("error.") + field + " is null"), std::string::npos) << field << ": " << e;
    doc["rows"][1]["health"]["nan"] = 12;  // a broken image: no error could be averaged
    EXPECT_EQ(read_error(doc, dir), "") << field;
  }
  for (const char* time : {"/rows/0/time_ms/min", "/rows/0/time_ms/median", "/rows/0/rel_time"}) {
    json doc = good_table();
    doc[json::json_pointer(time)] = nullptr;
    EXPECT_NE(read_error(doc, dir), "") << time;
  }
  json perfect = good_table();
  perfect["rows"][0]["error"]["psnr"] = nullptr;
  EXPECT_EQ(read_error(perfect, dir), "");
  // A key holding a NUL no longer cuts the one-line error short: it reads '?' there.
  json nul = good_table();
  nul["rows"][1]["variant"] = std::string("care\0ful", 8);
  nul["rows"][1]["error"]["rmse"] = nullptr;
  const std::string e = read_error(nul, dir);
  EXPECT_NE(e.find("care?ful|"), std::string::npos) << e;
  EXPECT_NE(e.find("error.rmse is null"), std::string::npos) << e;
}

}  // namespace
