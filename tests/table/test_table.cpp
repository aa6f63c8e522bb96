// The cost table (src/table): file formats, the rows of a measurement, merge.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "cost_rows.h"
#include "measure/measure.h"
#include "measure/rows_json.h"
#include "table/merge.h"
#include "table/table.h"
#include "test_support.h"
#include "util/fs.h"

namespace {
using namespace aovar;
using namespace aovar::table;
using aovar::test::on_front;
using aovar::test::plain_row;
namespace fs = std::filesystem;


// Every figure distinct (and exact in binary), so a field written under the wrong name cannot round-trip.
metrics::ErrorBreakdown sample_breakdown() {
  metrics::ErrorBreakdown b;
  b.edge_band_px = 6.25;
  b.split_depth = 3.5;
  b.edge = {0.25, 0.125, 0.375, 0.0625};
  b.interior = {0.75, 0.0625, 0.625, -0.03125};
  b.near = {0.5, 0.09375, 0.25, 0.015625};
  b.far = {0.5, 0.15625, 0.75, 0.046875};
  b.light = {0.375, 0.1875, 0.8125, 0.078125};
  b.dark = {0.5, 0.109375, 0.1875, -0.0234375};
  return b;
}

CostTable sample_table() {
  CostTable t;
  t.meta.tool = "test";
  t.meta.size = "64x36";
  t.meta.calibration = CalibrationRef{"cal.json", "beef", {}};
  t.meta.other = {{"from_a_newer_aovar", {1, 2}}};  // kept as read
  CostRow a = plain_row("alchemy-s08", 1.5, 0.05);
  a.axes = {{"algorithm", "alchemy"}, {"samples", "8"}};
  a.spirv_hash = "abc";
  StaticCost s;  // its JSON text in the CSV holds commas and quotes
  s.ao.fetches.depth = 12;
  s.ao.alu = 3.5;
  s.ao.dynamic_loops = 1;
  s.passes.fetches.prefilter = 2;
  s.work_per_pixel = 40.25;
  s.weighted_others.branches = 0.125;
  a.static_cost = s;
  a.health = {1, 2, 3};
  a.flicker = 0.0125;
  a.images = {"images/a,b.pfm", "images/a \"q\".png"};
  a.error->psnr = std::numeric_limits<double>::infinity();
  a.error->breakdown = sample_breakdown();
  a.device = "llvmpipe (LLVM 15.0.6, 256 bits)";
  a.driver = "Mesa 22.3.6";
  GpuPassCost ao;  // NaN: a statistic this Mesa does not report; written as null, read back as NaN
  ao.pass = "ao";
  ao.vgprs = 24;
  ao.waves_per_simd = 16;
  ao.alu_ms = 0.25;
  ao.est_ms = 0.25;
  ao.bound = "alu";
  ao.dram_bytes_per_pixel = 8;  // the traced cache model's columns (issue 33), a NaN hit rate among them
  ao.levels = {{"L0", 0.5, 40, 0.01}, {"L2", NAN, 12, 0.02}};
  a.gpu["navi21"] = {"Radeon RX 6800 XT", "Mesa 25.0.7", "1920x1080", "overview", 0.25, {ao}, "radv"};
  GpuPassCost fd;  // a GL chip's pass: the neutral statistics and the compiler's own line, no estimate
  fd.pass = "ao";
  fd.instructions = 589;
  fd.alu = 340;
  fd.texture = 8;
  fd.registers = 8.5;
  fd.occupancy = 12;
  fd.loops = 0;
  fd.raw = "FRAG shader: 589 inst, 233 nops, ... 8 cat5, ... 12 waves, 0 loops";
  a.gpu["a320"] = {"", "Mesa 25.0.7", "1920x1080", "", NAN, {fd}, "freedreno"};
  CostRow b = plain_row("hbao-s16", 0.1 + 0.2, std::nullopt, "view, \"two\"\nnext");
  b.predicted = true;
  b.pareto = true;
  t.rows = {a, b};
  return t;
}

TEST(Table, JsonRoundTrip) {
  CostTable t = sample_table();
  CostTable back = table_from_json(nlohmann::json::parse(to_json(t).dump()));
  EXPECT_EQ(back.rows, t.rows);
  EXPECT_EQ(back.meta, t.meta);
  EXPECT_TRUE(to_json(t)["rows"][0]["error"]["psnr"].is_null());  // +inf is written as null
  EXPECT_TRUE(to_json(t)["rows"][1]["error"].is_null());
  EXPECT_TRUE(to_json(t)["rows"][0]["gpu"]["navi21"]["passes"][0]["valu"].is_null());
  EXPECT_TRUE(std::isnan(back.rows[0].gpu.at("navi21").passes[0].valu));
  EXPECT_EQ(back.rows[0].device, "llvmpipe (LLVM 15.0.6, 256 bits)");
  test::TempDir dir;
  write_table_files(t, dir.path());
  EXPECT_EQ(read_table(dir / "cost_table.json").rows, t.rows);
  EXPECT_TRUE(fs::exists(dir / "cost_table.csv"));
  EXPECT_TRUE(fs::exists(dir / "cost_table.md"));
}

// The breakdown in both files: cost_table.json and measure.json hold it under error.breakdown, a NaN as null
// (read back as NaN); rows written before it load without one; the CSV's readable share columns.
// schema_version 2 added the neutral statistics, the compiler line and the compiler's name to "gpu"; a
// version 1 row (an AMD family's, without them) still reads, the new fields NaN or empty.
TEST(Table, GpuCostsOfVersionOneTablesReadWithoutTheNeutralFields) {
  const auto j = to_json(sample_table());
  EXPECT_EQ(j["rows"][0]["gpu"]["a320"]["compiler"], "freedreno");
  EXPECT_EQ(j["rows"][0]["gpu"]["a320"]["passes"][0]["raw"], "FRAG shader: 589 inst, 233 nops, ... 8 cat5, ... 12 waves, 0 loops");
  nlohmann::json v1 = j["rows"][0]["gpu"]["navi21"];
  v1.erase("compiler");
  for (const char* f : {"alu", "texture", "memory", "registers", "occupancy", "spills", "cycles", "loops"})
    v1["passes"][0].erase(f);
  const GpuCost old = gpu_cost_from_json(v1);
  EXPECT_EQ(old.compiler, "");
  EXPECT_EQ(old.passes[0].vgprs, 24);
  EXPECT_TRUE(std::isnan(old.passes[0].alu));
  EXPECT_TRUE(old.passes[0].raw.empty());
}

TEST(Table, ErrorBreakdownInTheFiles) {
  CostTable t = sample_table();
  const nlohmann::json j = to_json(t);
  const nlohmann::json& b = j["rows"][0]["error"]["breakdown"];
  EXPECT_EQ(b["edge_band_px"], 6.25);
  EXPECT_EQ(b["far"]["error_share"], 0.75);
  EXPECT_EQ(b["light"]["mean_error"], 0.078125);
  EXPECT_EQ(b["interior"]["rmse"], 0.0625);

  nlohmann::json old = j["rows"][0];
  old["error"].erase("breakdown");  // a table written before the breakdown
  const CostRow back = row_from_json(old);
  ASSERT_TRUE(back.error);
  EXPECT_FALSE(back.error->breakdown);
  EXPECT_EQ(back.error->rmse, t.rows[0].error->rmse);

  metrics::ErrorBreakdown with_nan = sample_breakdown();
  with_nan.far.rmse = std::numeric_limits<double>::quiet_NaN();  // an empty half
  const nlohmann::json nan_json = to_json(with_nan);
  EXPECT_TRUE(nan_json["far"]["rmse"].is_null());
  EXPECT_TRUE(std::isnan(breakdown_from_json(nlohmann::json::parse(nan_json.dump())).far.rmse));

  const std::string csv = to_csv(t);
  const auto lines = parse_csv(csv);
  auto column = [&](const std::string& name) {
    auto it = std::find(lines[0].begin(), lines[0].end(), name);
    EXPECT_NE(it, lines[0].end()) << name;
    return static_cast<std::size_t>(it - lines[0].begin());
  };
  EXPECT_EQ(lines[1][column("err_edge_share")], "0.375");
  EXPECT_EQ(lines[1][column("err_far_share")], "0.75");
  EXPECT_EQ(lines[1][column("err_light_share")], "0.8125");
  EXPECT_EQ(lines[2][column("err_far_share")], "") << "a row without an error";
}

TEST(Table, CsvRoundTripAndQuoting) {
  EXPECT_EQ(csv_field("plain"), "plain");
  EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_field("two\nlines"), "\"two\nlines\"");
  auto parsed = parse_csv("a,\"b,c\",\"d\"\"e\"\r\n\"x\ny\",,z\r\n");
  ASSERT_EQ(parsed.size(), 2u);
  EXPECT_EQ(parsed[0], (std::vector<std::string>{"a", "b,c", "d\"e"}));
  EXPECT_EQ(parsed[1], (std::vector<std::string>{"x\ny", "", "z"}));

  CostTable t = sample_table();
  std::string csv = to_csv(t);
  EXPECT_EQ(csv.rfind("variant,axes.algorithm,axes.samples,spirv_hash,", 0), 0u) << csv;
  auto lines = parse_csv(csv);
  ASSERT_EQ(lines.size(), 3u);  // header + one record per row, multi-line fields quoted
  EXPECT_NE(lines[0].end(), std::find(lines[0].begin(), lines[0].end(), "gpu.navi21.est_ms"));
  EXPECT_NE(csv.find(",ao:alu,24,16"), std::string::npos) << "est_ms, bound, max VGPRs, min waves: " << csv;
  CostTable back = from_csv(csv);
  EXPECT_EQ(back.rows, t.rows);
}

TEST(Table, MarkdownIsSortedBySceneViewTime) {
  CostTable t;
  t.rows = {plain_row("slow", 3, 0.01, "b"), plain_row("fast", 1, 0.02, "b"), plain_row("mid", 2, 0.03, "a"),
            plain_row("pipe|name", 0.5, 0.03, "a", "lavapipe", "z-scene")};
  std::string md = to_markdown(t);
  auto pos = [&](const char* s) { return md.find(s); };
  EXPECT_LT(pos("| mid |"), pos("| fast |"));
  EXPECT_LT(pos("| fast |"), pos("| slow |"));
  EXPECT_LT(pos("| slow |"), pos("pipe\\|name"));
  EXPECT_EQ(md.rfind("| scene | view |", 0), 0u);
}

// measure.json's rows (measure/rows_json.h) become cost rows in memory (measure::cost_rows): the shared
// fields, +inf PSNR from null, the images, the paired time on the baseline's scale, no Pareto mark (the front is
// decide's), and the baseline's timing-only row left out.
TEST(Table, RowsOfAMeasureJson) {
  nlohmann::json r = {{"variant", "alchemy-s08"}, {"axes", {{"samples", "8"}}}, {"duplicates", nlohmann::json::array()},
                      {"scene", "builtin:atrium"}, {"view", "overview"}, {"backend", "lavapipe"}, {"size", "64x36"},
                      {"threads", 2}, {"radius", 0.5}, {"spirv_hash", "h"}, {"inputs_hash", "i1"},
                      {"time_ms", {{"min", 1.0}, {"median", 1.1}, {"p90", 1.2}, {"n", 5}}},
                      {"passes", nlohmann::json::object()}, {"rel_time", 0.5}, {"rel_time_median", 0.4},
                      {"baseline", "base"}, {"is_baseline", false}, {"create_ms", 1}, {"first_frame_ms", 2}, {"jit_ms", 1},
                      {"health", {{"nan", 0}, {"inf", 0}, {"out_of_range", 4}, {"pixels", 100}}},
                      {"mean_visibility", 0.8},
                      {"error", {{"rmse", 0.1}, {"mae", 0.05}, {"psnr", nullptr}, {"ssim", 0.9}, {"bias", 0.01},
                                 {"max", 0.5}, {"share_over_0_1", 0.2}, {"pixels", 100}}},
                      {"error_one_frame", nullptr}, {"flicker", nullptr},
                      {"image", "images/a.pfm"}, {"preview", "images/a.png"}, {"error_map", ""},
                      {"rounds", {{"scale", "base@s"}, {"id", "b/0"}, {"ratios", {0.5, 0.4, 0.3, 0.42, 0.38, 0.41, 0.39}}}}};
  nlohmann::json base = r;
  base["variant"] = "base";
  base["inputs_hash"] = "i2";
  base["is_baseline"] = true;  // measured for timing only: no row of the table
  base["time_ms"]["min"] = 2.5;
  base["rel_time"] = base["rel_time_median"] = 1.0;
  base["rounds"] = {{"scale", "base@s"}, {"id", "all"}, {"ratios", {1, 1, 1, 1, 1, 1, 1}}};
  measure::MeasureResult m;
  m.rows = {measure::row_from_json(r), measure::row_from_json(base)};
  measure::pair_times(m.rows);
  auto rows = measure::cost_rows(m, "measure/scene");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].time_ms.min, 1.0);
  EXPECT_DOUBLE_EQ(rows[0].time_ms.paired, 0.4 * 2.5) << "rel_time_median x the baseline's min";
  // 7 rounds: the sign-test interval is the 1st to the 7th of the sorted ratios (coverage 1 - 2^-6).
  EXPECT_EQ(rows[0].rel_time_ci, (util::Interval{0.3, 0.5}));
  EXPECT_DOUBLE_EQ(rows[0].time_ms.paired_ci.lo, 0.3 * 2.5);
  EXPECT_DOUBLE_EQ(rows[0].time_ms.paired_ci.hi, 0.5 * 2.5);
  ASSERT_TRUE(rows[0].error);
  EXPECT_EQ(rows[0].error->rmse, 0.1);
  EXPECT_TRUE(std::isinf(rows[0].error->psnr));
  EXPECT_EQ(rows[0].health.out_of_range, 4);
  EXPECT_EQ(rows[0].images, (std::vector<std::string>{"measure/scene/images/a.pfm", "measure/scene/images/a.png"}));
  EXPECT_FALSE(rows[0].pareto) << "measure marks no front: decide::mark_pareto does, over the whole table";
  // And back: the row's JSON is what was read; a row written before the breakdown has none.
  EXPECT_EQ(measure::row_to_json(m.rows[0], m).at("time_ms"), r.at("time_ms"));
  EXPECT_EQ(measure::row_to_json(m.rows[0], m).at("error"), r.at("error"));
  EXPECT_FALSE(m.rows[0].error->breakdown);
  // With one: written, read back equal.
  measure::MeasureRow with = m.rows[0];
  with.error->breakdown = sample_breakdown();
  const measure::MeasureRow again = measure::row_from_json(nlohmann::json::parse(measure::row_to_json(with, m).dump()));
  ASSERT_TRUE(again.error && again.error->breakdown);
  EXPECT_EQ(*again.error->breakdown, sample_breakdown());
}


// One writer for the fields both files' rows have (table::shared_row_json): a measure.json row and the
// cost_table.json row of the same CostRow agree on each of them; the objects each file extends (time_ms,
// error, health) agree on the shared part.
TEST(Table, MeasureAndCostTableRowsWriteTheSharedFieldsAlike) {
  measure::MeasureRow m;
  static_cast<CostRow&>(m) = sample_table().rows[0];  // +inf PSNR, a breakdown, a GPU estimate, flicker
  const nlohmann::json shared = shared_row_json(m);
  const nlohmann::json in_measure = measure::row_to_json(m, measure::MeasureResult{});
  const nlohmann::json in_table = to_json(static_cast<const CostRow&>(m));
  EXPECT_TRUE(shared.at("error").at("psnr").is_null());
  for (const auto& [field, value] : shared.items()) {
    if (!value.is_object() || field == "axes" || field == "gpu") {
      EXPECT_EQ(in_measure.at(field), value) << field;
      EXPECT_EQ(in_table.at(field), value) << field;
      continue;
    }
    for (const auto& [part, inner] : value.items()) {
      EXPECT_EQ(in_measure.at(field).at(part), inner) << field << "." << part;
      EXPECT_EQ(in_table.at(field).at(part), inner) << field << "." << part;
    }
  }
  EXPECT_TRUE(in_measure.at("health").contains("pixels")) << "measure.json's own";
  EXPECT_TRUE(in_table.at("time_ms").contains("paired")) << "cost_table.json's own";
}

TEST(Merge, DisjointShardsJoinAndConflictsAreRefused) {
  test::TempDir dir;
  CostTable s1, s2, s3, other;
  s1.meta.size = s2.meta.size = "64x36";
  s1.meta.shard = "1/2";
  s2.meta.shard = "2/2";
  s1.rows = {plain_row("fast", 1, 0.2), plain_row("slow", 3, 0.3)};
  s2.rows = {plain_row("good", 2, 0.1), plain_row("fast", 1, 0.2)};  // identical duplicate: kept once
  write_json(s1, dir / "s1.json");
  write_json(s2, dir / "s2.json");
  auto r = test::run_aovar("merge " + (dir / "out.json").string() + " " + (dir / "s1.json").string() + " " +
                           (dir / "s2.json").string());
  ASSERT_EQ(r.status, 0) << r.output;
  CostTable m = read_table(dir / "out.json");
  ASSERT_EQ(m.rows.size(), 3u);
  EXPECT_FALSE(m.meta.shard);
  EXPECT_EQ(m.meta.size, "64x36");
  ASSERT_TRUE(m.meta.merged_from);
  ASSERT_EQ(m.meta.merged_from->size(), 2u);
  EXPECT_TRUE(m.meta.merged_from->back().ends_with("s2.json")) << m.meta.merged_from->back();
  EXPECT_FALSE(on_front(m.rows, "slow"));
  EXPECT_TRUE(on_front(m.rows, "good"));

  s3.meta = s2.meta;
  s3.rows = {plain_row("fast", 1.7, 0.2)};  // same key, other time
  write_json(s3, dir / "s3.json");
  auto c = test::run_aovar("merge " + (dir / "out2.json").string() + " " + (dir / "s1.json").string() + " " +
                           (dir / "s3.json").string());
  EXPECT_EQ(c.status, 2) << "an error, not a failed check";
  EXPECT_NE(c.output.find("conflicting rows for fast|"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("s1.json"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("s3.json"), std::string::npos) << c.output;
  EXPECT_EQ(std::count(c.output.begin(), c.output.end(), '\n'), 1) << c.output;
  EXPECT_FALSE(fs::exists(dir / "out2.json"));

  other.meta.size = "128x72";
  write_json(other, dir / "other.json");
  EXPECT_THROW(merge_tables({dir / "s1.json", dir / "other.json"}), std::runtime_error);
}


}  // namespace
